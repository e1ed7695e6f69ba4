// Play, pause, step and slow motion over World::advance, with the state before each step kept
// for interpolated drawing (playback.h).
#include "playback.h"

#include <algorithm>
#include <cmath>

#include "inertia/core/error.h"

namespace inertia::viewer {

Playback::Playback(io::Scene scene) : scene_(std::move(scene)), world_(io::instantiate(scene_)) {}

void Playback::capture(std::vector<BodyId>& ids, std::vector<Transform>& poses) const {
  ids = world_->rigidBodies().bodies();
  poses.resize(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) poses[i] = world_->transform(ids[i]);
}

int Playback::frame(double realSeconds) {
  require(std::isfinite(realSeconds) && realSeconds >= 0,
          "Playback::frame: realSeconds must be finite and >= 0");
  require(std::isfinite(timeScale) && timeScale > 0, "Playback: timeScale must be finite and > 0");
  if (paused) return 0;
  const Real dt = world_->settings().dt;
  const double h = double(dt);
  double remaining = realSeconds * timeScale;
  int taken = 0;
  // Whole steps one advance() call each: with the accumulator below dt, advance(dt, 1) takes
  // exactly one step and keeps the remainder, so the state before every step can be kept for
  // interpolation and beforeStep runs before each step.
  while (remaining > h && taken < std::max(1, maxStepsPerFrame) - 1) {
    capture(previousIds_, previousPoses_);
    if (beforeStep) beforeStep(*world_);
    taken += world_->advance(dt, 1);
    remaining -= h;
  }
  // The rest goes to the accumulator: one more step when it reaches dt (beyond the cap, the
  // time left over is dropped, as World::advance does).
  const bool willStep = double(world_->interpolationAlpha()) * h + remaining >= h;
  if (willStep) {
    capture(previousIds_, previousPoses_);
    if (beforeStep) beforeStep(*world_);
  }
  taken += world_->advance(Real(remaining), 1);
  return taken;
}

void Playback::singleStep() {
  capture(previousIds_, previousPoses_);
  if (beforeStep) beforeStep(*world_);
  world_->step(world_->settings().dt);
}

void Playback::restart() {
  world_ = io::instantiate(scene_);
  previousIds_.clear();
  previousPoses_.clear();
}

void Playback::applySettings(const WorldSettings& settings) {
  io::Scene changed = scene_;
  changed.world = settings;
  std::unique_ptr<World> world = io::instantiate(changed);  // validates the settings
  world->restoreState(world_->saveState());
  // Sleeping bodies would not notice new gravity or solver settings.
  for (BodyId body : world->rigidBodies().bodies()) world->rigidBodies().wake(body);
  world_ = std::move(world);
  scene_ = std::move(changed);
}

std::vector<Transform> Playback::drawPoses() const {
  std::vector<BodyId> ids;
  std::vector<Transform> poses;
  capture(ids, poses);
  if (paused) return poses;
  const Real alpha = std::clamp(world_->interpolationAlpha(), Real(0), Real(1));
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (i >= previousIds_.size() || previousIds_[i] != ids[i]) continue;
    const Transform& a = previousPoses_[i];
    Transform& b = poses[i];
    b.p = a.p + alpha * (b.p - a.p);
    b.q = a.q.slerp(alpha, b.q);
  }
  return poses;
}

}  // namespace inertia::viewer
