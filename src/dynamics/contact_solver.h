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

#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "constraint_graph.h"
#include "core/simd.h"
#include "inertia/core/types.h"
#include "step_workers.h"

namespace inertia::detail {

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
  /// Normal velocity (m/s): at the step's start, then the approach speed at impact
  /// (ContactBundles::updateApproach), for restitution.
  Real relativeVelocity = 0;
  /// The normal speed restitution leaves the point with (m/s, >= 0): e times the approach
  /// speed, on the flight integrator's modified energy (updateApproach).
  Real launch = 0;
};

struct ContactConstraint {
  int bodyA = -1;  ///< Solver body index, -1 for a static body.
  int bodyB = -1;
  Vec3 normal = Vec3::UnitY();
  std::array<Vec3, 2> tangent{Vec3::UnitX(), Vec3::UnitZ()};
  std::array<ConstraintPoint, 4> points{};
  int pointCount = 0;
  Real friction = 0;  ///< The coefficient in use this step (static while sticking).
  Real restitution = 0;
  Real rolling = 0;   ///< Lever arm (m).
  Real spinning = 0;  ///< Lever arm (m).
  std::array<Real, 2> rollingMass{};
  std::array<Real, 2> rollingImpulse{};
  Real spinningMass = 0;
  Real spinningImpulse = 0;
  Softness softness{};
  int contactIndex = 0;  ///< Which ContactInfo it came from.
};

/// Tangent directions completing `n` to a right-handed orthonormal basis, a function of n alone
/// (Frisvad / Duff et al. 2017 "Building an orthonormal basis, revisited"): no branch flips
/// for nearby normals except across n.z = 0's sign.
std::array<Vec3, 2> tangentBasis(const Vec3& n);

/// Effective masses of the rows of `c` from its bodies (anchors, normal and tangents already
/// set), for the LCP solvers. The bundles compute their own, with the Jacobians
/// (ContactBundles::build).
void computeMasses(ContactConstraint& c, const SolverBody& a, const SolverBody& b);

/// Colours the constraint graph of `cs` alone (colorGraph with no joints).
void colorConstraints(const std::vector<ContactConstraint>& cs,
                      const std::vector<SolverBody>& bodies, ConstraintColoring& out);

/// How a solve pass treats position error.
struct BiasMode {
  bool soft = true;       ///< Soft step rows (else rigid with Baumgarte).
  bool useBias = true;    ///< false: relax pass, velocities only.
  Real invH = 0;          ///< 1 / substep (1/s).
  Real pushVelocity = 3;  ///< Largest push-out speed (m/s).
  Real baumgarte = Real(0.2);
  Real linearSlop = Real(0.005);
};

/// Constraints per bundle: one AVX-512 register of Real (16 floats or 8 doubles). The SSE2
/// and AVX2 kernels run a bundle in two slices of 32 bytes.
inline constexpr int kLanes = int(64 / sizeof(Real));
/// Bundles per block of a colour's parallel pass: about kColorGrain constraints.
inline constexpr std::size_t kBundleGrain = std::max<std::size_t>(1, kColorGrain / kLanes);

/// kLanes values, one per constraint of a bundle.
struct alignas(64) WideReal {
  Real lane[kLanes];
};

/// The rows of one contact point of each constraint of a bundle (the fields of
/// ConstraintPoint, lane by lane).
struct WidePoint {
  WideReal rA[3], rB[3];
  WideReal adjustedSeparation, normalMass, tangentMass[2];
  /// The current separation (m): adjustedSeparation plus the bodies' motion since the step's
  /// start, refreshed by ContactBundles::build and updateMotion.
  WideReal separation;
  WideReal normalImpulse, tangentImpulse[2], maxNormalImpulse, relativeVelocity, launch;
  WideReal rnA[3], rnB[3], wnA[3], wnB[3];
  WideReal rtA[2][3], rtB[2][3], wtA[2][3], wtB[2][3];
};

