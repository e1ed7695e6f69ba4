// Running a sample in the viewer: play, pause, single step, slow motion and restart, with the
// physics at its fixed rate decoupled from the frame rate (World::advance) and body poses
// interpolated between the last two physics states for drawing (Fiedler, "Fix your timestep").
// No GL here, so it is testable headless.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "inertia/io/scene.h"
#include "inertia/world/world.h"

namespace inertia::viewer {

/// A scene and the world made from it, with the viewer's clock.
class Playback {
 public:
  /// Instantiates `scene` (io::instantiate's InvalidArgument passes through).
  explicit Playback(io::Scene scene);

  World& world() { return *world_; }
  const World& world() const { return *world_; }
  /// The scene as loaded, with the settings last applied.
  const io::Scene& scene() const { return scene_; }

  bool paused = false;
  /// Simulated seconds per real second (slow motion below 1), > 0.
  double timeScale = 1;
  /// At most this many fixed steps per frame; the simulation falls behind real time beyond.
  int maxStepsPerFrame = 8;
  /// Called before every physics step, e.g. to apply the mouse spring's force (forces act
  /// over one step).
  std::function<void(World&)> beforeStep{};

  /// A frame of `realSeconds` (finite, >= 0): unless paused, advances the world by
  /// realSeconds * timeScale with its fixed step (World::advance, the remainder carried over).
  /// Returns the number of steps taken.
  int frame(double realSeconds);
  /// One fixed step now (paused or not).
  void singleStep();
  /// Makes the world again from the scene, with the settings last applied.
  void restart();
  /// Replaces the world's settings: a new world is made with them and the state (bodies added
  /// since included, joints, particle systems, deformables) and clock are carried over
  /// (World::saveState) and every body is woken. Throws InvalidArgument for invalid settings
  /// (the world is unchanged).
  void applySettings(const WorldSettings& settings);

  /// The poses of the bodies' origins for drawing, in RigidBodySystem::bodies() order:
  /// interpolated by World::interpolationAlpha() between the state before the last step and
  /// the current one (positions linearly, orientations by slerp); the current poses when paused
  /// or for bodies that did not exist before the last step.
  std::vector<Transform> drawPoses() const;

 private:
  void step(Real dt, double frameTime, int maxSteps, int& taken);
  void capture(std::vector<BodyId>& ids, std::vector<Transform>& poses) const;

  io::Scene scene_;
  std::unique_ptr<World> world_;
  std::vector<BodyId> previousIds_{};
  std::vector<Transform> previousPoses_{};
};

}  // namespace inertia::viewer
