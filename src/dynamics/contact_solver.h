// Internal: contact constraints and the iterations that solve them.
//
// One set of rows serves both solvers. Per contact point: a non-penetration row along the
// normal, two friction rows in the tangent plane (Coulomb's cone, clamped as a disc), and per
// manifold two rolling rows and one spinning row on the relative angular velocity.
// - soft step (Catto, "Solver2D" 2024 and Box2D v3): per substep integrate velocities, warm
//   start, solve with a soft position bias, integrate positions, relax without bias; after the
//   substeps apply restitution.
// - pgs: the same rows, rigid (no softness), the position error fed back by Baumgarte's
//   stabilisation, no relaxation.
// The current separation is recomputed from the bodies' motion since the step's start (Box2D
// v3's "anchor" trick), so the narrow phase runs once per step while substeps see the
// separation close.
#pragma once

#include <array>
#include <vector>

#include "inertia/core/types.h"

namespace inertia::detail {

/// A body as the solver sees it: velocities and the motion since the step's start.
struct SolverBody {
  Vec3 v = Vec3::Zero();   ///< Linear velocity of the centre of mass (m/s).
  Vec3 w = Vec3::Zero();   ///< Angular velocity (rad/s).
  Vec3 dp = Vec3::Zero();  ///< Displacement of the centre of mass since the step's start (m).
  Quat dq = Quat::Identity();  ///< Rotation since the step's start.
  Real invMass = 0;            ///< (1/kg); 0 for static and kinematic bodies.
  Mat3 invInertia = Mat3::Zero();  ///< World inverse inertia at the step's start (1/(kg m^2)).
};

/// Soft constraint coefficients (Catto: a mass-spring-damper expressed as an implicit row).
struct Softness {
  Real biasRate = 0;
  Real massScale = 1;
  Real impulseScale = 0;
};
Softness makeSoft(Real hertz, Real dampingRatio, Real h);

struct ConstraintPoint {
  Vec3 rA = Vec3::Zero();  ///< Anchor relative to A's centre of mass at the step's start (m).
  Vec3 rB = Vec3::Zero();
  Real adjustedSeparation = 0;  ///< separation - (rB - rA) . n, see the file comment.
  Real normalMass = 0;
  std::array<Real, 2> tangentMass{};
  Real normalImpulse = 0;
  std::array<Real, 2> tangentImpulse{};
  Real maxNormalImpulse = 0;
  Real relativeVelocity = 0;  ///< Normal velocity at the step's start (m/s), for restitution.
};

struct ContactConstraint {
  int bodyA = -1;  ///< Solver body index, -1 for a static body.
  int bodyB = -1;
  Vec3 normal = Vec3::UnitY();
  std::array<Vec3, 2> tangent{Vec3::UnitX(), Vec3::UnitZ()};
  std::array<ConstraintPoint, 4> points{};
  int pointCount = 0;
  Real friction = 0;        ///< The coefficient in use this step (static while sticking).
  Real restitution = 0;
  Real rolling = 0;         ///< Lever arm (m).
  Real spinning = 0;        ///< Lever arm (m).
  std::array<Real, 2> rollingMass{};
  std::array<Real, 2> rollingImpulse{};
  Real spinningMass = 0;
  Real spinningImpulse = 0;
  Softness softness{};
  int contactIndex = 0;     ///< Which ContactInfo it came from.
};

/// Tangent directions completing `n` to a right-handed orthonormal basis, a function of n alone
/// (Frisvad / Duff et al. 2017 "Building an orthonormal basis, revisited"): no branch flips
/// for nearby normals except across n.z = 0's sign.
std::array<Vec3, 2> tangentBasis(const Vec3& n);

/// Effective masses of the rows of `c` from its bodies (anchors and normal already set).
void computeMasses(ContactConstraint& c, const SolverBody& a, const SolverBody& b);

/// Applies the accumulated impulses of every constraint to its bodies.
void warmStart(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies);

/// How a solve pass treats position error.
struct BiasMode {
  bool soft = true;        ///< Soft step rows (else rigid with Baumgarte).
  bool useBias = true;     ///< false: relax pass, velocities only.
  Real invH = 0;           ///< 1 / substep (1/s).
  Real pushVelocity = 3;   ///< Largest push-out speed (m/s).
  Real baumgarte = Real(0.2);
  Real linearSlop = Real(0.005);
};

/// One Gauss-Seidel pass over every constraint, in order.
void solve(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
           const BiasMode& mode);

/// Before a substep's iterations: points whose gap is still open take the current normal
/// velocity as their approach speed, so restitution uses the speed at impact rather than at
/// the step's start (which lags by up to g dt). Only constraints with restitution.
void updateApproach(std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies);

/// Newton's impact law after the substeps: points that approached faster than `threshold`
/// (m/s) and carried an impulse leave with restitution times their approach speed.
void applyRestitution(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      Real threshold);

}  // namespace inertia::detail
