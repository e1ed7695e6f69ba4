// A particle system: a pool, its emitters, force fields, obstacles and springs, stepped with
// any integrator of the ode layer.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "inertia/collision/collider.h"
#include "inertia/core/thread_pool.h"
#include "inertia/core/types.h"
#include "inertia/ode/method.h"
#include "inertia/particles/emitter.h"
#include "inertia/particles/fields.h"
#include "inertia/particles/pool.h"

namespace inertia {

namespace detail {
class StepWorkers;
}

/// A static obstacle particles collide with: a shape in a pose.
struct Obstacle {
  Collider collider;
  Transform pose;
};

/// An obstacle owned elsewhere (a rigid body's shape) that may move: its collider, its world
/// pose for this step and its rigid velocity field v(x) = linearVelocity + angularVelocity x
/// (x - center). Given to ParticleSystem::setMovingObstacles() before each step; the collider
/// must stay alive until that step is over.
struct MovingObstacle {
  const Collider* collider = nullptr;
  Transform pose{};
  Vec3 linearVelocity = Vec3::Zero();   ///< Velocity of `center` (m/s).
  Vec3 angularVelocity = Vec3::Zero();  ///< rad/s
  Vec3 center = Vec3::Zero();           ///< Reference point of linearVelocity (m, world).
  /// The body's inverse mass (1/kg) and inverse inertia about `center` (world, 1/(kg m^2)),
  /// for two-way contacts (deformables); 0 for static and kinematic bodies and for particles,
  /// which push nothing.
  Real inverseMass = 0;
  Mat3 inverseInertia = Mat3::Zero();
};

/// A damped spring between two particles (seed 002's n-ary forces):
/// F_a = -(k (|d| - rest) + c (dv . d^)) d^, d = x_a - x_b, and F_b = -F_a.
struct ParticleSpring {
  std::uint64_t a = 0, b = 0;  ///< Particle ids.
  Real restLength = 1;         ///< m, >= 0
  Real stiffness = 100;        ///< N/m, >= 0
  Real damping = 0;            ///< N s/m, >= 0
};

/// Settings of a particle system (designated initialisers).
struct ParticleSystemSettings {
  std::string name{};
  std::size_t capacity = 10000;
  ode::Method integrator = ode::Method::SymplecticEuler;
  Real restitution = Real(0.5);  ///< Newton's impact coefficient e against obstacles, 0..1.
  Real friction = Real(0.1);     ///< Coulomb coefficient on the tangential velocity, >= 0.
  /// Below this normal speed (m/s) an impact does not bounce (e = 0), so resting particles
  /// settle instead of jittering.
  Real restitutionThreshold = Real(0.05);
  /// Collide particles with each other as spheres of their radii (granular media), found
  /// through a uniform grid.
  bool particleCollisions = false;
  /// When stepped by a World: every rigid body's shapes are obstacles too (the world passes
  /// them with setMovingObstacles()), and the collision response uses the velocity relative to
  /// the body's surface (restitution and friction are this system's).
  bool collideWithBodies = false;
};

/// Counters of a particle system since it was created.
struct ParticleStats {
  std::int64_t alive = 0;
  std::int64_t emitted = 0;
  std::int64_t died = 0;
  std::int64_t dropped = 0;  ///< Not emitted because the pool was full.
};

/// Particles in structure-of-arrays storage stepped in parallel batches: the result is
/// bit-identical for any number of threads (every particle's update depends only on its own
/// state and on data fixed before the pass; batches are fixed-size, not thread-sized).
class ParticleSystem {
 public:
  /// Throws InvalidArgument for invalid settings.
  explicit ParticleSystem(const ParticleSystemSettings& settings);
  ~ParticleSystem();
  ParticleSystem(ParticleSystem&&) noexcept;
  ParticleSystem& operator=(ParticleSystem&&) noexcept;
  /// A deep copy, step scratch included (an integrator's history lives there): the copy
  /// continues bit-identically (World::saveState). Moving obstacles are shared, not copied.
  ParticleSystem(const ParticleSystem& other);
  ParticleSystem& operator=(const ParticleSystem& other);

  const ParticleSystemSettings& settings() const { return settings_; }
  const std::string& name() const { return settings_.name; }

  /// Each adder validates its argument (InvalidArgument) and returns the new item's index.
  std::size_t addEmitter(const EmitterSettings& emitter);
  std::size_t addField(const ForceField& field);
  std::size_t addObstacle(const Obstacle& obstacle);
  /// Springs join live particles by id (e.g. emitted by a burst with infinite lifetime); a
  /// spring whose particle died is dropped.
  std::size_t addSpring(const ParticleSpring& spring);