/// kLanes constraints that share no moving body, solved together lane by lane (Box2D v3's
/// wide solver, in 3D). Lanes without a constraint, and points beyond a lane's own count, have
/// zero masses: they compute impulses of zero.
struct WideConstraint {
  std::array<int, kLanes> bodyA{};  ///< Solver body, -1 for a static body or an empty lane.
  std::array<int, kLanes> bodyB{};
  std::uint32_t writeA = 0;  ///< Bit l: lane l's body A takes impulses (moving).
  std::uint32_t writeB = 0;
  std::array<std::uint32_t, kLanes> source{};  ///< The lanes' constraints (index into cs).
  int lanes = 0;                               ///< Lanes in use, from lane 0.
  int pointCount = 0;                          ///< The most points of any lane.
  bool angular = false;                        ///< Some lane has rolling or spinning friction.
  bool bouncy = false;                         ///< Some lane has restitution.
  WideReal normal[3], tangent[2][3];
  WideReal invMassA, invMassB;
  WideReal friction, restitution, rolling, spinning;
  WideReal rollingMass[2], rollingImpulse[2], spinningMass, spinningImpulse;
  WideReal biasRate, massScale, impulseScale;
  WideReal lanePoints;  ///< Each lane's own point count.
  // Images of the tangents and the normal under the inverse inertias, for the rolling and
  // spinning rows (only when `angular`).
  WideReal iaT[2][3], iaN[3], ibT[2][3], ibN[3];
  // Not initialised: a bundle is 16 KB (8 in double), most of it points, and the pile
  // scene's bundles use one point in four. clear() zeroes the part a bundle uses.
  std::array<WidePoint, 4> points;

  /// Zeroes every field and the first `pointCount` points; the others stay unread.
  void clear(int pointCount) {
    std::memset(static_cast<void*>(this), 0,
                offsetof(WideConstraint, points) + std::size_t(pointCount) * sizeof(WidePoint));
  }
};
static_assert(std::is_trivially_copyable_v<WideConstraint> &&
              std::is_standard_layout_v<WideConstraint>);

/// std::allocator, but resize() default-initialises new elements instead of value-initialising
/// them, so that growing the bundles does not zero what clear() zeroes again.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  using value_type = T;
  DefaultInitAllocator() noexcept = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// The inverse inertias of a bundle's bodies, lane by lane (row-major 3x3).
struct WideInertia {
  WideReal a[9], b[9];
};

/// The contact constraints of a step packed into bundles colour by colour: the bundles of a
/// colour share no moving body, so the step's workers run them in parallel with the same result as
/// in sequence, and the kLanes constraints of a bundle run in the lanes of SIMD registers
/// (AVX-512 or AVX2 when the processor has it, else SSE2; all give the same bits). The overflow
/// colour is packed one constraint per bundle and runs in sequence. A lane computes exactly
/// what the constraint would alone, so the result is independent of the packing, the
/// instruction set and the thread count.
class ContactBundles {
 public:
  /// Packs `cs` in the order of `coloring`, computes the rows' effective masses and angular
  /// Jacobians (as computeMasses, lane by lane: `cs` need not have them), and takes the bodies'
  /// motion since the step's start as updateMotion() does. The bundles are packed by the workers.
  void build(const std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies,
             const ConstraintColoring& coloring, StepWorkers& workers);
  /// Refreshes the points' separations from the bodies' dp and dR: after each position update.
  /// With the normal in the frames of A's and B's motion since the step's start, dRA^T n and
  /// dRB^T n, and n . (dpB - dpA), a point's separation is
  /// n . (dpB - dpA) + (dRB^T n) . rB - (dRA^T n) . rA + adjustedSeparation.
  void updateMotion(const std::vector<SolverBody>& bodies, StepWorkers& workers);

