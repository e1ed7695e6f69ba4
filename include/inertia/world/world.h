// The World: owns every simulated system and steps them with a fixed time step.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "inertia/articulation/articulation.h"
#include "inertia/core/id.h"
#include "inertia/core/types.h"
#include "inertia/deformable/deformable.h"
#include "inertia/dynamics/rigid_body_system.h"
#include "inertia/ode/method.h"
#include "inertia/particles/particle_system.h"

namespace inertia {

/// Settings of a world, filled with designated initialisers: World({.gravity = {0, -9.81f, 0}}).
struct WorldSettings {
  Vec3 gravity = Vec3(0, Real(-9.81), 0);  ///< Gravitational acceleration (m/s^2).
  Real dt = Real(1.0 / 60.0);              ///< Fixed time step of advance() (s).
  int substeps = 4;                        ///< Substeps per step (1..64).
  SolverSettings solver{};
  ode::Method integrator = ode::Method::SymplecticEuler;  ///< For unconstrained motion.
  int threads = 0;        ///< Worker threads; 0 uses every core. Results do not depend on it.
  bool sleeping = true;   ///< Let bodies at rest fall asleep.
  MaterialCombine combine{};  ///< How touching materials combine (friction, restitution, ...).
  ContactTuning contact{};    ///< Contact softness, slop, speculative margin, sleep thresholds.
};

/// Checks settings and throws InvalidArgument naming the first bad field.
void validate(const WorldSettings& settings);

namespace articulation {
class LinkResponse;
}

/// A collision shape on an articulation's link, at `pose` in the link's frame.
struct LinkShapeSettings {
  int link = 0;
  Shape shape = Sphere{Real(0.1)};
  Transform pose{};
  Material material{};  ///< Its density is not used: the link's mass comes from the model.
};

/// An articulation in a World: a model, its collision shapes, where its base stands, and its
/// initial state.
struct WorldArticulationSettings {
  std::string name;  ///< Its links are named NAME/LINK (recordings, messages).
  articulation::Model<Real> model;
  std::vector<LinkShapeSettings> shapes;
  Transform base{};  ///< The base frame in the world (the frame of the root joints' origins).
  articulation::ArticulationSettings<Real> solver{};
  articulation::VectorX<Real> q;   ///< Empty: the neutral configuration.
  articulation::VectorX<Real> qd;  ///< Empty: at rest.
  /// Whether its links collide with each other: each with every link but its parent and
  /// children (whose shapes meet at their joint by construction). Off by default.
  bool selfCollision = false;
};

/// Per-phase wall-clock seconds accumulated over all steps (broad phase, narrow phase, ...).
struct PhaseTimes {
  double broadPhase = 0;
  double narrowPhase = 0;
  double solver = 0;
  double integration = 0;
  double particles = 0;
  double deformables = 0;
};

/// A simulation world. Steps are deterministic: the same world stepped the same way gives the
/// same bytes whatever the thread count.
class World {
 public:
  explicit World(const WorldSettings& settings = {});
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  const WorldSettings& settings() const { return settings_; }

  /// Advances the world by exactly `dt` seconds (split into settings().substeps substeps).
  /// Throws InvalidArgument when dt is not finite and positive.
  void step(Real dt);

  /// Advances by a frame of `frameTime` seconds using the fixed step settings().dt and an
  /// accumulator (physics rate decoupled from the frame rate). At most `maxSteps` steps are taken
  /// per call, so a long frame cannot make the simulation fall ever further behind; the time
  /// that could not be simulated is dropped. Returns the number of steps taken.
  int advance(Real frameTime, int maxSteps = 8);

  /// After advance(): how far (0..1) the real time lies between the last two physics states,
  /// for interpolated drawing.
  Real interpolationAlpha() const { return Real(accumulator_ / double(settings_.dt)); }

  /// Simulated time (s) and number of steps taken so far.
  double time() const { return time_; }
  std::int64_t stepCount() const { return steps_; }

