// The rigid bodies of a world: bodies, their shapes, contacts and the contact solver pipeline.
// The World owns one and forwards its body API to it; it is usable on its own too.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "inertia/collision/collider.h"
#include "inertia/collision/contact.h"
#include "inertia/collision/queries.h"
#include "inertia/core/thread_pool.h"
#include "inertia/core/types.h"
#include "inertia/dynamics/body.h"
#include "inertia/dynamics/joint.h"
#include "inertia/dynamics/multibody.h"
#include "inertia/geometry/bounds.h"
#include "inertia/geometry/shapes.h"
#include "inertia/ode/method.h"

namespace inertia {

namespace detail {
struct RigidBodyData;
class StepWorkers;
}

/// The contact solver (DESIGN.md section 4, `"solver": {"type": ...}`).
/// - SoftStep: Catto's soft step (Box2D v3): substeps, soft contact constraints whose stiffness
///   follows the substep rate, relaxation iterations without the position bias, restitution
///   after the substeps, warm starting.
/// - Pgs: sequential impulses (projected Gauss-Seidel) on rigid rows with warm starting and
///   Baumgarte position correction, once per substep.
/// - LcpDantzig, LcpLemke: direct LCP solvers for small systems (validation and teaching): in
///   each substep, in place of the pgs iterations, each island's contact and joint rows (same
///   rows and Baumgarte bias as pgs; a joint's locked rows bilateral, its limits one-sided, its
///   motors and friction boxed, its springs soft through a compliance) form one dense LCP on
///   the Delassus matrix J M^-1 J^T, solved exactly. Dantzig (Baraff 1994's principal pivoting,
///   ODE's boxed "findex" LCP): normal, two friction rows per point boxed by mu times the normal
///   impulse (friction pyramid), and the rolling and spinning rows. Lemke (complementary pivoting):
///   the Stewart-Trinkle polygonal cone (|t1| + |t2| <= mu n, four directions and a sliding-speed
///   slack) and the rolling and spinning rows likewise. An island whose LCP exceeds 192 unknowns
///   (about 60 contact points for Dantzig, 30 for Lemke), or whose LCP fails, is solved by the pgs
///   iterations (`iterations` of them) for that substep instead.
enum class SolverType { SoftStep, Pgs, LcpDantzig, LcpLemke };

/// The scene-file name of a solver ("soft_step", "pgs", "lcp_dantzig", "lcp_lemke").
std::string_view solverName(SolverType type);
/// The solver of a scene-file name, or false when the name is unknown.
bool solverFromName(std::string_view name, SolverType& out);
/// The accepted solver names, comma separated, for error messages.
std::string_view solverNames();

struct SolverSettings {
  SolverType type = SolverType::SoftStep;
  /// Velocity iterations per substep (1..1000). Four keep a 40-base pyramid of boxes standing
  /// with soft_step (bench/rigid_bodies_bench.cpp). Three keep it standing too, but leave a
  /// box of the settled rain scene jittering at 0.1 m/s where four bring it to rest.
  int iterations = 4;
  /// soft_step only: relaxation passes per substep, after the position update and without the
  /// position bias (0..1000). Box2D v3 makes one; more remove more of the push-out velocity.
  int relaxIterations = 1;
  /// soft_step only: the stiffness (Hz) and damping ratio of joints' locked rows and violated
  /// limits, capped at half the substep rate. A load F on a joint of effective mass m sags it
  /// by F / (m (2 pi jointHertz)^2) at rest: 17 um for a body hanging at its centre at 120 Hz,
  /// four times that at 60 Hz. Box2D v3 makes joints 60 Hz (twice its 30 Hz contacts) and
  /// solves one iteration; at 120 Hz a 100 x 100 joint grid needs three (bench/joints_bench.cpp).
  /// Trees of plain ball joints are solved exactly and projected instead (joint_trees.h).
  Real jointHertz = 120;
  Real jointDampingRatio = 2;
};

/// Contact tuning (defaults as Box2D v3's but `hertz`, in metres and seconds).
struct ContactTuning {
  /// Stiffness of soft contacts (Hz), capped at a quarter of the substep rate: at 4 substeps of
  /// 1/60 s, the cap. Box2D v3's default is 30.
  Real hertz = 60;
  Real dampingRatio = 10;   ///< Damping ratio of soft contacts (over-damped: no bounce from push-out).
  Real pushVelocity = 3;    ///< Largest speed at which overlap is resolved (m/s).
  Real restitutionThreshold = 1;  ///< Approach speed below which contacts do not bounce (m/s).
  Real linearSlop = Real(0.005);  ///< Allowed overlap (m): Baumgarte correction ignores it.
  Real baumgarte = Real(0.2);     ///< Fraction of the overlap a pgs step corrects.
  /// Contacts are created this far (m) before the shapes touch (speculative margin).
  Real speculativeDistance = Real(0.02);
  /// A body whose step displacement exceeds this fraction of its smallest extent is treated as
  /// a bullet for that step (speculative contacts over its whole motion).
  Real bulletFraction = Real(0.25);
  /// Manifold reuse (as Jolt's body-pair cache, tighter): a pair of convex shapes whose relative
  /// pose moved less than these since its manifold was computed keeps the manifold's features,
  /// carried rigidly with the bodies (points and normal in the shapes' frames, separations
  /// recomputed), instead of running the narrow phase again. Distance (m) and angle (rad); 0
  /// for either turns reuse off.
  Real reuseDistance = Real(0.001);
  Real reuseAngle = Real(0.005);
  Real sleepSpeed = Real(0.05);  ///< Speed (m/s, angular times extent) below which a body rests.
  Real timeToSleep = Real(0.5);  ///< Rest time (s) after which an island falls asleep.
};

/// Checks the tuning and throws InvalidArgument naming the first bad field.
void validate(const ContactTuning& tuning);

/// What a step of the rigid bodies needs from the world.
struct DynamicsSettings {
  Vec3 gravity = Vec3(0, Real(-9.81), 0);  ///< (m/s^2)
  int substeps = 4;
  SolverSettings solver{};
  ode::Method integrator = ode::Method::SymplecticEuler;  ///< For bodies without contacts.
  bool sleeping = true;
  MaterialCombine combine{};
  ContactTuning contact{};
};

/// A contact between two shapes at the end of a step.
struct ContactInfo {
  BodyId bodyA;
  BodyId bodyB;
  ShapeId shapeA;
  ShapeId shapeB;
  ContactManifold manifold;                  ///< As collide() made it, at the step's start.
  /// Per point (N s): the last substep's, which warm-starts the next step (at rest, the
  /// weight carried over one substep, m g dt / substeps).
  std::array<Real, 4> normalImpulses{};
};

/// A contact that began or ended in the last step.
struct ContactEvent {
  BodyId bodyA;
  BodyId bodyB;
  ShapeId shapeA;
  ShapeId shapeB;
  Vec3 point = Vec3::Zero();   ///< A contact point (m, world); the last known one for an end.
  Vec3 normal = Vec3::UnitY(); ///< From A to B.
  Real approachSpeed = 0;      ///< Normal approach speed at the start (m/s, >= 0), for sounds.
};

/// A ray hit in the world.
struct WorldRayHit {
  BodyId body;
  ShapeId shape;
  RayHit hit;
};

/// Per-phase wall-clock seconds of the rigid-body pipeline.
struct DynamicsTimes {
  double broadPhase = 0;
  double narrowPhase = 0;
  double solver = 0;
  double integration = 0;
};

/// A node of the broad phase's tree, for debug drawing and statistics.
struct BroadPhaseNode {
  Aabb box;        ///< Its fat box (m): the leaves' hold a shape's bounds with a margin.
  int height = 0;  ///< 0 for a leaf (a shape).
};

/// The rigid bodies. Deterministic: the same calls give the same bytes whatever the number of
/// threads of the pool passed to step().
class RigidBodySystem {
 public:
  RigidBodySystem();
  ~RigidBodySystem();
  RigidBodySystem(const RigidBodySystem&);
  RigidBodySystem& operator=(const RigidBodySystem&);
  RigidBodySystem(RigidBodySystem&&) noexcept;
  RigidBodySystem& operator=(RigidBodySystem&&) noexcept;

