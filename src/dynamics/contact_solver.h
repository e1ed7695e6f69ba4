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
#include <cstdint>
#include <vector>

#include <tbb/task_arena.h>

#include "inertia/core/types.h"

namespace inertia::detail {

/// A body as the solver sees it: velocities and the motion since the step's start.
struct SolverBody {
  Vec3 v = Vec3::Zero();   ///< Linear velocity of the centre of mass (m/s).
  Vec3 w = Vec3::Zero();   ///< Angular velocity (rad/s).
  Vec3 dp = Vec3::Zero();  ///< Displacement of the centre of mass since the step's start (m).
  Quat dq = Quat::Identity();  ///< Rotation since the step's start.
  Mat3 dR = Mat3::Identity();  ///< dq as a matrix, refreshed whenever dq changes (cheaper to apply).
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
  // The rows' angular Jacobians and their images under the inverse inertias, fixed for the
  // step (anchors and inertia are frozen at its start), so an iteration applies an impulse with
  // a few scaled additions instead of cross products and matrix products.
  Vec3 rnA = Vec3::Zero();  ///< rA x n
  Vec3 rnB = Vec3::Zero();  ///< rB x n
  Vec3 wnA = Vec3::Zero();  ///< invIA (rA x n)
  Vec3 wnB = Vec3::Zero();  ///< invIB (rB x n)
  std::array<Vec3, 2> rtA{Vec3::Zero(), Vec3::Zero()};  ///< rA x t_k
  std::array<Vec3, 2> rtB{Vec3::Zero(), Vec3::Zero()};
  std::array<Vec3, 2> wtA{Vec3::Zero(), Vec3::Zero()};  ///< invIA (rA x t_k)
  std::array<Vec3, 2> wtB{Vec3::Zero(), Vec3::Zero()};
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

/// Effective masses and angular Jacobians of the rows of `c` from its bodies (anchors, normal
/// and tangents already set).
void computeMasses(ContactConstraint& c, const SolverBody& a, const SolverBody& b);

/// The constraints grouped by colour (graph colouring, as Box2D v3): no two constraints of a
/// colour share a moving body (static and kinematic bodies are shared freely), so a colour's
/// constraints can be solved in parallel with the same result as in sequence. Constraints that
/// find no free colour among kMaxColors form a last, overflow group solved in sequence.
inline constexpr int kMaxColors = 24;
/// Constraints per parallel task.
inline constexpr std::uint32_t kColorGrain = 64;
struct ConstraintColoring {
  std::vector<std::uint32_t> order;    ///< Constraint indices, colour by colour.
  std::vector<std::uint32_t> offsets;  ///< Group g is order[offsets[g], offsets[g + 1]).
  bool overflow = false;               ///< The last group is the overflow.
};

/// Colours `cs` greedily in order: deterministic, independent of any thread count.
void colorConstraints(const std::vector<ContactConstraint>& cs,
                      const std::vector<SolverBody>& bodies, ConstraintColoring& out);

/// Applies the accumulated impulses of every constraint to its bodies.
void warmStart(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies);
/// The same, colour by colour, in parallel on `arena` when given (the result does not depend on
/// it). Likewise the coloured overloads of solve() and applyRestitution() below.
void warmStart(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
               const ConstraintColoring& coloring, tbb::task_arena* arena);

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
void solve(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
           const BiasMode& mode, const ConstraintColoring& coloring, tbb::task_arena* arena);

/// Before a substep's iterations: points whose gap is still open take the current normal
/// velocity as their approach speed, so restitution uses the speed at impact rather than at
/// the step's start (which lags by up to g dt). Only constraints with restitution.
void updateApproach(std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies);

/// Newton's impact law after the substeps: points that approached faster than `threshold`
/// (m/s) and carried an impulse leave with restitution times their approach speed.
void applyRestitution(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      Real threshold);
void applyRestitution(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      Real threshold, const ConstraintColoring& coloring,
                      tbb::task_arena* arena);

}  // namespace inertia::detail
