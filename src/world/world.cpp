#include "inertia/world/world.h"

#include <array>
#include <chrono>
#include <cmath>
#include <string>

#include "core/thread_pool_impl.h"
#include "dynamics/step_workers.h"
#include "inertia/articulation/link_response.h"
#include "inertia/core/error.h"
#include "slots.h"

namespace inertia {

void validate(const WorldSettings& s) {
  require(s.gravity.allFinite(), "WorldSettings::gravity must be finite");
  require(std::isfinite(s.dt) && s.dt > 0, "WorldSettings::dt must be finite and > 0 (s)");
  require(s.substeps >= 1 && s.substeps <= 64, "WorldSettings::substeps must be in 1..64");
  require(s.solver.iterations >= 1 && s.solver.iterations <= 1000,
          "WorldSettings::solver.iterations must be in 1..1000");
  require(s.solver.relaxIterations >= 0 && s.solver.relaxIterations <= 1000,
          "WorldSettings::solver.relaxIterations must be in 0..1000");
  require(std::isfinite(s.solver.jointHertz) && s.solver.jointHertz > 0,
          "WorldSettings::solver.jointHertz must be finite and > 0 (Hz)");
  require(std::isfinite(s.solver.jointDampingRatio) && s.solver.jointDampingRatio >= 0,
          "WorldSettings::solver.jointDampingRatio must be finite and >= 0");
  validate(s.contact);
  require(s.threads >= 0 && s.threads <= 1024, "WorldSettings::threads must be in 0..1024");
}

World::World(const WorldSettings& settings) : settings_(settings) {
  validate(settings_);
  threads_ = std::make_unique<ThreadPool>(settings_.threads);
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::step(Real dt) {
  require(std::isfinite(dt) && dt > 0, "World::step: dt must be finite and > 0 (s)");
  using Clock = std::chrono::steady_clock;
  // Rigid bodies first (broad phase, narrow phase, solver and integration per substep), then
  // the particle systems, one step of dt each, in creation order.
  DynamicsSettings dynamics;
  dynamics.gravity = settings_.gravity;
  dynamics.substeps = settings_.substeps;
  dynamics.solver = settings_.solver;
  dynamics.integrator = settings_.integrator;
  dynamics.sleeping = settings_.sleeping;
  dynamics.combine = settings_.combine;
  dynamics.contact = settings_.contact;
  // Emitters on bodies are placed where their body is at the start of the step, where the
  // particle systems' step starts too: the new particles then move on through the step as the
  // body does.
  for (ParticleSlot& slot : particleSlots_)
    if (slot.system) followBodies(*slot.system);
  // One set of workers for the whole step: the rigid bodies' stages, then the particles', then
  // the deformables' implicit solves.
  detail::StepWorkers::run(&threads_->impl().arena, [&](detail::StepWorkers& workers) {
    // Articulations step inside the bodies' substeps (their links are driven bodies); their
    // link bodies follow them after.
    bodies_.step(dt, dynamics, workers);
    for (const ArticulationSlot& slot : articulationSlots_)
      if (slot.articulation) followArticulation(slot);
    const auto t0 = Clock::now();
    bool obstaclesGathered = false;
    for (ParticleSlot& slot : particleSlots_) {
      if (!slot.system) continue;
      ParticleSystem& ps = *slot.system;
      if (ps.settings().collideWithBodies) {
        if (!obstaclesGathered) gatherBodyObstacles();
        obstaclesGathered = true;
        ps.setMovingObstacles(bodyObstacles_);
      }
      ps.step(dt, workers);
    }
    phases_.particles += std::chrono::duration<double>(Clock::now() - t0).count();
    stepDeformables(dt, obstaclesGathered, workers);
  });
  time_ += double(dt);
  ++steps_;
}

// Emitters attached to bodies take the body's pose and velocity field.
// An emitter whose body was destroyed stays where it last was, still.
void World::followBodies(ParticleSystem& ps) {
  for (std::size_t k = 0; k < ps.emitterCount(); ++k) {
    Emitter& e = ps.emitter(k);
    const BodyId body = e.settings().attachTo;
    if (body.isNull()) continue;
    if (!bodies_.isValid(body)) {
      e.setCarrierVelocity(Vec3::Zero(), Vec3::Zero(), Vec3::Zero());
      continue;
    }
    e.setPose(bodies_.transform(body) * e.localPose());
    e.setCarrierVelocity(bodies_.linearVelocity(body), bodies_.angularVelocity(body), bodies_.centerOfMass(body));
  }
}

// Every body's shapes with their poses and the bodies' velocity fields, in body and shape order
// (deterministic), for particle systems that collide with bodies.
void World::gatherBodyObstacles() {
  bodyObstacles_.clear();
  obstacleBodies_.clear();
  for (BodyId body : bodies_.bodies()) {
    const Vec3 v = bodies_.linearVelocity(body), w = bodies_.angularVelocity(body);
    const Vec3 center = bodies_.centerOfMass(body);
    const bool dynamic = bodies_.type(body) == BodyType::Dynamic && bodies_.mass(body) > 0;
    const Real inverseMass = dynamic ? 1 / bodies_.mass(body) : Real(0);
    const Mat3 inverseInertia = dynamic ? bodies_.inverseInertiaWorld(body) : Mat3::Zero();
    for (ShapeId shape : bodies_.shapes(body)) {
      bodyObstacles_.push_back({&bodies_.collider(shape), bodies_.shapeTransform(shape), v, w,
                                center, inverseMass, inverseInertia});
      obstacleBodies_.push_back(body);
    }
  }
}

ParticleSystemId World::createParticleSystem(const ParticleSystemSettings& settings) {
  auto system = std::make_unique<ParticleSystem>(settings);
  for (std::uint32_t i = 0; i < particleSlots_.size(); ++i) {
    if (!particleSlots_[i].system) {
      particleSlots_[i].system = std::move(system);
      return {i, particleSlots_[i].generation};
    }
  }
  particleSlots_.push_back({std::move(system), 1});
  return {std::uint32_t(particleSlots_.size() - 1), 1};
}

bool World::isValid(ParticleSystemId id) const {
  return !id.isNull() && id.index < particleSlots_.size() &&
         particleSlots_[id.index].generation == id.generation && particleSlots_[id.index].system;
}

void World::destroyParticleSystem(ParticleSystemId id) {
  require(isValid(id), "World::destroyParticleSystem: invalid particle system id");
  ParticleSlot& slot = particleSlots_[id.index];
  slot.system.reset();
  ++slot.generation;  // stale ids stop matching
}

ParticleSystem& World::particleSystem(ParticleSystemId id) {
  require(isValid(id), "World::particleSystem: invalid particle system id (index " +
                           std::to_string(id.index) + ")");
  return *particleSlots_[id.index].system;
}

const ParticleSystem& World::particleSystem(ParticleSystemId id) const {
  return const_cast<World*>(this)->particleSystem(id);
}

std::vector<ParticleSystemId> World::particleSystems() const {
  std::vector<ParticleSystemId> ids;
  for (std::uint32_t i = 0; i < particleSlots_.size(); ++i)
    if (particleSlots_[i].system) ids.push_back({i, particleSlots_[i].generation});
  return ids;
}

// The deformables, one step of dt each in slot order, on the calling thread, after the bodies'
// step: the bodies are their moving obstacles and attachment points for the step, and what the
// deformable gave them back (contact and attachment impulses) changes their velocities for the
// next one (explicit coupling, momentum conserving).
void World::stepDeformables(Real dt, bool& obstaclesGathered, detail::StepWorkers& workers) {
  const auto t0 = std::chrono::steady_clock::now();
  for (DeformableSlot& slot : deformableSlots_) {
    if (!slot.deformable) continue;
    Deformable& d = *slot.deformable;
    if (d.settings().collideWithBodies) {
      if (!obstaclesGathered) gatherBodyObstacles();
      obstaclesGathered = true;
      d.setMovingObstacles(bodyObstacles_);
    }
    moveAttachments(d, dt);
    d.step(dt, workers);
    if (pushBodies(d)) obstaclesGathered = false;  // velocities changed: gather again
  }
  // Deformables with self-collision also collide with each other, over the step just taken.
  colliding_.clear();
  for (DeformableSlot& slot : deformableSlots_)
    if (slot.deformable && slot.deformable->settings().selfCollision)
      colliding_.push_back(slot.deformable.get());
  if (colliding_.size() >= 2) Deformable::collideDeformables(colliding_, dt, deformableCollisions_);
  phases_.deformables +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Each attachment's point follows its body (a destroyed body leaves it where it was, still).
// The bodies have already stepped: the point's motion over the deformable's step is from where
// the last one left it to where the body is now (the step's mean velocity: the velocity after
// the step holds the impulses applied at its end); the first time, at the body's velocity.
void World::moveAttachments(Deformable& d, Real dt) {
  const std::span<const Attachment> attachments = d.attachments();
  for (std::size_t k = 0; k < attachments.size(); ++k) {
    const BodyId body = attachments[k].body;
    if (!bodies_.isValid(body)) {
      d.setAttachmentMotion(k, d.attachmentPoint(k), Vec3::Zero());
      continue;
    }
    const Vec3 p = bodies_.transform(body).apply(attachments[k].anchor);
    const Vec3 v = d.hasAttachmentMotion(k)
                       ? Vec3((p - d.attachmentPoint(k)) / dt)
                       : Vec3(bodies_.linearVelocity(body) +
                              bodies_.angularVelocity(body).cross(p - bodies_.centerOfMass(body)));
    d.setAttachmentMotion(k, p - dt * v, v);
  }
}

// The impulses the deformable's last step gave dynamic bodies; true when there were any.
bool World::pushBodies(const Deformable& d) {
  bool pushed = false;
  for (const ObstacleImpulse& j : d.obstacleImpulses()) {
    bodies_.applyImpulse(obstacleBodies_[j.obstacle], j.impulse, j.point);
    pushed = true;
  }
  const std::span<const Attachment> attachments = d.attachments();
  for (std::size_t k = 0; k < attachments.size(); ++k) {
    const BodyId body = attachments[k].body;
    if (!bodies_.isValid(body) || bodies_.type(body) != BodyType::Dynamic) continue;
    const Vec3 p = bodies_.transform(body).apply(attachments[k].anchor);
    bodies_.applyImpulse(body, d.attachmentImpulse(k), p);
    pushed = true;
  }
  return pushed;
}

DeformableId World::createDeformable(const DeformableSettings& settings,
                                     const MassSpringModel& model) {
  auto deformable = std::make_unique<Deformable>(settings, model);
  for (std::uint32_t i = 0; i < deformableSlots_.size(); ++i) {
    if (!deformableSlots_[i].deformable) {
      deformableSlots_[i].deformable = std::move(deformable);
      return {i, deformableSlots_[i].generation};
    }
  }
  deformableSlots_.push_back({std::move(deformable), 1});
  return {std::uint32_t(deformableSlots_.size() - 1), 1};
}

bool World::isValid(DeformableId id) const {
  return !id.isNull() && id.index < deformableSlots_.size() &&
         deformableSlots_[id.index].generation == id.generation &&
         deformableSlots_[id.index].deformable;
}

void World::destroyDeformable(DeformableId id) {
  require(isValid(id), "World::destroyDeformable: invalid deformable id");
  DeformableSlot& slot = deformableSlots_[id.index];
  slot.deformable.reset();
  ++slot.generation;
}

Deformable& World::deformable(DeformableId id) {
  require(isValid(id),
          "World::deformable: invalid deformable id (index " + std::to_string(id.index) + ")");
  return *deformableSlots_[id.index].deformable;
}

const Deformable& World::deformable(DeformableId id) const {
  return const_cast<World*>(this)->deformable(id);
}

std::vector<DeformableId> World::deformables() const {
  std::vector<DeformableId> ids;
  for (std::uint32_t i = 0; i < deformableSlots_.size(); ++i)
    if (deformableSlots_[i].deformable) ids.push_back({i, deformableSlots_[i].generation});
  return ids;
}

PhaseTimes World::phaseTimes() const {
  PhaseTimes t = phases_;
  const DynamicsTimes& d = bodies_.times();
  t.broadPhase = d.broadPhase;
  t.narrowPhase = d.narrowPhase;
  t.solver = d.solver;
  t.integration = d.integration;
  return t;
}

World::State World::saveState() const {
  State state{bodies_, {}, {}, {}, time_, accumulator_, steps_};
  for (const ParticleSlot& slot : particleSlots_)
    state.particleSystems.emplace_back(
        slot.system ? std::make_shared<const ParticleSystem>(*slot.system) : nullptr,
        slot.generation);
  for (const DeformableSlot& slot : deformableSlots_)
    state.deformables.emplace_back(
        slot.deformable ? std::make_shared<const Deformable>(*slot.deformable) : nullptr,
        slot.generation);
  saveArticulations(state);
  return state;
}

namespace {

// Each slot as saved: a live one is assigned in place (references to it stay valid), a new
// one made, one freed since the save reset.
template <class Slot, class T>
void restoreSlots(std::vector<Slot>& slots, std::unique_ptr<T> Slot::*member,
                  const std::vector<std::pair<std::shared_ptr<const T>, std::uint32_t>>& saved) {
  detail::prepareRestoredSlots(slots, member, saved.size());
  for (std::size_t i = 0; i < saved.size(); ++i) {
    std::unique_ptr<T>& live = slots[i].*member;
    const bool wasLive = live != nullptr;
    if (!saved[i].first)
      live.reset();
    else if (live)
      *live = *saved[i].first;
    else
      live = std::make_unique<T>(*saved[i].first);
    slots[i].generation = detail::restoredGeneration(saved[i].first != nullptr, saved[i].second,
                                                     slots[i].generation, wasLive);
  }
}

}  // namespace

void World::restoreState(const State& state) {
  bodies_ = state.bodies;
  restoreSlots(particleSlots_, &ParticleSlot::system, state.particleSystems);
  restoreSlots(deformableSlots_, &DeformableSlot::deformable, state.deformables);
  restoreArticulations(state);
  time_ = state.time;
  accumulator_ = state.accumulator;
  steps_ = state.steps;
}

int World::advance(Real frameTime, int maxSteps) {
  require(std::isfinite(frameTime) && frameTime >= 0,
          "World::advance: frameTime must be finite and >= 0 (s)");
  require(maxSteps >= 1, "World::advance: maxSteps must be >= 1");
  accumulator_ += double(frameTime);
  const double h = double(settings_.dt);
  int taken = 0;
  while (accumulator_ >= h && taken < maxSteps) {
    step(settings_.dt);
    accumulator_ -= h;
    ++taken;
  }
  // Drop what could not be simulated rather than fall ever further behind.
  if (accumulator_ >= h) accumulator_ = std::fmod(accumulator_, h);
  return taken;
}

}  // namespace inertia
