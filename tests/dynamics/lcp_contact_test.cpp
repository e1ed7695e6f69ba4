// The direct LCP contact solvers (lcp_dantzig, lcp_lemke) against converged PGS and against
// statics: on small stacks at rest every contact carries the weight above it, and the three
// solvers (which solve the same rows) agree on it.
#include "dynamics/lcp_contact.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include "../step_constants.h"
#include "inertia/dynamics/rigid_body_system.h"

using namespace inertia;
using inertia::test::kDt;
using inertia::test::kG;
using inertia::test::kSubsteps;

namespace {

DynamicsSettings settingsFor(SolverType type) {
  DynamicsSettings s;
  s.substeps = kSubsteps;
  s.sleeping = false;
  s.solver.type = type;
  s.solver.iterations = type == SolverType::Pgs ? 500 : 8;  // pgs run to convergence
  return s;
}

struct Stack {
  RigidBodySystem rbs;
  std::vector<BodyId> boxes;
  Real totalMass = 0;
  Vec3 up = Vec3::UnitY();
};

// `count` unit cubes (1000 kg each) stacked in resting contact on a plane tilted by `theta`
// about z, friction mu on every shape.
Stack makeStack(int count, Real theta, Real mu) {
  Stack s;
  const Quat tilt(Eigen::AngleAxis<Real>(theta, Vec3::UnitZ()));
  s.up = tilt * Vec3::UnitY();
  const Material m{.friction = mu};
  const BodyId ground = s.rbs.createBody({.type = BodyType::Static});
  s.rbs.addShape(ground, Plane{s.up, 0}, m);
  for (int i = 0; i < count; ++i) {
    const BodyId b =
        s.rbs.createBody({.position = s.up * (Real(0.5) + Real(i)), .orientation = tilt});
    s.rbs.addShape(b, Box{Vec3::Constant(Real(0.5))}, m);
    s.boxes.push_back(b);
    s.totalMass += s.rbs.mass(b);
  }
  return s;
}

// Per touching manifold (keyed by its bodies): the total normal impulse of the last substep
// (N s) and its centre of pressure (m).
struct Load {
  Real impulse = 0;
  Vec3 centre = Vec3::Zero();
};
using Loads = std::map<std::pair<std::uint32_t, std::uint32_t>, Load>;

Loads loads(const RigidBodySystem& rbs) {
  Loads out;
  for (const ContactInfo& c : rbs.contacts()) {
    Load l;
    for (int i = 0; i < c.manifold.pointCount; ++i) {
      const ContactPoint& p = c.manifold.points[static_cast<std::size_t>(i)];
      const Real lambda = c.normalImpulses[static_cast<std::size_t>(i)];
      l.impulse += lambda;
      l.centre += lambda * Real(0.5) * (p.pointA + p.pointB);
    }
    if (l.impulse <= 0) continue;
    l.centre /= l.impulse;
    out[{c.bodyA.index, c.bodyB.index}] = l;
  }
  return out;
}

Loads settle(Stack& s, SolverType type, int steps) {
  const DynamicsSettings settings = settingsFor(type);
  for (int i = 0; i < steps; ++i) s.rbs.step(kDt, settings, nullptr);
  return loads(s.rbs);
}

// Settled: every box's speed (m/s, and rad/s times its half extent) is below this.
constexpr Real kRestSpeed = Real(1e-6);

// The impulse tolerance. At rest a solver's last-substep impulse on a contact equals the
// weight it carries times h = dt / substeps, plus the momentum the bodies above still change
// in that substep, at most m 2 kRestSpeed (the speed before and after are both below it):
// 5e-5 of m g h (g h = 0.041 m/s). On top, the rounding of the stored float impulses and of
// the four-point sums (16 eps relative).
Real impulseTolerance(Real carriedMass) {
  const Real mgh = carriedMass * kG * kDt / kSubsteps;
  return carriedMass * 2 * kRestSpeed + 16 * std::numeric_limits<Real>::epsilon() * mgh;
}

Real maxSpeed(const Stack& s) {
  Real v = 0;
  for (BodyId b : s.boxes)
    v = std::max({v, s.rbs.linearVelocity(b).norm(), Real(0.5) * s.rbs.angularVelocity(b).norm()});
  return v;
}

void expectAgree(const char* scene, int count, Real theta, Real mu) {
  const Real h = kDt / kSubsteps;
  std::map<SolverType, Loads> results;
  for (SolverType type : {SolverType::Pgs, SolverType::LcpDantzig, SolverType::LcpLemke}) {
    Stack s = makeStack(count, theta, mu);
    results[type] = settle(s, type, 60);
    EXPECT_LT(maxSpeed(s), kRestSpeed) << scene << " " << solverName(type);
    // Statics: the manifold under box i carries boxes i..count-1, normal component cos(theta).
    ASSERT_EQ(results[type].size(), static_cast<std::size_t>(count))
        << scene << " " << solverName(type);
    for (const auto& [key, load] : results[type]) {
      // The upper of the manifold's two bodies (the ground is not a box).
      int below = -1;
      for (int i = 0; i < count; ++i) {
        const std::uint32_t index = s.boxes[static_cast<std::size_t>(i)].index;
        if (index == key.first || index == key.second) below = i;
      }
      ASSERT_GE(below, 0);
      const Real carried = s.totalMass * Real(count - below) / Real(count);
      const Real expected = carried * kG * std::cos(theta) * h;
      EXPECT_NEAR(load.impulse, expected, impulseTolerance(carried))
          << scene << " " << solverName(type) << " manifold under box " << below;
    }
  }
  // The LCP solvers against converged PGS, manifold by manifold: the same total and the same
  // centre of pressure. The centre moves with the moment the bodies above still take in a
  // substep, I 2 kRestSpeed / 0.5 m = 167 kg m^2 4e-6 rad/s over at least 40.9 N s: 1.6e-5 m,
  // plus float rounding of the positions (2 m times 1e-7).
  const Loads& pgs = results[SolverType::Pgs];
  for (SolverType type : {SolverType::LcpDantzig, SolverType::LcpLemke}) {
    for (const auto& [key, load] : results[type]) {
      ASSERT_TRUE(pgs.count(key));
      const Load& ref = pgs.at(key);
      EXPECT_NEAR(load.impulse, ref.impulse, impulseTolerance(ref.impulse / (kG * h)))
          << scene << " " << solverName(type);
      EXPECT_LT((load.centre - ref.centre).norm(), Real(2e-5)) << scene << " " << solverName(type);
    }
  }
  // Not compared: the split of a manifold's load between its points. Statics fixes only the
  // total and the centre of pressure; the LCP's regulariser (A + 1e-8 I on the scaled rows) picks
  // one split, so an input change of float rounding (1e-7) can move the split by O(1), and the
  // two solvers' runs differ by more. lcp_test checks that Dantzig and Lemke find the same
  // solution of the same well-posed problem.
}

}  // namespace