  // Rigid bodies (DESIGN.md section 3); the full body API is on rigidBodies().
  /// Adds a body (InvalidArgument for invalid settings).
  BodyId createBody(const BodySettings& settings = {}) { return bodies_.createBody(settings); }
  void destroyBody(BodyId id) { bodies_.destroyBody(id); }
  bool isValid(BodyId id) const { return bodies_.isValid(id); }
  /// Attaches a shape of `material` at `local` (relative to the body's origin).
  ShapeId addShape(BodyId body, const Shape& shape, const Material& material = {},
                   const Transform& local = {}) {
    return bodies_.addShape(body, shape, material, local);
  }
  /// Adds a joint from any type's settings (joint.h; InvalidArgument for invalid settings);
  /// the full joint API is on rigidBodies().
  template <class JointSettings>
  JointId createJoint(const JointSettings& settings) {
    return bodies_.createJoint(settings);
  }
  void destroyJoint(JointId id) { bodies_.destroyJoint(id); }
  bool isValid(JointId id) const { return bodies_.isValid(id); }
  Transform transform(BodyId id) const { return bodies_.transform(id); }
  Vec3 linearVelocity(BodyId id) const { return bodies_.linearVelocity(id); }    ///< (m/s)
  Vec3 angularVelocity(BodyId id) const { return bodies_.angularVelocity(id); }  ///< (rad/s)
  /// The first shape a ray hits.
  std::optional<WorldRayHit> castRay(const Ray& ray) const { return bodies_.castRay(ray); }
  RigidBodySystem& rigidBodies() { return bodies_; }
  const RigidBodySystem& rigidBodies() const { return bodies_; }

  /// Number of bodies, and of touching contact manifolds after the last step.
  int bodyCount() const { return bodies_.bodyCount(); }
  int contactCount() const { return bodies_.contactCount(); }

  /// Adds a particle system (InvalidArgument for invalid settings); the world steps it once
  /// per step with the step's dt, after the bodies. Before that step it moves the emitters
  /// attached to bodies (EmitterSettings::attachTo) with them and, when the system's
  /// settings().collideWithBodies, gives it every body's shapes as moving obstacles. Particles
  /// do not push bodies back.
  ParticleSystemId createParticleSystem(const ParticleSystemSettings& settings);
  /// Removes it; its id becomes invalid. Throws InvalidArgument for an invalid id.
  void destroyParticleSystem(ParticleSystemId id);
  bool isValid(ParticleSystemId id) const;
  /// The system of a valid id (InvalidArgument otherwise).
  ParticleSystem& particleSystem(ParticleSystemId id);
  const ParticleSystem& particleSystem(ParticleSystemId id) const;
  /// The ids of the live particle systems, in slot order (the order the world steps them; a new
  /// system takes the first free slot).
  std::vector<ParticleSystemId> particleSystems() const;

  /// Adds a deformable built from `model` (InvalidArgument for invalid settings or model); the
  /// world steps it once per step with the step's dt, after the particle systems. When its
  /// settings().collideWithBodies, every body's shapes are its obstacles for that step (one
  /// way: the bodies do not feel it; shapes at rest are swept against, moving ones tested at
  /// the step's end with their surface velocity). Gravity acts through its fields, as on
  /// particles.
  DeformableId createDeformable(const DeformableSettings& settings, const MassSpringModel& model);
  /// Removes it; its id becomes invalid. Throws InvalidArgument for an invalid id.
  void destroyDeformable(DeformableId id);
  bool isValid(DeformableId id) const;
  /// The deformable of a valid id (InvalidArgument otherwise).
  Deformable& deformable(DeformableId id);
  const Deformable& deformable(DeformableId id) const;
  /// The ids of the live deformables, in slot order (the order the world steps them).
  std::vector<DeformableId> deformables() const;

