// The contact rows on their own: soft-constraint coefficients, tangent bases, and single
// solves whose answers follow from the impulse equations by hand.
#include "dynamics/contact_solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "../epsilon.h"
#include "../draws.h"

using namespace inertia;
using namespace inertia::detail;
using inertia::test::kRealEps;

namespace {

// A unit-mass body with the inertia of a unit cube's 1/6 (kg m^2) moving at v.
SolverBody body(const Vec3& v) {
  SolverBody b;
  b.v = v;
  b.invMass = 1;
  b.invInertia = Mat3::Identity() * 6;
  return b;
}

// One point under the body's centre, normal +y from the static ground (A) to the body (B).
ContactConstraint pointContact(Real separation, Real friction) {
  ContactConstraint c;
  c.bodyA = -1;
  c.bodyB = 0;
  c.normal = Vec3::UnitY();
  c.tangent = tangentBasis(c.normal);
  c.pointCount = 1;
  c.points[0].rA = Vec3::Zero();
  c.points[0].rB = Vec3(0, Real(-0.5), 0);  // straight below the centre: no lever arm on n
  c.points[0].adjustedSeparation = separation - (c.points[0].rB - c.points[0].rA).dot(c.normal);
  c.friction = friction;
  return c;
}
}  // namespace

// Catto's soft constraint: with omega = 2 pi f, a1 = 2 zeta + h omega, a2 = h omega a1,
// biasRate = omega / a1, massScale = a2 / (1 + a2), impulseScale = 1 / (1 + a2); 0 Hz is rigid.
TEST(ContactSolver, SoftCoefficientsFollowTheClosedForm) {
  const Real f = 30, zeta = 10, h = Real(1.0 / 240.0);
  const double omega = 2 * std::numbers::pi * f, a1 = 2 * zeta + h * omega, a2 = h * omega * a1;
  const Softness s = makeSoft(f, zeta, h);
  EXPECT_NEAR(s.biasRate, omega / a1, 1e-5 * omega / a1);
  EXPECT_NEAR(s.massScale, a2 / (1 + a2), 1e-6);
  EXPECT_NEAR(s.impulseScale, 1 / (1 + a2), 1e-6);
  const Softness rigid = makeSoft(0, zeta, h);
  EXPECT_EQ(rigid.biasRate, 0);
  EXPECT_EQ(rigid.massScale, 1);
  EXPECT_EQ(rigid.impulseScale, 0);
}

TEST(ContactSolver, TangentBasisIsOrthonormalAndRightHanded) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  std::vector<Vec3> normals{Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ(),
                            Vec3(0, 0, -1 + 1e-7).normalized()};
  for (int i = 0; i < 1000; ++i) normals.push_back(inertia::test::draw3<Vec3>([&] { return Real(g(rng)); }).normalized());
  for (const Vec3& n : normals) {
    const auto t = tangentBasis(n);
    EXPECT_NEAR(t[0].norm(), 1, 16 * kRealEps);
    EXPECT_NEAR(t[1].norm(), 1, 16 * kRealEps);
    EXPECT_NEAR(t[0].dot(n), 0, 16 * kRealEps);
    EXPECT_NEAR(t[1].dot(n), 0, 16 * kRealEps);
    EXPECT_NEAR(t[0].dot(t[1]), 0, 16 * kRealEps);
    EXPECT_NEAR(t[0].cross(t[1]).dot(n), 1, 16 * kRealEps);
  }
}

// A rigid pass on a touching point stops the approach exactly: vn = 0 after one solve, with
// the impulse m |vn| (the anchor lies on the normal through the centre, so no rotation).
TEST(ContactSolver, RigidRowStopsTheApproach) {
  std::vector<SolverBody> bodies{body(Vec3(0, -2, 0))};
  std::vector<ContactConstraint> cs{pointContact(0, 0)};
  computeMasses(cs[0], SolverBody{}, bodies[0]);
  EXPECT_NEAR(cs[0].points[0].normalMass, 1, 4 * kRealEps);
  BiasMode mode;
  mode.soft = false;
  mode.invH = 240;
  solve(cs, bodies, mode);
  EXPECT_NEAR(bodies[0].v.y(), 0, 4 * kRealEps);
  EXPECT_NEAR(cs[0].points[0].normalImpulse, 2, 4 * kRealEps);
}