TEST(LcpContact, BoxOnGroundAgreesWithConvergedPgs) { expectAgree("box", 1, 0, Real(0.6)); }

TEST(LcpContact, TowerOfThreeAgreesWithConvergedPgs) { expectAgree("tower", 3, 0, Real(0.6)); }

// A box on a 30 degree slope held by friction: mu = 1 exceeds tan 30 = 0.577 and also
// sqrt(2) tan 30 = 0.816, the most the Lemke pyramid (|t1| + |t2| <= mu n) may need when the
// slope direction lies between its axes.
TEST(LcpContact, BoxHeldOnSlopeAgreesWithConvergedPgs) {
  const Real theta = Real(std::numbers::pi / 6);
  expectAgree("slope", 1, theta, 1);
  for (SolverType type : {SolverType::LcpDantzig, SolverType::LcpLemke}) {
    Stack s = makeStack(1, theta, 1);
    const Vec3 start = s.rbs.transform(s.boxes[0]).p;
    settle(s, type, 120);
    // Held: a box sliding at the least deceleration this test could miss would move metres in
    // 2 s; at rest the creep is below kRestSpeed * 2 s.
    EXPECT_LT((s.rbs.transform(s.boxes[0]).p - start).norm(), Real(1e-4)) << solverName(type);
  }
}