  /// Adds an articulation (InvalidArgument for a bad model, state or shape). Each link becomes a
  /// dynamic body of rigidBodies() named NAME/LINK that carries the link's shapes: it collides
  /// with bodies and with other articulations' links (and its own tree's with selfCollision),
  /// and its contacts are solved in the bodies' substeps through the articulation's mass matrix
  /// (link_response.h), with its limits, drives and friction after each substep's contacts.
  /// The world steps the articulation in those substeps by semi-implicit Euler, in the world's
  /// gravity; the link bodies follow it after each step.
  ArticulationId createArticulation(const WorldArticulationSettings& settings);
  /// Removes it and its link bodies; its id becomes invalid.
  void destroyArticulation(ArticulationId id);
  bool isValid(ArticulationId id) const;
  /// The articulation of a valid id (InvalidArgument otherwise). After setState() on it, call
  /// syncArticulation() so that the link bodies follow.
  articulation::Articulation<Real>& articulation(ArticulationId id);
  const articulation::Articulation<Real>& articulation(ArticulationId id) const;
  void syncArticulation(ArticulationId id);
  std::string_view articulationName(ArticulationId id) const;
  /// The body of link `link` (InvalidArgument for a bad index).
  BodyId linkBody(ArticulationId id, int link) const;
  /// The ids of the live articulations, in slot order.
  std::vector<ArticulationId> articulations() const;

  /// Seconds per phase, summed over all steps.
  PhaseTimes phaseTimes() const;

  /// An articulation as a State keeps it (world_articulations.cpp).
  struct SavedArticulation;
  /// A copy of everything the world simulates: the rigid bodies with their shapes, contacts
  /// and joints, every particle system, deformable and articulation (in its slot, so ids stay
  /// valid), and the clock. restoreState() continues from it bit-identically. A State is
  /// immutable and cheap to copy (the systems are shared between copies).
  struct State {
    RigidBodySystem bodies;
    /// Per slot: the system (null for a free slot) and the slot's generation.
    std::vector<std::pair<std::shared_ptr<const ParticleSystem>, std::uint32_t>> particleSystems;
    std::vector<std::pair<std::shared_ptr<const Deformable>, std::uint32_t>> deformables;
    std::vector<std::pair<std::shared_ptr<const SavedArticulation>, std::uint32_t>> articulations;
    double time = 0;
    double accumulator = 0;
    std::int64_t steps = 0;
  };
  State saveState() const;
  /// Puts the world back in `state` (saved by this world or another). A system alive in both
  /// is assigned in place, so references from particleSystem(), deformable() and
  /// articulation() stay valid;
  /// one created since is destroyed and its id becomes invalid.
  void restoreState(const State& state);

 private:
  void followBodies(ParticleSystem& ps);
  void gatherBodyObstacles();
  struct ParticleSlot {
    std::unique_ptr<ParticleSystem> system;  // null when the slot is free
    std::uint32_t generation = 1;
  };
  struct DeformableSlot {
    std::unique_ptr<Deformable> deformable;  // null when the slot is free
    std::uint32_t generation = 1;
  };
  void stepDeformables(Real dt, bool& obstaclesGathered, detail::StepWorkers& workers);
  struct ArticulationSlot {
    std::unique_ptr<articulation::Articulation<Real>> articulation;  // null when free
    std::unique_ptr<articulation::LinkResponse> response;
    std::vector<BodyId> links;
    int group = -1;
    std::string name;
    std::uint32_t generation = 1;
  };
  ArticulationSlot& articulationSlot(ArticulationId id);
  const ArticulationSlot& articulationSlot(ArticulationId id) const;
  void followArticulation(const ArticulationSlot& slot);
  void saveArticulations(State& state) const;
  void restoreArticulations(const State& state);
  std::vector<ArticulationSlot> articulationSlots_;
  void moveAttachments(Deformable& d, Real dt);
  bool pushBodies(const Deformable& d);
  WorldSettings settings_;
  // The world's threads: never more than settings.threads, so that results can be checked
  // across thread counts.
  std::unique_ptr<ThreadPool> threads_;
  std::vector<ParticleSlot> particleSlots_;
  std::vector<DeformableSlot> deformableSlots_;
  RigidBodySystem bodies_;
  double time_ = 0;
  double accumulator_ = 0;
  std::int64_t steps_ = 0;
  PhaseTimes phases_;
  std::vector<MovingObstacle> bodyObstacles_;  // scratch of step(), reused
  std::vector<BodyId> obstacleBodies_;         // the body of each of bodyObstacles_
  std::vector<Deformable*> colliding_;         // deformables with self-collision, per step
  DeformableCollisionCache deformableCollisions_;  // their collisions' trees and buffers
};

}  // namespace inertia
