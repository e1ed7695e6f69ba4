#include "contact_solver.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace inertia::detail {

namespace {

// The static body: no velocity, no motion, infinite mass.
const SolverBody kStatic{};

Real invEffective(Real k) { return k > 0 ? Real(1) / k : Real(0); }

// An impulse `lambda` along one row: direction d, Jacobian images wA = invIA (rA x d) and
// wB = invIB (rB x d).
[[gnu::always_inline]] inline void applyRow(SolverBody& a, SolverBody& b, const Vec3& d, const Vec3& wA, const Vec3& wB,
                     Real lambda) {
  a.v -= (a.invMass * lambda) * d;
  a.w -= lambda * wA;
  b.v += (b.invMass * lambda) * d;
  b.w += lambda * wB;
}

// The velocity along one row: d . (vB - vA) + wB . (rB x d) - wA . (rA x d).
[[gnu::always_inline]] inline Real rowVelocity(const SolverBody& a, const SolverBody& b, const Vec3& d, const Vec3& rA,
                        const Vec3& rB) {
  return d.dot(b.v - a.v) + b.w.dot(rB) - a.w.dot(rA);
}

inline void applyAngular(SolverBody& a, SolverBody& b, const Vec3& L) {
  a.w -= a.invInertia * L;
  b.w += b.invInertia * L;
}

// The normal n in the frames of A's and B's motion since the step's start (n . (dR r) =
// (dR^T n) . r), so a point's current separation costs two dot products.
struct MovedNormal {
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  Real offset = 0;  ///< n . (dpB - dpA)
};

[[gnu::always_inline]] inline MovedNormal movedNormal(const SolverBody& a, const SolverBody& b,
                                            const Vec3& n) {
  return {a.dR.transpose() * n, b.dR.transpose() * n, n.dot(b.dp - a.dp)};
}

// The separation of point p now, from the bodies' motion since the step's start.
[[gnu::always_inline]] inline Real currentSeparation(const MovedNormal& m, const ConstraintPoint& p) {
  return m.offset + m.b.dot(p.rB) - m.a.dot(p.rA) + p.adjustedSeparation;
}

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
  for (int i = 0; i < c.pointCount; ++i) {
    ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
    p.rnA = p.rA.cross(c.normal);
    p.rnB = p.rB.cross(c.normal);
    p.wnA = a.invInertia * p.rnA;
    p.wnB = b.invInertia * p.rnB;
    p.normalMass = invEffective(mSum + p.rnA.dot(p.wnA) + p.rnB.dot(p.wnB));
    for (std::size_t k = 0; k < 2; ++k) {
      p.rtA[k] = p.rA.cross(c.tangent[k]);
      p.rtB[k] = p.rB.cross(c.tangent[k]);
      p.wtA[k] = a.invInertia * p.rtA[k];
      p.wtB[k] = b.invInertia * p.rtB[k];
      p.tangentMass[k] = invEffective(mSum + p.rtA[k].dot(p.wtA[k]) + p.rtB[k].dot(p.wtB[k]));
    }
  }
  const Mat3 iSum = a.invInertia + b.invInertia;
  for (int k = 0; k < 2; ++k) c.rollingMass[k] = invEffective(c.tangent[k].dot(iSum * c.tangent[k]));
  c.spinningMass = invEffective(c.normal.dot(iSum * c.normal));
}