// A speculative point (gap s) lets the body close the gap within the substep and no more:
// vn = -s / h afterwards, and a separating body gets no impulse at all.
TEST(ContactSolver, SpeculativeRowAllowsClosingTheGapOnly) {
  const Real s = Real(0.01), invH = 240;
  std::vector<SolverBody> bodies{body(Vec3(0, -5, 0))};
  std::vector<ContactConstraint> cs{pointContact(s, 0)};
  computeMasses(cs[0], SolverBody{}, bodies[0]);
  BiasMode mode;
  mode.invH = invH;
  solve(cs, bodies, mode);
  EXPECT_NEAR(bodies[0].v.y(), -s * invH, 8 * kRealEps * 5);
  bodies[0].v = Vec3(0, 1, 0);
  cs[0].points[0].normalImpulse = 0;
  solve(cs, bodies, mode);
  EXPECT_EQ(bodies[0].v.y(), 1);
  EXPECT_EQ(cs[0].points[0].normalImpulse, 0);
}

// Coulomb: a sliding point's friction impulse is mu times its normal impulse, opposing the
// slip; a slow point sticks (its tangential velocity is removed within the cone).
TEST(ContactSolver, FrictionIsClampedToTheCone) {
  const Real mu = Real(0.5);
  std::vector<SolverBody> bodies{body(Vec3(3, -1, 0))};
  std::vector<ContactConstraint> cs{pointContact(0, mu)};
  cs[0].tangent = {Vec3::UnitX(), Vec3(0, 0, -1)};  // slip axis first, as the world sets it
  computeMasses(cs[0], SolverBody{}, bodies[0]);
  BiasMode mode;
  mode.soft = false;
  mode.invH = 240;
  solve(cs, bodies, mode);
  const ConstraintPoint& p = cs[0].points[0];
  EXPECT_NEAR(p.normalImpulse, 1, 8 * kRealEps);
  EXPECT_NEAR(std::hypot(p.tangentImpulse[0], p.tangentImpulse[1]), mu * p.normalImpulse,
              8 * kRealEps);
  EXPECT_LT(p.tangentImpulse[0], 0);  // opposes +x slip
  EXPECT_NEAR(p.tangentImpulse[1], 0, 8 * kRealEps);

  std::vector<SolverBody> slow{body(Vec3(Real(0.01), -1, 0))};
  std::vector<ContactConstraint> stick{pointContact(0, mu)};
  computeMasses(stick[0], SolverBody{}, slow[0]);
  for (int i = 0; i < 50; ++i) solve(stick, slow, mode);
  // The contact point's tangential velocity is gone (the body may spin about the point).
  const Vec3 vPoint = slow[0].v + slow[0].w.cross(stick[0].points[0].rB);
  EXPECT_NEAR(vPoint.x(), 0, 1e-4);
}

// Newton's law after the iterations: an approach at 4 m/s with e = 0.5 leaves at 2 m/s; an
// approach below the threshold does not bounce.
TEST(ContactSolver, RestitutionReversesTheApproachSpeed) {
  for (Real approach : {Real(4), Real(0.5)}) {
    std::vector<SolverBody> bodies{body(Vec3(0, -approach, 0))};
    std::vector<ContactConstraint> cs{pointContact(0, 0)};
    cs[0].restitution = Real(0.5);
    cs[0].points[0].relativeVelocity = -approach;
    cs[0].points[0].launch = Real(0.5) * approach;  // as prepared: e times the approach speed
    computeMasses(cs[0], SolverBody{}, bodies[0]);
    BiasMode mode;
    mode.soft = false;
    mode.invH = 240;
    solve(cs, bodies, mode);
    applyRestitution(cs, bodies, 1);
    EXPECT_NEAR(bodies[0].v.y(), approach > 1 ? Real(0.5) * approach : 0, 8 * kRealEps * approach);
  }
}