  /// Adds a body (InvalidArgument for invalid settings). It has no shapes yet.
  BodyId createBody(const BodySettings& settings);
  /// Removes a body and its shapes; the ids become invalid.
  void destroyBody(BodyId id);
  bool isValid(BodyId id) const;
  bool isValid(ShapeId id) const;

  /// Attaches a shape at `local` (relative to the body's origin) made of `material`, and
  /// updates the body's mass properties. Planes and height fields go on static bodies only;
  /// meshes on dynamic bodies must be closed. Throws InvalidArgument otherwise.
  ShapeId addShape(BodyId body, const Shape& shape, const Material& material = {},
                   const Transform& local = {});
  /// The same with a prepared collider (shares its acceleration structures).
  ShapeId addShape(BodyId body, const Collider& collider, const Material& material = {},
                   const Transform& local = {});
  void removeShape(ShapeId shape);
  /// Which shapes this one collides with (body.h); from the next step, and wakes its body.
  /// New shapes collide with everything. Joints' collideConnected and an articulation's own
  /// links are filtered besides.
  void setFilter(ShapeId shape, const CollisionFilter& filter);
  CollisionFilter filter(ShapeId shape) const;

  // State of a body (all in world coordinates).
  Transform transform(BodyId id) const;       ///< Pose of the body's origin.
  Vec3 centerOfMass(BodyId id) const;         ///< (m)
  Vec3 linearVelocity(BodyId id) const;       ///< Of the centre of mass (m/s).
  Vec3 angularVelocity(BodyId id) const;      ///< (rad/s)
  Real mass(BodyId id) const;                 ///< (kg); 0 for static and kinematic bodies.
  Mat3 inertiaWorld(BodyId id) const;         ///< About the centre of mass (kg m^2).
  /// The inverse of inertiaWorld (1/(kg m^2)) as the solver uses it; zero for static and
  /// kinematic bodies. inertiaWorld().inverse() loses it for a body of micrometres in float,
  /// whose cofactors underflow (0/0: NaN).
  Mat3 inverseInertiaWorld(BodyId id) const;
  BodyType type(BodyId id) const;
  std::string_view name(BodyId id) const;
  bool isAwake(BodyId id) const;
  BodyId body(ShapeId shape) const;