namespace {

void warmStartOne(ContactConstraint& c, SolverBody& a, SolverBody& b) {
  for (int i = 0; i < c.pointCount; ++i) {
    const ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
    applyRow(a, b, c.normal, p.wnA, p.wnB, p.normalImpulse);
    for (std::size_t k = 0; k < 2; ++k)
      applyRow(a, b, c.tangent[k], p.wtA[k], p.wtB[k], p.tangentImpulse[k]);
  }
  if (c.rolling > 0 || c.spinning > 0)
    applyAngular(a, b,
                 c.rollingImpulse[0] * c.tangent[0] + c.rollingImpulse[1] * c.tangent[1] +
                     c.spinningImpulse * c.normal);
}

void solveOne(ContactConstraint& c, SolverBody& a, SolverBody& b, const BiasMode& mode) {
  {
    const Vec3& n = c.normal;
    const MovedNormal moved = movedNormal(a, b, n);
    Real totalNormal = 0;

    // Non-penetration rows.
    for (int i = 0; i < c.pointCount; ++i) {
      ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
      const Real s = currentSeparation(moved, p);
      Real bias = 0, massScale = 1, impulseScale = 0;
      if (s > 0) {
        bias = s * mode.invH;  // speculative: the gap may close within this substep, no more
      } else if (mode.useBias) {
        if (mode.soft) {
          bias = std::max(c.softness.biasRate * s, -mode.pushVelocity);
          massScale = c.softness.massScale;
          impulseScale = c.softness.impulseScale;
        } else {
          // Baumgarte: feed back a fraction of the overlap beyond the slop.
          bias = std::max(mode.baumgarte * mode.invH * std::min(s + mode.linearSlop, Real(0)),
                          -mode.pushVelocity);
        }
      }
      const Real vn = rowVelocity(a, b, n, p.rnA, p.rnB);
      Real impulse = -p.normalMass * massScale * (vn + bias) - impulseScale * p.normalImpulse;
      const Real updated = std::max(p.normalImpulse + impulse, Real(0));
      impulse = updated - p.normalImpulse;
      p.normalImpulse = updated;
      p.maxNormalImpulse = std::max(p.maxNormalImpulse, impulse);
      totalNormal += updated;
      applyRow(a, b, n, p.wnA, p.wnB, impulse);
    }

    // Coulomb friction: the tangential impulse stays in the disc of radius mu * normal.
    for (int i = 0; i < c.pointCount; ++i) {
      ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
      std::array<Real, 2> updated;
      for (std::size_t k = 0; k < 2; ++k)
        updated[k] = p.tangentImpulse[k] -
                     p.tangentMass[k] * rowVelocity(a, b, c.tangent[k], p.rtA[k], p.rtB[k]);
      const Real limit = c.friction * p.normalImpulse;
      const Real len2 = updated[0] * updated[0] + updated[1] * updated[1];
      // Without a branch (sliding or sticking is unpredictable): scaling by 1 is exact.
      const Real scale = len2 > limit * limit ? limit / std::sqrt(len2) : Real(1);
      updated[0] *= scale;
      updated[1] *= scale;
      for (std::size_t k = 0; k < 2; ++k)
        applyRow(a, b, c.tangent[k], p.wtA[k], p.wtB[k], updated[k] - p.tangentImpulse[k]);
      p.tangentImpulse = updated;
    }
    // Rolling resistance (torque <= b N about the tangents) and spinning friction.
    if (c.rolling > 0) {
      const Vec3 dw = b.w - a.w;
      std::array<Real, 2> updated;
      for (int k = 0; k < 2; ++k)
        updated[k] = c.rollingImpulse[k] - c.rollingMass[k] * dw.dot(c.tangent[k]);
      const Real limit = c.rolling * totalNormal;
      const Real len2 = updated[0] * updated[0] + updated[1] * updated[1];
      if (len2 > limit * limit) {
        const Real scale = limit / std::sqrt(len2);
        updated[0] *= scale;
        updated[1] *= scale;
      }
      applyAngular(a, b, (updated[0] - c.rollingImpulse[0]) * c.tangent[0] +
                             (updated[1] - c.rollingImpulse[1]) * c.tangent[1]);
      c.rollingImpulse = updated;
    }
    if (c.spinning > 0) {
      const Real limit = c.spinning * totalNormal;
      const Real updated = std::clamp(c.spinningImpulse - c.spinningMass * (b.w - a.w).dot(n),
                                      -limit, limit);
      applyAngular(a, b, (updated - c.spinningImpulse) * n);
      c.spinningImpulse = updated;
    }
  }
}

}  // namespace