namespace {
// A random contact graph: `count` constraints between `bodyCount` bodies (some static, some
// kinematic with zero inverse mass), with 1 to 4 points at random anchors, some with
// restitution, rolling or spinning friction, random accumulated impulses, and bodies that have
// moved since the step's start.
void randomGraph(std::mt19937_64& rng, int bodyCount, int count, std::vector<SolverBody>& bodies,
                 std::vector<ContactConstraint>& cs) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> pick(-1, bodyCount - 1);
  std::uniform_int_distribution<int> points(1, 4);
  auto r = [&] { return Real(u(rng)); };
  auto vec = [&] { return Vec3(r(), r(), r()); };
  bodies.clear();
  for (int i = 0; i < bodyCount; ++i) {
    SolverBody b = body(vec());
    b.w = vec();
    b.invInertia = Vec3(6 + r(), 6 + r(), 6 + r()).asDiagonal();
    b.dp = Real(0.01) * vec();
    b.dq = Quat(1, Real(0.01) * r(), Real(0.01) * r(), Real(0.01) * r()).normalized();
    b.dR = b.dq.toRotationMatrix();
    if (i % 10 == 9) {  // kinematic: moves, but takes no impulse
      b.invMass = 0;
      b.invInertia.setZero();
    }
    bodies.push_back(b);
  }
  const Softness soft = makeSoft(30, 10, Real(1.0 / 240.0));
  cs.clear();
  while (int(cs.size()) < count) {
    ContactConstraint c;
    c.bodyA = pick(rng);
    c.bodyB = pick(rng);
    auto moving = [&](int i) { return i >= 0 && bodies[std::size_t(i)].invMass > 0; };
    if (c.bodyA == c.bodyB || (!moving(c.bodyA) && !moving(c.bodyB))) continue;
    c.normal = vec().normalized();
    c.tangent = tangentBasis(c.normal);
    c.pointCount = points(rng);
    for (int k = 0; k < c.pointCount; ++k) {
      ConstraintPoint& p = c.points[std::size_t(k)];
      p.rA = vec() * Real(0.5);
      p.rB = vec() * Real(0.5);
      p.adjustedSeparation = Real(0.01 * u(rng)) - (p.rB - p.rA).dot(c.normal);
      p.normalImpulse = Real(0.1) * std::abs(r());
      p.tangentImpulse = {Real(0.02) * r(), Real(0.02) * r()};
      p.relativeVelocity = -2 * std::abs(r());
    }
    c.friction = Real(0.5);
    c.restitution = cs.size() % 3 == 0 ? Real(0.3) : Real(0);
    for (int k = 0; k < c.pointCount; ++k)
      c.points[std::size_t(k)].launch = c.restitution * -c.points[std::size_t(k)].relativeVelocity;
    if (cs.size() % 5 == 0) {
      c.rolling = Real(0.02);
      c.spinning = Real(0.01);
      c.rollingImpulse = {Real(0.001) * r(), Real(0.001) * r()};
      c.spinningImpulse = Real(0.001) * r();
    }
    c.softness = soft;
    const SolverBody none{};
    computeMasses(c, c.bodyA >= 0 ? bodies[std::size_t(c.bodyA)] : none,
                  c.bodyB >= 0 ? bodies[std::size_t(c.bodyB)] : none);
    cs.push_back(c);
  }
}
}  // namespace