  Emitter& emitter(std::size_t i) { return emitters_.at(i); }
  std::span<const ForceField> fields() const { return fields_; }
  std::span<const Obstacle> obstacles() const { return obstacles_; }
  std::size_t emitterCount() const { return emitters_.size(); }

  /// Sets the moving obstacles of the next steps (a World does it before every step when
  /// settings().collideWithBodies). Each is validated (InvalidArgument); their colliders must
  /// outlive the steps that use them. Particles collide with a static one (zero velocity)
  /// continuously, like with an Obstacle; with a moving one discretely at the end of the step:
  /// a particle within its radius of the obstacle's surface is pushed out along the normal and
  /// its velocity relative to the surface answers as in an impact (Newton and Coulomb), so a
  /// particle resting on a moving platform is carried along and a body sweeping into particles
  /// pushes them. A particle can pass through a body moving by more than about its own size per
  /// step (no swept test against moving bodies).
  void setMovingObstacles(std::span<const MovingObstacle> obstacles);
  std::span<const ParticleSpring> springs() const { return springs_; }

  ParticlePool& pool() { return pool_; }
  const ParticlePool& pool() const { return pool_; }
  ParticleStats stats() const;
  double time() const { return time_; }

  /// Advances by h seconds: integrate under the fields and springs, emit (each new particle
  /// moves from its emission point for the part of the step after its emission), age and kill,
  /// collide with obstacles (continuously: the swept segment is tested) and, when enabled,
  /// with each other, on the threads of `pool` (in sequence when null; the result is the
  /// same). Throws InvalidArgument when h is not finite and > 0.
  void step(Real h, ThreadPool* pool = nullptr);
  /// The same on the workers of a step already under way (World steps its bodies and
  /// particle systems on one set of workers). Internal.
  void step(Real h, detail::StepWorkers& workers);

  /// Total kinetic energy (J) and the potential energy of the springs (J), for tests and plots.
  double kineticEnergy() const;
  double springEnergy() const;

 private:
  struct Scratch;
  struct StepPlan;
  StepPlan makePlan(bool coupled) const;
  void integrate(Real h, detail::StepWorkers& workers);
  std::size_t advanceEmitted(std::size_t first, Real h, detail::StepWorkers& workers);
  std::size_t integrateBatch(const StepPlan& plan, std::size_t slot, bool fresh, std::size_t begin,
                             std::size_t count, Real h, Real t);
  void integrateCoupled(Real h, detail::StepWorkers& workers);
  /// Collides particles [begin, end) with the obstacles. `previous` holds their positions at
  /// the start of the step (3 Reals each, from `begin`) for the swept test, or is null for a
  /// discrete test only. `near`, when given, lists (as offsets from `begin`, increasing) the
  /// `nearCount` particles that may touch an obstacle, already found by the step's kernel.
  void collideObstacles(std::size_t begin, std::size_t end, const Real* previous,
                        const std::uint16_t* near = nullptr, std::size_t nearCount = 0);
  std::size_t nearList(std::size_t begin, std::size_t count, const Real* start, const Real* end,
                       std::uint16_t* list) const;
  void collideParticles(detail::StepWorkers& workers);
  void resolveSprings();
  void springAccelerations(std::span<const Real> x, std::span<const Real> v,
                           std::span<Real> acc) const;

  ParticleSystemSettings settings_;
  ParticlePool pool_;
  std::vector<Emitter> emitters_;
  std::vector<ForceField> fields_;
  std::vector<Obstacle> obstacles_;
  // Per obstacle, computed when added: world bounds to cull tests, and for planes the world
  // normal and offset, tested inline (the ground plane meets every particle every step).
  // Moving obstacles (setMovingObstacles) follow the static ones in obstacleCache_.
  struct ObstacleCache {
    Aabb bounds;
    const Collider* collider = nullptr;
    Transform pose{};
    bool plane = false;
    Vec3 normal = Vec3::UnitY();
    Real offset = 0;
    bool moving = false;  // non-zero velocity: discrete test with the relative velocity
    Vec3 linearVelocity = Vec3::Zero(), angularVelocity = Vec3::Zero(), center = Vec3::Zero();
  };
  static ObstacleCache makeCache(const Collider& collider, const Transform& pose);
  std::vector<ObstacleCache> obstacleCache_;
  std::size_t planeCount_ = 0;  // planes among obstacleCache_
  bool collidePlaneOnly(const ObstacleCache& plane, const Real* previous, Real r, Vec3& end,
                        Vec3& velocity) const;
  std::vector<ParticleSpring> springs_;
  std::vector<std::uint32_t> springIndex_;  // 2 per spring: pool indices of a and b
  std::unique_ptr<Scratch> scratch_;
  ParticleStats stats_;
  double time_ = 0;
};

}  // namespace inertia