  void setTransform(BodyId id, const Transform& pose);   ///< Teleports; wakes the body.
  void setLinearVelocity(BodyId id, const Vec3& v);      ///< Wakes the body.
  void setAngularVelocity(BodyId id, const Vec3& w);     ///< Wakes the body.
  /// Kinematic bodies: sets the velocities that reach `target` in `dt` seconds.
  void moveKinematic(BodyId id, const Transform& target, Real dt);
  /// A force (N) at a world point (m), applied over the next step; wakes the body.
  void applyForce(BodyId id, const Vec3& force, const Vec3& point);
  void applyForceAtCenter(BodyId id, const Vec3& force);
  void applyTorque(BodyId id, const Vec3& torque);  ///< (N m)
  /// An impulse (N s) at a world point (m): changes the velocities at once; wakes the body.
  void applyImpulse(BodyId id, const Vec3& impulse, const Vec3& point);
  void applyAngularImpulse(BodyId id, const Vec3& impulse);  ///< (N m s)
  void wake(BodyId id);

  // Driven bodies (multibody.h): an articulation's links. They take part in the broad and
  // narrow phase as bodies; the solver neither integrates nor pushes them, but solves their
  // contacts through `response`, and the owner moves them after each step.
  /// Makes the dynamic bodies `members` (in member order) a group answered by `response`, which
  /// must outlive the group. The members never sleep. With `selfCollisionParents` empty they do
  /// not collide with each other; else it holds each member's parent (a member index, -1 at a
  /// root) and members collide with each other, except each with its parent (self-collision).
  /// Returns the group. InvalidArgument for an invalid, non-dynamic, jointed or grouped member,
  /// or parents of the wrong count or out of range.
  int addMultibody(MultibodyResponse* response, std::span<const BodyId> members,
                   std::span<const int> selfCollisionParents = {});
  /// Dissolves a group: its members become ordinary bodies again.
  void removeMultibody(int group);
  /// Points group `group` at `response`: a copy of its response, after this system was assigned
  /// from a copy (a world's snapshot). InvalidArgument for a free group or a null response.
  void setMultibodyResponse(int group, MultibodyResponse* response);
  /// A driven body's pose (of its origin) and velocities: its origin's (m/s) and angular
  /// (rad/s), world. InvalidArgument for a body that is not driven.
  void setDrivenState(BodyId id, const Transform& pose, const Vec3& originVelocity,
                      const Vec3& angularVelocity);

