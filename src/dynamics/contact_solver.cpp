#include "contact_solver.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <numeric>
#include <utility>

// The AVX2 and AVX-512 builds of the kernels take their instruction set from a pragma around
// them: GCC's `target`, or clang's attribute on each function (clang ignores GCC's pragma).
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define INERTIA_HAVE_AVX2_KERNELS 1
#endif

namespace inertia::detail {

namespace {

Real invEffective(Real k) { return k > 0 ? Real(1) / k : Real(0); }

}  // namespace

Softness makeSoft(Real hertz, Real zeta, Real h) {
  if (hertz <= 0) return {0, 1, 0};
  const Real omega = Real(2 * std::numbers::pi) * hertz;
  const Real a1 = 2 * zeta + h * omega;
  const Real a2 = h * omega * a1;
  const Real a3 = 1 / (1 + a2);
  return {omega / a1, a2 * a3, a3};
}

std::array<Vec3, 2> tangentBasis(const Vec3& n) {
  const Real sign = std::copysign(Real(1), n.z());
  const Real a = -1 / (sign + n.z());
  const Real b = n.x() * n.y() * a;
  return {Vec3(1 + sign * n.x() * n.x() * a, sign * b, -sign * n.x()),
          Vec3(b, sign + n.y() * n.y() * a, -n.y())};
}

void computeMasses(ContactConstraint& c, const SolverBody& a, const SolverBody& b) {
  const Real mSum = a.invMass + b.invMass;
  // 1 / (mA + mB + (rA x d) . IA (rA x d) + (rB x d) . IB (rB x d)) along direction d.
  auto rowMass = [&](const ConstraintPoint& p, const Vec3& d) {
    const Vec3 rdA = p.rA.cross(d), rdB = p.rB.cross(d);
    return invEffective(mSum + rdA.dot(a.invInertia * rdA) + rdB.dot(b.invInertia * rdB));
  };
  for (int i = 0; i < c.pointCount; ++i) {
    ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
    p.normalMass = rowMass(p, c.normal);
    for (std::size_t k = 0; k < 2; ++k) p.tangentMass[k] = rowMass(p, c.tangent[k]);
  }
  const Mat3 iSum = a.invInertia + b.invInertia;
  for (int k = 0; k < 2; ++k)
    c.rollingMass[k] = invEffective(c.tangent[k].dot(iSum * c.tangent[k]));
  c.spinningMass = invEffective(c.normal.dot(iSum * c.normal));
}

void colorConstraints(const std::vector<ContactConstraint>& cs,
                      const std::vector<SolverBody>& bodies, ConstraintColoring& out) {
  out.edges.resize(cs.size());
  for (std::size_t k = 0; k < cs.size(); ++k) out.edges[k] = {cs[k].bodyA, cs[k].bodyB};
  colorGraph({}, out.edges, bodies, out);
}

// The kernels, once per instruction set (contact_kernels.inl).
namespace sse2 {
#define INERTIA_PACK_BYTES 16
#include "contact_kernels.inl"
#undef INERTIA_PACK_BYTES
}  // namespace sse2

#ifdef INERTIA_HAVE_AVX2_KERNELS
#ifdef __clang__
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
namespace avx2 {
#define INERTIA_PACK_BYTES 32
#include "contact_kernels.inl"
#undef INERTIA_PACK_BYTES
}  // namespace avx2
#ifdef __clang__
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

// AVX-512F alone: the kernels use 512-bit registers, and the set brings thirty-two of them.
#ifdef __clang__
#pragma clang attribute push(__attribute__((target("avx512f"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f")
#endif
namespace avx512 {
#define INERTIA_PACK_BYTES 64
#include "contact_kernels.inl"
#undef INERTIA_PACK_BYTES
}  // namespace avx512
#ifdef __clang__
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif

namespace {

struct Kernels {
  void (*prepare)(WideConstraint&, const WideInertia&);
  void (*warmStart)(const WideConstraint*, std::size_t, SolverBody*);
  void (*solve)(WideConstraint*, std::size_t, SolverBody*, const BiasMode&);
  void (*beginApproach)(WideConstraint*, std::size_t, const SolverBody*);
  void (*updateApproach)(WideConstraint*, std::size_t, const SolverBody*, Real, Real);
  void (*restitution)(WideConstraint*, std::size_t, SolverBody*, Real);
  void (*updateMotion)(WideConstraint*, std::size_t, const SolverBody*);
};

constexpr Kernels kSse2{sse2::prepareBundle,      sse2::warmStartRange,      sse2::solveRange,
                        sse2::beginApproachRange, sse2::updateApproachRange, sse2::restitutionRange,
                        sse2::updateMotionRange};
#ifdef INERTIA_HAVE_AVX2_KERNELS
constexpr Kernels kAvx2{avx2::prepareBundle,      avx2::warmStartRange,      avx2::solveRange,
                        avx2::beginApproachRange, avx2::updateApproachRange, avx2::restitutionRange,
                        avx2::updateMotionRange};
constexpr Kernels kAvx512{avx512::prepareBundle,       avx512::warmStartRange,
                          avx512::solveRange,          avx512::beginApproachRange,
                          avx512::updateApproachRange, avx512::restitutionRange,
                          avx512::updateMotionRange};
#endif

SimdChoice& contactChoice() {
  static SimdChoice choice(std::max(cpuSimdLevel(), SimdLevel::Sse2));
  return choice;
}

const Kernels& kernels() {
#ifdef INERTIA_HAVE_AVX2_KERNELS
  switch (contactChoice().current()) {
    case SimdLevel::Avx512:
      return kAvx512;
    case SimdLevel::Avx2:
      return kAvx2;
    default:
      break;
  }
#endif
  return kSse2;
}

// Every constraint alone, in the order of `cs`.
ConstraintColoring sequentialColoring(std::size_t count) {
  ConstraintColoring c;
  c.order.resize(count);
  std::iota(c.order.begin(), c.order.end(), 0u);
  c.offsets = {0, static_cast<std::uint32_t>(count)};
  c.overflow = true;
  return c;
}

void put3(WideReal (&w)[3], int lane, const Vec3& v) {
  for (int k = 0; k < 3; ++k) w[k].lane[lane] = v[k];
}

// Lane `l` of `w` and of `inertia` from constraint `c`; the rest of `w` is zero.
void packLane(WideConstraint& w, WideInertia& inertia, int l, const ContactConstraint& c,
              const std::vector<SolverBody>& bodies) {
  const SolverBody none{};
  const SolverBody& a = c.bodyA >= 0 ? bodies[std::size_t(c.bodyA)] : none;
  const SolverBody& b = c.bodyB >= 0 ? bodies[std::size_t(c.bodyB)] : none;
  w.bodyA[std::size_t(l)] = c.bodyA;
  w.bodyB[std::size_t(l)] = c.bodyB;
  if (a.invMass > 0) w.writeA |= 1u << l;
  if (b.invMass > 0) w.writeB |= 1u << l;
  w.lanePoints.lane[l] = Real(c.pointCount);
  w.invMassA.lane[l] = a.invMass;
  w.invMassB.lane[l] = b.invMass;
  for (int i = 0; i < 9; ++i) {
    inertia.a[i].lane[l] = a.invInertia(i / 3, i % 3);
    inertia.b[i].lane[l] = b.invInertia(i / 3, i % 3);
  }
  put3(w.normal, l, c.normal);
  for (std::size_t k = 0; k < 2; ++k) put3(w.tangent[k], l, c.tangent[k]);
  w.friction.lane[l] = c.friction;
  w.restitution.lane[l] = c.restitution;
  w.bouncy = w.bouncy || c.restitution != 0;
  w.biasRate.lane[l] = c.softness.biasRate;
  w.massScale.lane[l] = c.softness.massScale;
  w.impulseScale.lane[l] = c.softness.impulseScale;
  if (c.rolling > 0 || c.spinning > 0) {
    w.angular = true;
    w.rolling.lane[l] = c.rolling;
    w.spinning.lane[l] = c.spinning;
    for (std::size_t k = 0; k < 2; ++k) w.rollingImpulse[k].lane[l] = c.rollingImpulse[k];
    w.spinningImpulse.lane[l] = c.spinningImpulse;
  }
  for (int i = 0; i < c.pointCount; ++i) {
    const ConstraintPoint& p = c.points[std::size_t(i)];
    WidePoint& q = w.points[std::size_t(i)];
    put3(q.rA, l, p.rA);
    put3(q.rB, l, p.rB);
    q.adjustedSeparation.lane[l] = p.adjustedSeparation;
    q.normalImpulse.lane[l] = p.normalImpulse;
    q.maxNormalImpulse.lane[l] = p.maxNormalImpulse;
    q.relativeVelocity.lane[l] = p.relativeVelocity;
    q.launch.lane[l] = p.launch;
    for (std::size_t k = 0; k < 2; ++k) q.tangentImpulse[k].lane[l] = p.tangentImpulse[k];
  }
}

}  // namespace

SimdLevel bestContactSimd() { return contactChoice().best(); }
SimdLevel contactSimd() { return contactChoice().current(); }
SimdLevel setContactSimd(SimdLevel level) {
  return contactChoice().force(std::max(level, SimdLevel::Sse2));
}

// A colour's bundles share no moving body, so the workers run them in blocks with the same
// result as in sequence. The overflow group, whose bundles may share bodies, runs in sequence
// on the main worker.
template <class Pass>
void ContactBundles::forColors(StepWorkers& workers, Pass pass) const {
  const std::size_t groups = groupOffsets_.empty() ? 0 : groupOffsets_.size() - 1;
  for (std::size_t g = 0; g < groups; ++g) {
    const std::uint32_t begin = groupOffsets_[g], end = groupOffsets_[g + 1];
    if (g + 1 == groups && overflow_) {
      pass(begin, std::size_t(end - begin));
      continue;
    }
    workers.parallelFor(end - begin, kBundleGrain, [&](std::size_t first, std::size_t last) {
      pass(std::uint32_t(begin + first), last - first);
    });
  }
}

template <class Pass>
void ContactBundles::forAll(StepWorkers& workers, Pass pass) const {
  workers.parallelFor(
      bundles_.size(),
      [&](std::size_t first, std::size_t last) { pass(std::uint32_t(first), last - first); },
      kBundleGrain);
}

void ContactBundles::build(const std::vector<ContactConstraint>& cs,
                           const std::vector<SolverBody>& bodies,
                           const ConstraintColoring& coloring, StepWorkers& workers) {
  const std::size_t groups = coloring.offsets.empty() ? 0 : coloring.offsets.size() - 1;
  overflow_ = coloring.overflow;
  groupOffsets_.assign(1, 0);
  members_.resize(coloring.order.size());
  firstMember_.clear();
  // The members of each bundle, in sequence (cheap); the bundles are then packed in parallel.
  for (std::size_t g = 0; g < groups; ++g) {
    const bool sequential = g + 1 == groups && overflow_;
    const std::uint32_t offset = coloring.offsets[g];
    const auto begin = coloring.order.begin() + offset;
    const auto end = coloring.order.begin() + coloring.offsets[g + 1];
    std::uint32_t* members = members_.data() + offset;
    if (sequential) {
      std::copy(begin, end, members);
    } else {
      // Lanes of a bundle run as many points as its fullest lane: bundle like with like, most
      // points first (a stable counting sort on 0..4 points). The order within a colour does
      // not change the result.
      std::array<std::uint32_t, 5> slot{};
      for (auto it = begin; it != end; ++it) ++slot[std::size_t(4 - cs[*it].pointCount)];
      for (std::uint32_t k = 0, sum = 0; k < slot.size(); ++k) sum += std::exchange(slot[k], sum);
      for (auto it = begin; it != end; ++it)
        members[slot[std::size_t(4 - cs[*it].pointCount)]++] = *it;
    }
    const std::uint32_t per = sequential ? 1 : std::uint32_t(kLanes);
    for (std::uint32_t first = offset; first < coloring.offsets[g + 1]; first += per)
      firstMember_.push_back(first);
    groupOffsets_.push_back(static_cast<std::uint32_t>(firstMember_.size()));
  }
  firstMember_.push_back(static_cast<std::uint32_t>(coloring.order.size()));
  bundles_.resize(firstMember_.size() - 1);
  const Kernels& kernel = kernels();
  workers.parallelFor(
      bundles_.size(),
      [&](std::size_t firstBundle, std::size_t lastBundle) {
        for (std::size_t i = firstBundle; i < lastBundle; ++i) {
          WideConstraint& w = bundles_[i];
          // A bundle ends at the next one's first member, or at its group's end.
          const std::uint32_t first = firstMember_[i];
          const int lanes = int(std::min<std::uint32_t>(firstMember_[i + 1] - first, kLanes));
          int points = 0;
          for (int l = 0; l < lanes; ++l)
            points = std::max(points, cs[members_[first + std::uint32_t(l)]].pointCount);
          w.clear(points);
          w.bodyA.fill(-1);
          w.bodyB.fill(-1);
          w.lanes = lanes;
          w.pointCount = points;
          WideInertia inertia{};
          for (int l = 0; l < w.lanes; ++l) {
            const std::uint32_t k = members_[first + std::uint32_t(l)];
            w.source[std::size_t(l)] = k;
            packLane(w, inertia, l, cs[k], bodies);
          }
          kernel.prepare(w, inertia);
        }
      },
      8);
  updateMotion(bodies, workers);
}

void ContactBundles::updateMotion(const std::vector<SolverBody>& bodies, StepWorkers& workers) {
  const Kernels& k = kernels();
  forAll(workers, [&](std::uint32_t first, std::size_t count) {
    k.updateMotion(bundles_.data() + first, count, bodies.data());
  });
}

void ContactBundles::warmStart(std::vector<SolverBody>& bodies, StepWorkers& workers) const {
  const Kernels& k = kernels();
  forColors(workers, [&](std::uint32_t first, std::size_t count) {
    k.warmStart(bundles_.data() + first, count, bodies.data());
  });
}

void ContactBundles::solve(std::vector<SolverBody>& bodies, const BiasMode& mode,
                           StepWorkers& workers) {
  const Kernels& k = kernels();
  forColors(workers, [&](std::uint32_t first, std::size_t count) {
    k.solve(bundles_.data() + first, count, bodies.data(), mode);
  });
}

void ContactBundles::warmStart(SolverBody* bodies, std::uint32_t first, std::size_t count) const {
  kernels().warmStart(bundles_.data() + first, count, bodies);
}

void ContactBundles::solve(SolverBody* bodies, const BiasMode& mode, std::uint32_t first,
                           std::size_t count) {
  kernels().solve(bundles_.data() + first, count, bodies, mode);
}

void ContactBundles::beginApproach(const std::vector<SolverBody>& bodies, StepWorkers& workers) {
  const Kernels& k = kernels();
  forAll(workers, [&](std::uint32_t first, std::size_t count) {
    k.beginApproach(bundles_.data() + first, count, bodies.data());
  });
}

void ContactBundles::updateApproach(const std::vector<SolverBody>& bodies, Real h, Real flight,
                                    StepWorkers& workers) {
  const Kernels& k = kernels();
  forAll(workers, [&](std::uint32_t first, std::size_t count) {
    k.updateApproach(bundles_.data() + first, count, bodies.data(), 1 / h, flight);
  });
}

void ContactBundles::applyRestitution(std::vector<SolverBody>& bodies, Real threshold,
                                      StepWorkers& workers) {
  const Kernels& k = kernels();
  forColors(workers, [&](std::uint32_t first, std::size_t count) {
    k.restitution(bundles_.data() + first, count, bodies.data(), threshold);
  });
}

void ContactBundles::store(std::vector<ContactConstraint>& cs, StepWorkers& workers) const {
  // A lane's constraint is its own: the bundles write disjoint constraints.
  forAll(workers, [&](std::uint32_t firstBundle, std::size_t count) {
    for (std::size_t b = firstBundle; b < firstBundle + count; ++b) {
      const WideConstraint& w = bundles_[b];
      for (int l = 0; l < w.lanes; ++l) {
        ContactConstraint& c = cs[w.source[std::size_t(l)]];
        for (int i = 0; i < c.pointCount; ++i) {
          ConstraintPoint& p = c.points[std::size_t(i)];
          const WidePoint& q = w.points[std::size_t(i)];
          p.normalImpulse = q.normalImpulse.lane[l];
          p.maxNormalImpulse = q.maxNormalImpulse.lane[l];
          p.relativeVelocity = q.relativeVelocity.lane[l];
          p.launch = q.launch.lane[l];
          for (std::size_t k = 0; k < 2; ++k) p.tangentImpulse[k] = q.tangentImpulse[k].lane[l];
        }
        if (c.rolling > 0 || c.spinning > 0) {
          for (std::size_t k = 0; k < 2; ++k) c.rollingImpulse[k] = w.rollingImpulse[k].lane[l];
          c.spinningImpulse = w.spinningImpulse.lane[l];
        }
      }
    }
  });
}

void ContactBundles::build(const std::vector<ContactConstraint>& cs,
                           const std::vector<SolverBody>& bodies,
                           const ConstraintColoring& coloring) {
  StepWorkers::run(nullptr, [&](StepWorkers& w) { build(cs, bodies, coloring, w); });
}

void ContactBundles::updateMotion(const std::vector<SolverBody>& bodies) {
  StepWorkers::run(nullptr, [&](StepWorkers& w) { updateMotion(bodies, w); });
}

void ContactBundles::warmStart(std::vector<SolverBody>& bodies, tbb::task_arena* arena) const {
  StepWorkers::run(arena, [&](StepWorkers& w) { warmStart(bodies, w); });
}

void ContactBundles::solve(std::vector<SolverBody>& bodies, const BiasMode& mode,
                           tbb::task_arena* arena) {
  StepWorkers::run(arena, [&](StepWorkers& w) { solve(bodies, mode, w); });
}

void ContactBundles::beginApproach(const std::vector<SolverBody>& bodies) {
  StepWorkers::run(nullptr, [&](StepWorkers& w) { beginApproach(bodies, w); });
}

void ContactBundles::updateApproach(const std::vector<SolverBody>& bodies, Real h, Real flight) {
  StepWorkers::run(nullptr, [&](StepWorkers& w) { updateApproach(bodies, h, flight, w); });
}

void ContactBundles::applyRestitution(std::vector<SolverBody>& bodies, Real threshold,
                                      tbb::task_arena* arena) {
  StepWorkers::run(arena, [&](StepWorkers& w) { applyRestitution(bodies, threshold, w); });
}

void ContactBundles::store(std::vector<ContactConstraint>& cs) const {
  StepWorkers::run(nullptr, [&](StepWorkers& w) { store(cs, w); });
}

namespace {

// Packs `cs` one constraint per bundle, runs `pass`, and stores the impulses back.
template <class Pass>
void runSequential(std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies,
                   Pass pass) {
  ContactBundles bundles;
  bundles.build(cs, bodies, sequentialColoring(cs.size()));
  pass(bundles);
  bundles.store(cs);
}

}  // namespace

void warmStart(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies) {
  runSequential(cs, bodies, [&](ContactBundles& b) { b.warmStart(bodies, nullptr); });
}

void solve(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
           const BiasMode& mode) {
  runSequential(cs, bodies, [&](ContactBundles& b) { b.solve(bodies, mode, nullptr); });
}

void beginApproach(std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies) {
  runSequential(cs, bodies, [&](ContactBundles& b) { b.beginApproach(bodies); });
}

void updateApproach(std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies,
                    Real h, Real flight) {
  runSequential(cs, bodies, [&](ContactBundles& b) { b.updateApproach(bodies, h, flight); });
}

void applyRestitution(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      Real threshold) {
  runSequential(cs, bodies,
                [&](ContactBundles& b) { b.applyRestitution(bodies, threshold, nullptr); });
}

}  // namespace inertia::detail

namespace inertia {

const char* contactSolverInstructionSet() { return detail::simdLevelName(detail::contactSimd()); }

}  // namespace inertia