void updateApproach(std::vector<ContactConstraint>& cs, const std::vector<SolverBody>& bodies) {
  for (ContactConstraint& c : cs) {
    if (c.restitution == 0) continue;
    const SolverBody& a = c.bodyA >= 0 ? bodies[static_cast<std::size_t>(c.bodyA)] : kStatic;
    const SolverBody& b = c.bodyB >= 0 ? bodies[static_cast<std::size_t>(c.bodyB)] : kStatic;
    const MovedNormal moved = movedNormal(a, b, c.normal);
    for (int i = 0; i < c.pointCount; ++i) {
      ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
      if (p.maxNormalImpulse == 0 && currentSeparation(moved, p) > 0)
        p.relativeVelocity = rowVelocity(a, b, c.normal, p.rnA, p.rnB);
    }
  }
}

namespace {

void restitutionOne(ContactConstraint& c, SolverBody& a, SolverBody& b, Real threshold) {
  for (int i = 0; i < c.pointCount; ++i) {
    ConstraintPoint& p = c.points[static_cast<std::size_t>(i)];
    if (p.relativeVelocity > -threshold || p.maxNormalImpulse == 0) continue;
    const Real vn = rowVelocity(a, b, c.normal, p.rnA, p.rnB);
    Real impulse = -p.normalMass * (vn + c.restitution * p.relativeVelocity);
    const Real updated = std::max(p.normalImpulse + impulse, Real(0));
    impulse = updated - p.normalImpulse;
    p.normalImpulse = updated;
    p.maxNormalImpulse = std::max(p.maxNormalImpulse, impulse);
    applyRow(a, b, c.normal, p.wnA, p.wnB, impulse);
  }
}

// Runs `kernel(c, a, b)` on every constraint: the bodies as references into `bodies`, or, for
// a static or kinematic side (inverse mass 0), a private copy that the kernel may write to
// harmlessly, so that constraints sharing only such a body can run at the same time.
template <class Kernel>
void runOne(ContactConstraint& c, std::vector<SolverBody>& bodies, Kernel& kernel) {
  // Per thread and filled only for a fixed side: constructing two bodies per constraint and
  // pass cost more than a friction row.
  thread_local SolverBody fixedA, fixedB;
  auto side = [&](int i, SolverBody& fixed) -> SolverBody& {
    if (i < 0) {
      fixed = kStatic;
      return fixed;
    }
    SolverBody& body = bodies[static_cast<std::size_t>(i)];
    if (body.invMass > 0) return body;
    fixed = body;
    return fixed;
  };
  kernel(c, side(c.bodyA, fixedA), side(c.bodyB, fixedB));
}

// Constraints in colour order; the constraints of one colour share no moving body, so they
// run in parallel on the arena with the same result as in sequence. The overflow group, whose
// constraints may share bodies, runs in sequence.
template <class Kernel>
void runColored(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                const ConstraintColoring& coloring, tbb::task_arena* arena, Kernel kernel) {
  const std::size_t groups = coloring.offsets.empty() ? 0 : coloring.offsets.size() - 1;
  for (std::size_t g = 0; g < groups; ++g) {
    const std::uint32_t begin = coloring.offsets[g], end = coloring.offsets[g + 1];
    auto range = [&](std::uint32_t from, std::uint32_t to) {
      for (std::uint32_t k = from; k < to; ++k) runOne(cs[coloring.order[k]], bodies, kernel);
    };
    const bool overflow = g + 1 == groups && coloring.overflow;
    if (arena && !overflow && end - begin >= 2 * kColorGrain) {
      arena->execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(begin, end, kColorGrain),
                          [&](const tbb::blocked_range<std::uint32_t>& r) {
                            range(r.begin(), r.end());
                          });
      });
    } else {
      range(begin, end);
    }
  }
}

