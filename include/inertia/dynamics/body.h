// Rigid bodies and materials: the settings a user creates them from.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>

#include "inertia/core/id.h"
#include "inertia/core/types.h"

namespace inertia {

// BodyId and ShapeId: core/id.h.

/// How a body moves (the seeds' "mixed dynamics"):
/// - Static: never moves, infinite mass; costs nothing per step unless something touches it.
/// - Kinematic: moved by the velocity (or target pose) the user gives it; pushes dynamic bodies
///   and is not pushed; infinite mass for the solver.
/// - Dynamic: moved by forces, gravity and contacts.
enum class BodyType : std::uint8_t { Static, Kinematic, Dynamic };

/// The scene-file name of a body type ("static", "kinematic", "dynamic").
std::string_view bodyTypeName(BodyType type);
/// The body type of a scene-file name, or false when unknown.
bool bodyTypeFromName(std::string_view name, BodyType& out);

/// The surface and bulk properties of a shape (the seeds' VirtualPhysics material).
struct Material {
  Real density = 1000;        ///< Mass per volume (kg/m^3), > 0; gives the body's mass.
  Real friction = Real(0.6);  ///< Static Coulomb friction coefficient (>= 0).
  /// Dynamic (sliding) Coulomb friction coefficient (>= 0); negative means "same as friction".
  Real dynamicFriction = -1;
  Real restitution = 0;  ///< Newton's coefficient of restitution, 0 (plastic) .. 1 (elastic).
  /// Rolling resistance lever arm (m, >= 0): the torque resisting rolling is at most
  /// rollingFriction * normal force (the classical "coefficient of rolling friction" b).
  Real rollingFriction = 0;
  /// Spinning (torsional) friction lever arm (m, >= 0): the torque resisting spin about the
  /// contact normal is at most spinningFriction * normal force.
  Real spinningFriction = 0;

  /// The dynamic friction coefficient that applies (friction when dynamicFriction < 0).
  Real sliding() const { return dynamicFriction < 0 ? friction : dynamicFriction; }
};

/// Checks a material and throws InvalidArgument naming the first bad field.
void validate(const Material& material);

/// Which shapes may touch, as Box2D's b2Filter: two shapes in the same non-zero `group` always
/// collide when the group is positive and never when it is negative; otherwise they collide
/// when each one's `category` bits meet the other's `mask`. The default collides with
/// everything. It applies between bodies' shapes; particles and deformables meet every shape.
struct CollisionFilter {
  std::uint32_t category = 1;        ///< The categories (bits) the shape belongs to.
  std::uint32_t mask = 0xFFFFFFFFu;  ///< The categories it collides with.
  std::int32_t group = 0;            ///< 0: none; > 0 always, < 0 never within the group.

  bool operator==(const CollisionFilter&) const = default;
};

/// Whether filters a and b let their shapes collide (symmetric).
constexpr bool shouldCollide(const CollisionFilter& a, const CollisionFilter& b) {
  if (a.group != 0 && a.group == b.group) return a.group > 0;
  return (a.mask & b.category) != 0 && (b.mask & a.category) != 0;
}

/// The range of a dynamic body's mass (kg) and principal moments of inertia (kg m^2) that Real
/// can simulate: 2^24 inside the normal range of Real both ways, so that their inverses, and
/// the sums and products the solver forms with them, stay finite (float: about 2e-31 to 2e31;
/// a float water sphere is refused below a radius of about 50 nm). The API refuses a shape or
/// a mass override outside it rather than turn NaN later.
inline constexpr Real kMinMassProperty = std::numeric_limits<Real>::min() * Real(16777216);
inline constexpr Real kMaxMassProperty = std::numeric_limits<Real>::max() / Real(16777216);
/// How closely a body's inverse inertia answers: 1%. A tensor conditioned past kInverseResidual
/// / eps (principal moments spanning 1e5 in float: a rod 800 times longer than thick), or whose
/// cofactor inverse misses by more, has its smallest moments raised to a quarter of that
/// condition when the body's mass is computed; the spin about such a body's long axis is slower
/// than the true one.
inline constexpr Real kInverseResidual = Real(1e-2);
/// True when x lies in [kMinMassProperty, kMaxMassProperty].
bool simulableMassProperty(Real x);
/// "[min, max]" of that range, for messages.
std::string massPropertyRange();

/// How two touching materials' coefficients combine into the contact's.
enum class CombineRule : std::uint8_t { Average, GeometricMean, Minimum, Maximum, Multiply };

/// Combines two coefficients by `rule`.
Real combine(CombineRule rule, Real a, Real b);

/// The combine rules of a world. Box2D's defaults: friction (static and dynamic) by the
/// geometric mean, restitution by the maximum; rolling and spinning lever arms by the maximum.
struct MaterialCombine {
  CombineRule friction = CombineRule::GeometricMean;
  CombineRule restitution = CombineRule::Maximum;
  CombineRule rollingFriction = CombineRule::Maximum;
  CombineRule spinningFriction = CombineRule::Maximum;
};

/// Settings of a new body, filled with designated initialisers:
/// world.createBody({.position = {0, 5, 0}}).
struct BodySettings {
  BodyType type = BodyType::Dynamic;
  Vec3 position = Vec3::Zero();         ///< Position of the body's origin (m, world).
  Quat orientation = Quat::Identity();  ///< Unit quaternion (normalised on creation).
  Vec3 linearVelocity = Vec3::Zero();   ///< Velocity of the centre of mass (m/s, world).
  Vec3 angularVelocity = Vec3::Zero();  ///< Angular velocity (rad/s, world).
  Real linearDamping = 0;               ///< Viscous damping of the linear velocity (1/s, >= 0).
  Real angularDamping = 0;              ///< Viscous damping of the angular velocity (1/s, >= 0).
  Real gravityScale = 1;                ///< Multiplies the world's gravity for this body.
  Real maxLinearSpeed = 400;            ///< Speed limit of the centre of mass (m/s, > 0).
  Real maxAngularSpeed = 200;           ///< Limit of the angular speed (rad/s, > 0).
  /// Mass (kg); 0 takes it from the shapes' densities. When given, the shapes' inertia is
  /// scaled to it (or `inertia` is used).
  Real mass = 0;
  /// Principal moments of inertia about the centre of mass in the body's axes (kg m^2); zero
  /// takes them from the shapes. Only with `mass`.
  Vec3 inertia = Vec3::Zero();
  bool allowSleep = true;  ///< May fall asleep when at rest (if the world allows sleeping).
  /// Continuous collision: speculative contacts over the whole step's motion, so the body
  /// cannot tunnel at any speed. Fast bodies get it automatically (see WorldSettings).
  bool bullet = false;
  std::string name{};  ///< For recordings and messages (optional).
};

/// Checks settings and throws InvalidArgument naming the first bad field.
void validate(const BodySettings& settings);

}  // namespace inertia