  // Joints (joint.h). Creation throws InvalidArgument naming the bad field: an invalid body,
  // a body joined to itself, a zero axis, a lower limit above the upper, a negative threshold.
  // It wakes both bodies.
  JointId createJoint(const BallJointSettings& settings);
  JointId createJoint(const HingeJointSettings& settings);
  JointId createJoint(const SliderJointSettings& settings);
  JointId createJoint(const UniversalJointSettings& settings);
  JointId createJoint(const SixDofJointSettings& settings);
  JointId createJoint(const WeldJointSettings& settings);
  JointId createJoint(const DistanceJointSettings& settings);
  /// Removes a joint (destroying a body removes its joints); the id becomes invalid.
  void destroyJoint(JointId id);
  bool isValid(JointId id) const;
  JointType jointType(JointId id) const;
  std::string_view jointName(JointId id) const;
  BodyId jointBodyA(JointId id) const;  ///< Null for the world.
  BodyId jointBodyB(JointId id) const;
  /// A disabled joint is not solved. A joint that breaks is disabled; enabling it again
  /// repairs it. Wakes its bodies.
  void setJointEnabled(JointId id, bool enabled);
  bool isJointEnabled(JointId id) const;
  bool isJointBroken(JointId id) const;
  /// The motor, limits or spring of a hinge or slider (a spring also of a weld or distance
  /// joint); std::nullopt removes it. InvalidArgument for a type without one. Wakes the bodies.
  void setJointMotor(JointId id, const std::optional<JointMotor>& motor);
  void setJointLimits(JointId id, const std::optional<JointLimits>& limits);
  void setJointSpring(JointId id, const std::optional<JointSpring>& spring);
  /// A six-DOF joint's degree of freedom `axis` (0..5: x, y, z, rx, ry, rz).
  void setJointAxis(JointId id, int axis, const JointAxis& settings);
  /// Last step's constraint force on body B at its anchor (N, world), and torque (N m).
  Vec3 jointForce(JointId id) const;
  Vec3 jointTorque(JointId id) const;
  /// The free coordinate now: a hinge's angle (rad), a slider's position (m), a distance
  /// joint's length (m), a ball joint's twist (rad); 0 for the others.
  Real jointCoordinate(JointId id) const;
  /// Degree of freedom `axis` (0..5) of any joint's frames now: B's frame origin along A's
  /// frame axes x, y, z (m), and B's frame relative to A's as X-Y-Z Euler angles (rad).
  Real jointAxisCoordinate(JointId id, int axis) const;
  JointError jointError(JointId id) const;
  /// The anchors in world coordinates (m).
  Vec3 jointAnchorA(JointId id) const;
  Vec3 jointAnchorB(JointId id) const;
  /// The joint's frames in world coordinates now: at the anchors, x along the joint's axis
  /// (a six-DOF joint's frames as given).
  Transform jointFrameA(JointId id) const;
  Transform jointFrameB(JointId id) const;
  /// Degree of freedom `axis` (0..5: x, y, z, rx, ry, rz) as set: a hinge's angle is rx, a
  /// slider's position x.
  const JointAxis& jointAxis(JointId id, int axis) const;
  int jointCount() const;
  /// The live joints in creation-slot order.
  std::vector<JointId> joints() const;
  /// The joints that broke in the last step, in slot order.
  const std::vector<JointEvent>& jointEvents() const;

  /// Advances by `dt` seconds in settings.substeps substeps on the threads of `pool` (in
  /// sequence when null). Never throws for valid state.
  void step(Real dt, const DynamicsSettings& settings, ThreadPool* pool = nullptr);
  /// The same on the workers of a step already under way (World steps its bodies and
  /// particle systems on one set of workers). Internal.
  void step(Real dt, const DynamicsSettings& settings, detail::StepWorkers& workers);

  int bodyCount() const;
  /// Manifolds with at least one touching point (separation <= linear slop) after the last step.
  int contactCount() const;
  /// The live bodies in creation-slot order.
  std::vector<BodyId> bodies() const;
  /// The shapes of a body, in the order they were added.
  std::vector<ShapeId> shapes(BodyId id) const;
  const Collider& collider(ShapeId id) const;
  Transform shapeTransform(ShapeId id) const;  ///< World pose of the shape.
  const Material& material(ShapeId id) const;

  /// Every manifold of the last step (touching or speculative), in a deterministic order.
  const std::vector<ContactInfo>& contacts() const;
  /// The nodes of the broad phase's dynamic tree over the shapes' fattened bounds (planes are
  /// kept apart and are not in it): for debug drawing and statistics.
  std::vector<BroadPhaseNode> broadPhaseNodes() const;
  const std::vector<ContactEvent>& beginEvents() const;
  const std::vector<ContactEvent>& endEvents() const;

  /// The first shape the ray hits, over every body.
  std::optional<WorldRayHit> castRay(const Ray& ray) const;

  /// Kinetic energy (J) and momenta of the dynamic bodies (driven bodies left out: their owner
  /// accounts for them).
  Real kineticEnergy() const;
  Vec3 linearMomentum() const;                 ///< (kg m/s)
  Vec3 angularMomentum(const Vec3& about) const;  ///< About a world point (kg m^2/s).

  const DynamicsTimes& times() const;

 private:
  std::unique_ptr<detail::RigidBodyData> d_;
};

/// The instruction set the contact solver's kernels use on this processor: "AVX-512", "AVX2"
/// or "SSE2" (every set gives the same bits; the environment variable INERTIA_SIMD caps it).
const char* contactSolverInstructionSet();

}  // namespace inertia