// Restitution is applied after the substeps as in pgs: a ball dropped from 1 m with e = 0.5
// rises to e^2 = 0.25 m (2%: the impact speed is the one of the substep before contact, off
// by up to g h of 4.4 m/s, as in contact_dynamics_test's bounce test).
TEST(LcpContact, BounceRisesToRestitutionSquared) {
  for (SolverType type : {SolverType::LcpDantzig, SolverType::LcpLemke}) {
    RigidBodySystem rbs;
    const BodyId ground = rbs.createBody({.type = BodyType::Static});
    rbs.addShape(ground, Plane{Vec3::UnitY(), 0});
    const Real r = Real(0.1), e = Real(0.5);
    const BodyId ball = rbs.createBody({.position = Vec3(0, 1 + r, 0)});
    rbs.addShape(ball, Sphere{r}, Material{.restitution = e});
    DynamicsSettings settings = settingsFor(type);
    settings.integrator = ode::Method::VelocityVerlet;
    bool bounced = false;
    Real apex = 0;
    for (int i = 0; i < 240; ++i) {
      rbs.step(kDt, settings, nullptr);
      const Real vy = rbs.linearVelocity(ball).y();
      if (vy > 0) bounced = true;
      if (bounced) apex = std::max(apex, rbs.transform(ball).p.y() - r);
      if (bounced && vy < 0) break;
    }
    EXPECT_NEAR(apex, e * e, Real(0.02) * e * e) << solverName(type);
  }
}

// Both LCP solvers keep a 3-box tower standing for 3 s: the top box moves < 1 cm.
TEST(LcpContact, TowerOfThreeStandsThreeSeconds) {
  for (SolverType type : {SolverType::LcpDantzig, SolverType::LcpLemke}) {
    Stack s = makeStack(3, 0, Real(0.6));
    const Vec3 top = s.rbs.transform(s.boxes.back()).p;
    settle(s, type, 180);
    EXPECT_LT((s.rbs.transform(s.boxes.back()).p - top).norm(), Real(0.01)) << solverName(type);
    EXPECT_GT((s.rbs.transform(s.boxes.back()).q * Vec3::UnitY()).y(), Real(0.9999));
  }
}

// ---- solveContactsLcp on hand-made rows ---------------------------------------------------

namespace {

using detail::BiasMode;
using detail::ContactConstraint;
using detail::LcpContactStats;
using detail::LcpMethod;
using detail::SolverBody;

// A unit cube of 1 kg (inertia 1/6 kg m^2) moving at v.
SolverBody cube(const Vec3& v) {
  SolverBody b;
  b.v = v;
  b.invMass = 1;
  b.invInertia = Mat3::Identity() * 6;
  return b;
}

// Points on the ground plane y = 0 under body `body` (centre at y = 0.5), normal +y, the
// first tangent +x (the slip axis, as the world sets it when sliding).
ContactConstraint groundContact(int body, const std::vector<Vec3>& points, Real mu,
                                const SolverBody& b) {
  ContactConstraint c;
  c.bodyA = -1;
  c.bodyB = body;
  c.normal = Vec3::UnitY();
  c.tangent = {Vec3::UnitX(), Vec3(0, 0, -1)};
  c.friction = mu;
  c.pointCount = static_cast<int>(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    detail::ConstraintPoint& p = c.points[i];
    p.rA = points[i];
    p.rB = points[i] - Vec3(0, Real(0.5), 0);
    p.adjustedSeparation = -(p.rB - p.rA).dot(c.normal);  // touching: separation 0
  }
  detail::computeMasses(c, SolverBody{}, b);
  return c;
}

BiasMode rigidMode() {
  BiasMode m;
  m.soft = false;
  m.invH = 240;
  return m;
}

std::vector<Vec3> corners() {
  return {Vec3(Real(0.5), 0, Real(0.5)), Vec3(Real(-0.5), 0, Real(0.5)),
          Vec3(Real(-0.5), 0, Real(-0.5)), Vec3(Real(0.5), 0, Real(-0.5))};
}

}  // namespace