// Graph colouring: every constraint in exactly one group, and within a colour no two
// constraints share a body that takes impulses (static and kinematic bodies may be shared).
TEST(ContactSolver, ColoringSeparatesMovingBodies) {
  std::mt19937_64 rng(11);
  for (int bodyCount : {2, 10, 200}) {
    std::vector<SolverBody> bodies;
    std::vector<ContactConstraint> cs;
    randomGraph(rng, bodyCount, 600, bodies, cs);
    ConstraintColoring col;
    colorConstraints(cs, bodies, col);
    ASSERT_EQ(col.order.size(), cs.size());
    std::vector<int> seen(cs.size(), 0);
    for (std::uint32_t k : col.order) ++seen[k];
    for (int n : seen) EXPECT_EQ(n, 1);
    const std::size_t groups = col.offsets.size() - 1;
    EXPECT_LE(groups, std::size_t(kMaxColors + 1));
    for (std::size_t g = 0; g < groups; ++g) {
      if (g + 1 == groups && col.overflow) continue;  // the overflow group may share bodies
      std::vector<int> users(bodies.size(), 0);
      for (std::uint32_t k = col.offsets[g]; k < col.offsets[g + 1]; ++k)
        for (int i : {cs[col.order[k]].bodyA, cs[col.order[k]].bodyB})
          if (i >= 0 && bodies[std::size_t(i)].invMass > 0) ++users[std::size_t(i)];
      for (int n : users) EXPECT_LE(n, 1) << "group " << g;
    }
    // 2 bodies: all 600 constraints share them, so 24 colours of one and the overflow.
    if (bodyCount == 2) {
      EXPECT_TRUE(col.overflow);
    }
    if (bodyCount == 200) {
      EXPECT_FALSE(col.overflow);
    }
  }
}

namespace {
// Bundled passes as a step makes them: warm start, soft iterations, a position update, a
// relax pass, restitution. Returns the bodies; the impulses are stored into `cs`.
std::vector<SolverBody> bundledPasses(std::vector<ContactConstraint>& cs,
                                      std::vector<SolverBody> bodies,
                                      const ConstraintColoring& col, tbb::task_arena* arena) {
  ContactBundles bundles;
  bundles.build(cs, bodies, col);
  BiasMode mode;
  mode.invH = 240;
  BiasMode relax = mode;
  relax.useBias = false;
  bundles.beginApproach(bodies);
  bundles.updateApproach(bodies, Real(1) / 240, Real(1) / 240);
  bundles.warmStart(bodies, arena);
  for (int it = 0; it < 3; ++it) bundles.solve(bodies, mode, arena);
  for (SolverBody& b : bodies) b.dp += b.v / 240;
  bundles.updateMotion(bodies);
  bundles.solve(bodies, relax, arena);
  bundles.applyRestitution(bodies, Real(0.1), arena);
  bundles.store(cs);
  return bodies;
}

void expectSameBits(const std::vector<SolverBody>& a, const std::vector<SolverBody>& b,
                    const std::vector<ContactConstraint>& ca,
                    const std::vector<ContactConstraint>& cb) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].v, b[i].v) << "body " << i;
    EXPECT_EQ(a[i].w, b[i].w) << "body " << i;
  }
  for (std::size_t k = 0; k < ca.size(); ++k) {
    for (int i = 0; i < ca[k].pointCount; ++i) {
      const ConstraintPoint &p = ca[k].points[std::size_t(i)], &q = cb[k].points[std::size_t(i)];
      EXPECT_EQ(p.normalImpulse, q.normalImpulse) << "constraint " << k;
      EXPECT_EQ(p.tangentImpulse, q.tangentImpulse) << "constraint " << k;
      EXPECT_EQ(p.maxNormalImpulse, q.maxNormalImpulse) << "constraint " << k;
      EXPECT_EQ(p.relativeVelocity, q.relativeVelocity) << "constraint " << k;
    }
    EXPECT_EQ(ca[k].rollingImpulse, cb[k].rollingImpulse) << "constraint " << k;
    EXPECT_EQ(ca[k].spinningImpulse, cb[k].spinningImpulse) << "constraint " << k;
  }
}
// A random graph (randomGraph) and its colouring.
struct ColoredGraph {
  std::vector<SolverBody> start;
  std::vector<ContactConstraint> cs;
  ConstraintColoring col;
};
ColoredGraph coloredGraph(std::uint64_t seed, int bodyCount, int count) {
  std::mt19937_64 rng(seed);
  ColoredGraph g;
  randomGraph(rng, bodyCount, count, g.start, g.cs);
  colorConstraints(g.cs, g.start, g.col);
  return g;
}
}  // namespace