ConstraintColoring identityColoring(std::size_t count) {
  ConstraintColoring c;
  c.order.resize(count);
  std::iota(c.order.begin(), c.order.end(), 0u);
  c.offsets = {0, static_cast<std::uint32_t>(count)};
  c.overflow = true;
  return c;
}

}  // namespace

void colorConstraints(const std::vector<ContactConstraint>& cs,
                      const std::vector<SolverBody>& bodies, ConstraintColoring& out) {
  // Greedy, in constraint order (Box2D v3): each constraint takes the first colour in which
  // neither of its moving bodies is used yet; static and kinematic bodies do not count.
  const std::size_t words = (bodies.size() + 63) / 64;
  std::vector<std::uint64_t> used(kMaxColors * words, 0);
  std::vector<int> color(cs.size(), kMaxColors);
  std::array<std::uint32_t, kMaxColors + 1> counts{};
  auto moving = [&](int i) { return i >= 0 && bodies[static_cast<std::size_t>(i)].invMass > 0; };
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const int a = cs[k].bodyA, b = cs[k].bodyB;
    for (int c = 0; c < kMaxColors; ++c) {
      std::uint64_t* set = used.data() + std::size_t(c) * words;
      auto taken = [&](int i) { return moving(i) && (set[std::size_t(i) / 64] >> (i % 64)) & 1u; };
      if (taken(a) || taken(b)) continue;
      if (moving(a)) set[std::size_t(a) / 64] |= std::uint64_t(1) << (a % 64);
      if (moving(b)) set[std::size_t(b) / 64] |= std::uint64_t(1) << (b % 64);
      color[k] = c;
      break;
    }
    ++counts[std::size_t(color[k])];
  }
  out.offsets.assign(1, 0);
  for (int c = 0; c <= kMaxColors; ++c)
    if (counts[std::size_t(c)] > 0) out.offsets.push_back(out.offsets.back() + counts[std::size_t(c)]);
  out.overflow = counts[kMaxColors] > 0;
  // Stable: within a colour, constraints keep their order.
  std::array<std::uint32_t, kMaxColors + 1> next{};
  for (int c = 0, g = 0; c <= kMaxColors; ++c)
    if (counts[std::size_t(c)] > 0) next[std::size_t(c)] = out.offsets[std::size_t(g++)];
  out.order.resize(cs.size());
  for (std::size_t k = 0; k < cs.size(); ++k)
    out.order[next[std::size_t(color[k])]++] = static_cast<std::uint32_t>(k);
}

void warmStart(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
               const ConstraintColoring& coloring, tbb::task_arena* arena) {
  runColored(cs, bodies, coloring, arena,
             [](ContactConstraint& c, SolverBody& a, SolverBody& b) { warmStartOne(c, a, b); });
}

void solve(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
           const BiasMode& mode, const ConstraintColoring& coloring, tbb::task_arena* arena) {
  runColored(cs, bodies, coloring, arena, [&mode](ContactConstraint& c, SolverBody& a,
                                                  SolverBody& b) { solveOne(c, a, b, mode); });
}

void applyRestitution(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      Real threshold, const ConstraintColoring& coloring,
                      tbb::task_arena* arena) {
  runColored(cs, bodies, coloring, arena,
             [threshold](ContactConstraint& c, SolverBody& a, SolverBody& b) {
               if (c.restitution != 0) restitutionOne(c, a, b, threshold);
             });
}

void warmStart(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies) {
  warmStart(cs, bodies, identityColoring(cs.size()), nullptr);
}

void solve(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
           const BiasMode& mode) {
  solve(cs, bodies, mode, identityColoring(cs.size()), nullptr);
}

void applyRestitution(std::vector<ContactConstraint>& cs, std::vector<SolverBody>& bodies,
                      Real threshold) {
  applyRestitution(cs, bodies, threshold, identityColoring(cs.size()), nullptr);
}

}  // namespace inertia::detail