  /// Applies the accumulated impulses of every constraint to its bodies.
  void warmStart(std::vector<SolverBody>& bodies, StepWorkers& workers) const;
  /// One Gauss-Seidel pass over every constraint.
  void solve(std::vector<SolverBody>& bodies, const BiasMode& mode, StepWorkers& workers);
  /// The approach speed at impact, for restitution, of the points whose gap is still open and
  /// that have not pushed yet (only constraints with restitution): beginApproach() keeps their
  /// normal velocity v0 before a substep's velocity update, and updateApproach() after it (v1)
  /// makes it the speed at which the gap s closes under the substep's normal acceleration
  /// a = (v1 - v0) / h: v^2 = v0^2 - 2 a s. A point keeps the value of the substep in which it
  /// first pushes, i.e. touches. (The substep's velocity v1 would be up to |a| h off, and the
  /// step's start velocity up to |a| dt.) `flight` is the lag of the free flight's integrator
  /// (flightLag): restitution then acts on the energy that integrator conserves.
  void beginApproach(const std::vector<SolverBody>& bodies, StepWorkers& workers);
  void updateApproach(const std::vector<SolverBody>& bodies, Real h, Real flight,
                      StepWorkers& workers);
  /// Newton's impact law after the substeps: points that approached faster than `threshold`
  /// (m/s) and carried an impulse leave with restitution times their approach speed.
  void applyRestitution(std::vector<SolverBody>& bodies, Real threshold, StepWorkers& workers);
  /// Writes the impulses, approach speeds and largest impulses back into `cs`.
  void store(std::vector<ContactConstraint>& cs, StepWorkers& workers) const;

  // Per group, for a solve loop that runs other constraints of each colour beside the
  // contacts (solver_stages.cpp): the groups are the colouring's, the overflow last.
  std::size_t groupCount() const { return groupOffsets_.empty() ? 0 : groupOffsets_.size() - 1; }
  std::uint32_t groupBegin(std::size_t g) const { return groupOffsets_[g]; }
  std::uint32_t groupEnd(std::size_t g) const { return groupOffsets_[g + 1]; }
  /// Group g may share bodies between its bundles: it runs in sequence.
  bool sequentialGroup(std::size_t g) const { return overflow_ && g + 1 == groupCount(); }
  /// warmStart and solve on bundles [first, first + count) of one group.
  void warmStart(SolverBody* bodies, std::uint32_t first, std::size_t count) const;
  void solve(SolverBody* bodies, const BiasMode& mode, std::uint32_t first, std::size_t count);

  // The same, each on its own workers of `arena` (in sequence without one): for tests and the
  // LCP solvers' fallback.
  void build(const std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies,
             const ConstraintColoring& coloring);
  void updateMotion(const std::vector<SolverBody>& bodies);
  void warmStart(std::vector<SolverBody>& bodies, tbb::task_arena* arena) const;
  void solve(std::vector<SolverBody>& bodies, const BiasMode& mode, tbb::task_arena* arena);
  void beginApproach(const std::vector<SolverBody>& bodies);
  void updateApproach(const std::vector<SolverBody>& bodies, Real h, Real flight);
  void applyRestitution(std::vector<SolverBody>& bodies, Real threshold, tbb::task_arena* arena);
  void store(std::vector<ContactConstraint>& cs) const;

 private:
  // Runs pass(first, count) over the bundles colour by colour (see the .cpp).
  template <class Pass>
  void forColors(StepWorkers& workers, Pass pass) const;
  // Runs pass(first, count) over all bundles in blocks, for passes whose bundles are
  // independent (they read the bodies but do not write them).
  template <class Pass>
  void forAll(StepWorkers& workers, Pass pass) const;

  std::vector<WideConstraint, DefaultInitAllocator<WideConstraint>> bundles_;
  std::vector<std::uint32_t> groupOffsets_;  ///< Colour g is bundles_[offsets[g], offsets[g + 1]).
  bool overflow_ = false;                    ///< The last group runs in sequence.
  // Scratch of build(): the constraints in bundle order, and each bundle's first member.
  std::vector<std::uint32_t> members_;
  std::vector<std::uint32_t> firstMember_;
};

/// The set the bundle kernels can use: AVX-512 or AVX2 when the processor has it, else SSE2
/// (GCC's generic 16-byte vectors off x86).
SimdLevel bestContactSimd();
/// The set the kernels use: bestContactSimd() unless a test forced a narrower one.
SimdLevel contactSimd();
/// Forces the set (clamped to bestContactSimd(), and at least SSE2); returns the previous one.
/// For tests; not while a step runs.
SimdLevel setContactSimd(SimdLevel level);

// The same passes on constraints one at a time in the order of `cs` (for the LCP solvers'
// fallback and for tests): each packs `cs` one constraint per bundle, runs, and stores back.
void warmStart(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies);
void solve(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
           const BiasMode& mode);
void beginApproach(std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies);
void updateApproach(std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies,
                    Real h, Real flight);
void applyRestitution(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      Real threshold);

}  // namespace inertia::detail