// The coloured passes give the same bytes on 1 and 4 threads (and without an arena): the
// result cannot depend on how a colour is split into tasks.
TEST(ContactSolver, ColoredPassesAreIndependentOfThreads) {
  const auto [start, cs0, col] = coloredGraph(12, 2000, 6000);
  tbb::task_arena one(1), four(4);
  std::vector<ContactConstraint> c0 = cs0, c1 = cs0, c4 = cs0;
  const std::vector<SolverBody> a = bundledPasses(c0, start, col, nullptr);
  expectSameBits(a, bundledPasses(c1, start, col, &one), c0, c1);
  expectSameBits(a, bundledPasses(c4, start, col, &four), c0, c4);
  // And the solve did something: some body's velocity changed.
  bool changed = false;
  for (std::size_t i = 0; i < a.size(); ++i) changed = changed || a[i].v != start[i].v;
  EXPECT_TRUE(changed);
}

// A lane computes what its constraint computes alone: the coloured bundles of kLanes give the
// bits of the same passes run one constraint at a time in colour order (mixed point counts,
// static and kinematic bodies, restitution, rolling and spinning friction in some lanes). A
// lane reading or writing another's body, or a padding lane pushing, would change them.
TEST(ContactSolver, BundledLanesEqualConstraintsSolvedOneByOne) {
  const auto [start, cs0, col] = coloredGraph(13, 300, 700);
  ASSERT_FALSE(col.overflow);

  std::vector<ContactConstraint> bundled = cs0;
  const std::vector<SolverBody> a = bundledPasses(bundled, start, col, nullptr);

  // The same in sequence: cs in colour order, each pass one constraint at a time.
  std::vector<ContactConstraint> seq;
  for (std::uint32_t k : col.order) seq.push_back(cs0[k]);
  std::vector<SolverBody> b = start;
  BiasMode mode;
  mode.invH = 240;
  BiasMode relax = mode;
  relax.useBias = false;
  beginApproach(seq, b);
  updateApproach(seq, b, Real(1) / 240, Real(1) / 240);
  warmStart(seq, b);
  for (int it = 0; it < 3; ++it) solve(seq, b, mode);
  for (SolverBody& body : b) body.dp += body.v / 240;
  solve(seq, b, relax);
  applyRestitution(seq, b, Real(0.1));

  std::vector<ContactConstraint> byIndex(cs0.size());
  for (std::size_t i = 0; i < col.order.size(); ++i) byIndex[col.order[i]] = seq[i];
  expectSameBits(a, b, bundled, byIndex);
  // And the passes did something in every kind of row.
  bool pushed = false, bounced = false, rolled = false;
  for (const ContactConstraint& c : bundled) {
    rolled = rolled || c.rollingImpulse[0] != 0;
    for (int i = 0; i < c.pointCount; ++i) {
      pushed = pushed || c.points[std::size_t(i)].maxNormalImpulse > 0;
      bounced = bounced || (c.restitution > 0 && c.points[std::size_t(i)].normalImpulse > 0);
    }
  }
  EXPECT_TRUE(pushed && bounced && rolled);
}

// The AVX2 and AVX-512 kernels give the SSE2 kernels' bits (lane-wise IEEE arithmetic
// without fused multiply-adds; AVX-512 runs a bundle's sixteen lanes at once and solves two
// bundles of a colour side by side, the others run a bundle in two slices; the float AVX2 and
// AVX-512 kernels move the velocities by transposes). A set the processor lacks falls back to
// the widest it has.
TEST(ContactSolver, WideKernelsGiveTheSse2KernelsBits) {
  const auto [start, cs0, col] = coloredGraph(14, 300, 700);
  const SimdLevel best = bestContactSimd();
  std::vector<ContactConstraint> reference = cs0;
  setContactSimd(SimdLevel::Sse2);
  EXPECT_EQ(contactSimd(), SimdLevel::Sse2);
  const std::vector<SolverBody> a = bundledPasses(reference, start, col, nullptr);
  for (SimdLevel level : {SimdLevel::Avx2, SimdLevel::Avx512}) {
    SCOPED_TRACE(simdLevelName(level));
    setContactSimd(level);
    EXPECT_EQ(contactSimd(), std::min(level, best));
    std::vector<ContactConstraint> c = cs0;
    const std::vector<SolverBody> b = bundledPasses(c, start, col, nullptr);
    expectSameBits(a, b, reference, c);
  }
  setContactSimd(best);
}