// A cube landing flat at 1 m/s while sliding at 2 m/s (mu = 0.5): friction saturates along
// the slip and tips the cube forward. Dantzig, Lemke and PGS run to convergence (2000
// iterations) agree on the velocities after the impulse and on the total normal impulse: the
// slip lies along the first tangent, where disc, square and diamond cones coincide. PGS's
// error after 2000 iterations on this 12-row system is below 1e-5 (its change over the last
// 1000 iterations, measured); the LCP solvers are exact to float rounding.
TEST(LcpContact, SlidingCubeMatchesConvergedPgs) {
  const Vec3 v0(2, -1, 0);
  std::vector<SolverBody> pgsBodies{cube(v0)};
  std::vector<ContactConstraint> pgs{groundContact(0, corners(), Real(0.5), pgsBodies[0])};
  for (int i = 0; i < 2000; ++i) detail::solve(pgs, pgsBodies, rigidMode());
  Real pgsNormal = 0;
  for (const auto& p : pgs[0].points) pgsNormal += p.normalImpulse;
  EXPECT_NEAR(pgsBodies[0].v.y(), 0, 1e-5);      // the landing is stopped
  EXPECT_LT(pgsBodies[0].v.x(), 2 - Real(0.4));  // friction slowed the slide

  for (LcpMethod method : {LcpMethod::Dantzig, LcpMethod::Lemke}) {
    std::vector<SolverBody> bodies{cube(v0)};
    std::vector<ContactConstraint> cs{groundContact(0, corners(), Real(0.5), bodies[0])};
    LcpContactStats stats;
    detail::solveContactsLcp(cs, bodies, rigidMode(), method, 8, &stats);
    EXPECT_EQ(stats.direct, 1);
    EXPECT_EQ(stats.fallbacks, 0);
    EXPECT_LT((bodies[0].v - pgsBodies[0].v).norm(), Real(1e-5)) << int(method);
    EXPECT_LT((bodies[0].w - pgsBodies[0].w).norm(), Real(1e-5)) << int(method);
    Real normal = 0;
    for (const auto& p : cs[0].points) {
      normal += p.normalImpulse;
      EXPECT_GE(p.normalImpulse, 0);
      // Coulomb at every point: the friction impulse is within its cone (square or diamond).
      EXPECT_LE(std::abs(p.tangentImpulse[0]) + std::abs(p.tangentImpulse[1]),
                Real(0.5) * p.normalImpulse * (1 + Real(1e-5)) + Real(1e-6));
    }
    EXPECT_NEAR(normal, pgsNormal, Real(1e-5));
  }
}

// Islands are solved one by one; an island beyond kMaxLcpUnknowns (Dantzig: 3 per point;
// Lemke: 6 per point) goes to the pgs fallback, and the result still stops the approach.
TEST(LcpContact, LargeIslandsFallBackToPgs) {
  auto ring = [](int n) {
    std::vector<Vec3> pts;
    for (int i = 0; i < n; ++i) {
      const Real a = Real(2 * std::numbers::pi * i / n);
      pts.push_back(Vec3(Real(0.5) * std::cos(a), 0, Real(0.5) * std::sin(a)));
    }
    return pts;
  };
  struct Case {
    LcpMethod method;
    int pointsPerBody;
    bool direct;
  };
  // Dantzig: 64 points = 192 unknowns fits (3 per point), 68 does not.
  // Lemke: 32 points = 192 fits (6 per point), 36 does not.
  for (const Case& k : {Case{LcpMethod::Dantzig, 64, true}, Case{LcpMethod::Dantzig, 68, false},
                        Case{LcpMethod::Lemke, 32, true}, Case{LcpMethod::Lemke, 36, false}}) {
    std::vector<SolverBody> bodies{cube(Vec3(0, -1, 0)), cube(Vec3(0, -1, 0))};
    std::vector<ContactConstraint> cs;
    // Body 0 on k.pointsPerBody points (in constraints of 4), body 1 on the four corners.
    const std::vector<Vec3> pts = ring(k.pointsPerBody);
    for (std::size_t i = 0; i < pts.size(); i += 4)
      cs.push_back(
          groundContact(0, {pts[i], pts[i + 1], pts[i + 2], pts[i + 3]}, Real(0.5), bodies[0]));
    cs.push_back(groundContact(1, corners(), Real(0.5), bodies[1]));
    LcpContactStats stats;
    detail::solveContactsLcp(cs, bodies, rigidMode(), k.method, 50, &stats);
    EXPECT_EQ(stats.islands, 2);
    EXPECT_EQ(stats.direct, k.direct ? 2 : 1) << int(k.method) << " " << k.pointsPerBody;
    EXPECT_EQ(stats.fallbacks, k.direct ? 0 : 1);
    for (const SolverBody& b : bodies) EXPECT_NEAR(b.v.y(), 0, Real(1e-3));
  }
}
