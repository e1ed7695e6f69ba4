// Joints against their oracles: a physical pendulum's period (the complete elliptic integral),
// a chain's joint error at rest, limits, motors, springs, reaction forces and breaking, an
// inclined slider's acceleration, and the same bits at one and two threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string_view>
#include <utility>
#include <vector>

#include "../step_constants.h"
#include "inertia/world/world.h"

using namespace inertia;
using inertia::test::kDt;
using inertia::test::kG;

namespace {

constexpr Real kPi = Real(std::numbers::pi);

WorldSettings quietWorld() {
  WorldSettings s;
  s.sleeping = false;
  s.threads = 1;
  return s;
}

// A sphere of radius r and density 1000 whose centre hangs at distance L from a pivot at the
// origin, released at angle theta0 from the vertical in the x-y plane, on a hinge (axis z) or a
// ball joint.
struct SpherePendulum {
  World world{quietWorld()};
  BodyId bob;
  JointId joint;
  Real L = 1, r = Real(0.1);

  enum class Kind { Hinge, Ball, SixDofHinge, SixDofBall };

  SpherePendulum(Real theta0, Kind kind, SolverType solver = SolverType::SoftStep)
      : world([&] {
          WorldSettings s = quietWorld();
          s.solver.type = solver;
          return s;
        }()) {
    const Vec3 at(L * std::sin(theta0), -L * std::cos(theta0), 0);
    bob = world.createBody({.position = at});
    world.addShape(bob, Sphere{r});
    // The six-DOF joint's frames: x along the hinge axis z, at the pivot.
    const Quat xToZ = Quat::FromTwoVectors(Vec3::UnitX(), Vec3::UnitZ());
    SixDofJointSettings six{.bodyB = bob, .frameA = {Vec3::Zero(), xToZ}, .frameB = {-at, xToZ}};
    switch (kind) {
      case Kind::Hinge:
        joint = world.createJoint(HingeJointSettings{.bodyB = bob, .anchorB = -at});
        break;
      case Kind::Ball:
        joint = world.createJoint(BallJointSettings{.bodyB = bob, .anchorB = -at});
        break;
      case Kind::SixDofHinge:
        six.axes[3].locked = false;
        joint = world.createJoint(six);
        break;
      case Kind::SixDofBall:
        six.axes[3].locked = six.axes[4].locked = six.axes[5].locked = false;
        joint = world.createJoint(six);
        break;
    }
  }
  Real angle() const {
    const Vec3 p = world.transform(bob).p;
    return std::atan2(p.x(), -p.y());
  }
  // The period (s) from the first and last of `crossings` downward zero crossings of the angle
  // (linear interpolation between steps).
  double period(int crossings) {
    std::vector<double> times;
    Real previous = angle();
    while (int(times.size()) < crossings && world.time() < 100) {
      world.step(kDt);
      const Real now = angle();
      if (previous > 0 && now <= 0)
        times.push_back(world.time() - kDt + kDt * double(previous / (previous - now)));
      previous = now;
    }
    return (times.back() - times.front()) / double(times.size() - 1);
  }
  // T = 4 sqrt(I_pivot / (m g L)) K(sin(theta0 / 2)) for a physical pendulum.
  double exactPeriod(Real theta0) const {
    const double m = world.rigidBodies().mass(bob);
    const double iPivot = 0.4 * m * r * r + m * L * L;
    return 4 * std::sqrt(iPivot / (m * kG * L)) * std::comp_ellint_1(std::sin(theta0 / 2));
  }
};

// Period error budget: symplectic Euler's phase error at h = 1/240 s, (omega h)^2 / 24 ~ 1e-5,
// and the soft joint's compliance at 120 Hz against a 0.5 Hz swing, (0.5/120)^2 ~ 2e-5; the
// 1e-3 bound leaves room for the soft joint's damping of the amplitude over the ten periods
// (the large-amplitude period depends on the amplitude), which the 0.5% would hide.
TEST(JointPendulum, PeriodMatchesEllipticIntegralOnEveryJointThatAllowsTheSwing) {
  using Kind = SpherePendulum::Kind;
  for (Kind kind : {Kind::Hinge, Kind::Ball, Kind::SixDofHinge, Kind::SixDofBall}) {
    for (Real theta0 : {Real(0.1), Real(1.5)}) {
      SpherePendulum p(theta0, kind);
      const double measured = p.period(11);
      EXPECT_NEAR(measured / p.exactPeriod(theta0), 1, 0.001)
          << "joint " << int(kind) << " theta0 " << theta0;
    }
  }
}

// pgs and the LCP solvers solve the joints as rigid rows with Baumgarte's feedback (the LCP
// solvers in their own passes before each substep's contacts): the same period.
TEST(JointPendulum, PeriodIsTheSameWithRigidSolvers) {
  for (SolverType solver : {SolverType::Pgs, SolverType::LcpDantzig, SolverType::LcpLemke}) {
    SpherePendulum p(Real(1.5), SpherePendulum::Kind::Hinge, solver);
    EXPECT_NEAR(p.period(11) / p.exactPeriod(Real(1.5)), 1, 0.001) << solverName(solver);
  }
}

}  // namespace

namespace {

// A chain of `count` capsules (half-height 0.2 m, radius 0.05 m, along y) hanging straight
// down from the world on ball joints at their ends, the first one turning; the last one
// carries a sphere `bobMassRatio` times as heavy as a link (none when 0).
struct CapsuleChain {
  World world;
  std::vector<BodyId> links;
  std::vector<JointId> joints;
  BodyId bob;

  CapsuleChain(int count, Real bobMassRatio, int threads = 1)
      : world([&] {
          WorldSettings s = quietWorld();
          s.threads = threads;
          return s;
        }()) {
    const Real half = Real(0.2), radius = Real(0.05);
    BodyId previous;
    for (int i = 0; i < count; ++i) {
      const Vec3 at(0, -(2 * half + 2 * radius) * (Real(i) + Real(0.5)), 0);
      const BodyId link =
          world.createBody({.position = at, .angularVelocity = Vec3(0, 0, i == 0 ? Real(1) : 0)});
      world.addShape(link, Capsule{half, radius});
      const Vec3 top(0, half + radius, 0);
      joints.push_back(world.createJoint(
          BallJointSettings{.bodyA = previous,
                            .bodyB = link,
                            .anchorA = previous.isNull() ? Vec3::Zero() : Vec3(-top),
                            .anchorB = top}));
      links.push_back(link);
      previous = link;
    }
    if (bobMassRatio > 0) {
      const Real bobRadius = Real(0.25);
      const Vec3 end = world.transform(previous).p - Vec3(0, Real(0.25), 0);
      bob = world.createBody({.position = end - Vec3(0, bobRadius, 0),
                              .mass = bobMassRatio * world.rigidBodies().mass(previous)});
      world.addShape(bob, Sphere{bobRadius});
      joints.push_back(world.createJoint(BallJointSettings{.bodyA = previous,
                                                           .bodyB = bob,
                                                           .anchorA = Vec3(0, Real(-0.25), 0),
                                                           .anchorB = Vec3(0, bobRadius, 0)}));
    }
  }
  Real worstError() const {
    Real worst = 0;
    for (JointId j : joints) worst = std::max(worst, world.rigidBodies().jointError(j).position);
    return worst;
  }
};

}  // namespace

// A soft joint under a steady load F deflects as a spring of stiffness m_eff (2 pi f)^2, f
// twice the contact stiffness (120 Hz at 4 substeps of 1/60 s): the top joint of 20 links
// (F = 20 m g, m_eff = m / 2) by 40 g / (2 pi 120)^2 = 0.69 mm; the heavy bob's joints by up to
// 2 (100 + 20) g / (2 pi 120)^2 = 4.1 mm.
TEST(JointChain, TwentyLinksStayWithinAMillimetre) {
  CapsuleChain c(20, 0);
  for (int i = 0; i < 180; ++i) c.world.step(kDt);
  EXPECT_LT(c.worstError(), Real(0.001));
}

TEST(JointChain, HeavyBobOnALightChainStaysWithinACentimetre) {
  CapsuleChain c(20, 100);
  Real worst = 0;
  for (int i = 0; i < 180; ++i) {
    c.world.step(kDt);
    worst = std::max(worst, c.worstError());
  }
  EXPECT_LT(worst, Real(0.01));
}

TEST(JointChain, SameBitsAtOneAndTwoThreads) {
  CapsuleChain one(20, 10, 1), two(20, 10, 2);
  for (int i = 0; i < 120; ++i) {
    one.world.step(kDt);
    two.world.step(kDt);
  }
  for (std::size_t i = 0; i < one.links.size(); ++i) {
    const Transform a = one.world.transform(one.links[i]), b = two.world.transform(two.links[i]);
    EXPECT_EQ(0, std::memcmp(a.p.data(), b.p.data(), sizeof(Real) * 3)) << i;
    EXPECT_EQ(0, std::memcmp(a.q.coeffs().data(), b.q.coeffs().data(), sizeof(Real) * 4)) << i;
  }
}

namespace {

// A rod (box 1 m x 0.1 m x 0.1 m along x) on a hinge about z at its end x = 0, horizontal.
struct Arm {
  World world;
  BodyId rod;
  JointId hinge;
  Arm(HingeJointSettings s, Vec3 gravity = Vec3(0, -kG, 0))
      : world([&] {
          WorldSettings w = quietWorld();
          w.gravity = gravity;
          return w;
        }()) {
    rod = world.createBody({.position = Vec3(Real(0.5), 0, 0)});
    world.addShape(rod, Box{Vec3(Real(0.5), Real(0.05), Real(0.05))});
    s.bodyB = rod;
    s.anchorB = Vec3(Real(-0.5), 0, 0);
    hinge = world.createJoint(s);
  }
  Real angle() const { return world.rigidBodies().jointCoordinate(hinge); }
  Real rate() const { return world.angularVelocity(rod).z(); }
  Real inertiaAboutPivot() const {
    const Real m = world.rigidBodies().mass(rod);
    return m * (Real(1) + Real(0.01)) / 12 + m * Real(0.25);
  }
};

}  // namespace

// The limit is a speculative one-sided row that becomes soft when violated: under the arm's
// weight (m g L/2 about the pivot) it deflects by the soft row's static compliance, torque /
// (I_eff (2 pi 120 Hz)^2) = 0.0012 rad at most for this arm; 0.01 rad is the bound.
TEST(JointHinge, LowerLimitHoldsUnderLoad) {
  Arm arm({.limits = JointLimits{Real(-0.3), Real(0.3)}});
  for (int i = 0; i < 120; ++i) arm.world.step(kDt);
  EXPECT_NEAR(arm.angle(), Real(-0.3), Real(0.01));
  EXPECT_NEAR(arm.rate(), 0, Real(0.01));
}

// A motor whose torque suffices holds its speed exactly once reached (a velocity row); one
// whose torque does not lets the arm fall with I alpha = m g L/2 - T_max, so the reported
// torque about the axis is T_max while it slips.
TEST(JointHinge, MotorReachesItsSpeedOrStallsAtItsTorque) {
  Arm strong({.motor = JointMotor{.speed = 2, .maxForce = 1000}}, Vec3::Zero());
  for (int i = 0; i < 30; ++i) strong.world.step(kDt);
  EXPECT_NEAR(strong.rate(), 2, Real(0.02));

  Arm weak({.motor = JointMotor{.speed = 0, .maxForce = 10}});
  const Real m = weak.world.rigidBodies().mass(weak.rod);
  ASSERT_GT(m * kG * Real(0.5), 20);  // the weight's torque is more than twice the motor's
  for (int i = 0; i < 6; ++i) weak.world.step(kDt);
  const Real axial = weak.world.rigidBodies().jointTorque(weak.hinge).z();
  EXPECT_NEAR(axial, 10, Real(0.1));
}

// A wheel (a sphere on a hinge through its centre) on a spring to the world oscillates as a
// damped oscillator of the spring's frequency (the frequency of the row's effective mass, here
// the wheel's inertia about the axis) and damping ratio. The soft row is backward Euler, which
// adds a damping ratio of omega h / 2 each time it is solved after a position update: twice a
// substep (the solve and the relax pass), omega h = 0.052 at 2 Hz and h = 1/240 s. The damped
// period then follows from the measured decay, T = 2 pi / (omega sqrt(1 - zeta^2)), within
// backward Euler's phase error, O((omega h)^2) undamped and O(zeta omega h) damped.
TEST(JointHinge, SpringOscillatesAtItsFrequencyAndDampingRatio) {
  const double omega = 2 * std::numbers::pi * 2, h = 1.0 / 240;
  for (Real zeta : {Real(0), Real(0.2)}) {
    World world(quietWorld());
    const BodyId wheel = world.createBody({.angularVelocity = Vec3(0, 0, 1)});
    world.addShape(wheel, Sphere{Real(0.3)});
    const JointId j = world.createJoint(HingeJointSettings{
        .bodyB = wheel, .spring = JointSpring{.frequency = 2, .dampingRatio = zeta}});
    std::vector<double> crossings, peaks;  // the largest |angle| of each half period
    Real previous = 0, peak = 0;
    while (crossings.size() < 5) {
      world.step(kDt);
      const Real now = world.rigidBodies().jointCoordinate(j);
      peak = std::max(peak, std::abs(now));
      if ((previous < 0) != (now < 0)) {
        crossings.push_back(world.time() - kDt + kDt * double(previous / (previous - now)));
        peaks.push_back(double(std::exchange(peak, 0)));
      }
      previous = now;
    }
    const double period = 2 * (crossings.back() - crossings.front()) / double(crossings.size() - 1);
    // The peaks before the first and the fifth crossing are two periods apart.
    const double measuredZeta = std::log(peaks[0] / peaks[4]) / (2 * period) / omega;
    EXPECT_NEAR(measuredZeta, zeta, omega * h) << zeta;
    const double damped =
        2 * std::numbers::pi / (omega * std::sqrt(1 - measuredZeta * measuredZeta));
    EXPECT_NEAR(period / damped, 1, omega * h * (omega * h + zeta)) << zeta;
  }
}

// A sphere hanging at rest on a ball joint: the joint holds its weight, F = m g upwards on it
// (the soft row's rounding is far below 1%). Below that load it breaks in the first step,
// once; above it, it holds.
TEST(JointBall, ReactionIsTheWeightAndBreaksAboveItsThreshold) {
  for (Real threshold : {kUnbreakable, Real(0.5), Real(2)}) {
    World world(quietWorld());
    const BodyId bob = world.createBody({.position = Vec3(0, -1, 0)});
    world.addShape(bob, Sphere{Real(0.1)});
    const Real weight = world.rigidBodies().mass(bob) * kG;
    const JointId j = world.createJoint(BallJointSettings{
        .bodyB = bob, .anchorB = Vec3(0, 1, 0), .breakForce = threshold * weight});
    int events = 0;
    for (int i = 0; i < 60; ++i) {
      world.step(kDt);
      events += int(world.rigidBodies().jointEvents().size());
    }
    const bool breaks = threshold < 1;
    EXPECT_EQ(events, breaks ? 1 : 0) << threshold;
    EXPECT_EQ(world.rigidBodies().isJointBroken(j), breaks);
    if (!breaks) {
      EXPECT_NEAR(world.rigidBodies().jointForce(j).y(), weight, Real(0.01) * weight);
      EXPECT_NEAR(world.transform(bob).p.y(), -1, Real(1e-3));
    } else {
      EXPECT_LT(world.transform(bob).p.y(), -5);  // fell for a second
    }
  }
}

// A soft row is a spring of the joint's stiffness: a sphere hanging at rest from a ball joint
// at its centre (no lever: K = 1/m) sags by g / (2 pi jointHertz)^2. In the soft step's steady
// state the warm start carries the weight (m g h a substep) and the solve's soft impulse
// -s m (bias C) - t lambda vanishes at C = -t g h / (s bias) = -g / omega^2 exactly (Box2D
// v3's coefficients); the overdamped approach (damping ratio 2, slowest rate 0.27 omega) is
// complete within a second. So the sag's error is float's rounding of the coefficients (1e-7
// relative measured): 1e-5 is a hundred ulps. 120 Hz is the cap at 4 substeps of 1/60 s.
TEST(JointBall, SagAtRestIsTheSoftRowsSpringDeflection) {
  for (Real hertz : {Real(120), Real(60), Real(30)}) {
    WorldSettings settings = quietWorld();
    settings.solver.jointHertz = hertz;
    World world(settings);
    const BodyId bob = world.createBody({});
    world.addShape(bob, Sphere{Real(0.1)});
    world.createJoint(BallJointSettings{.bodyB = bob});
    for (int i = 0; i < 120; ++i) world.step(kDt);
    const double omega = 2 * std::numbers::pi * double(hertz);
    const double sag = double(kG) / (omega * omega);
    EXPECT_NEAR(-world.transform(bob).p.y(), sag, 1e-5 * sag) << hertz;
    EXPECT_NEAR(world.transform(bob).p.x(), 0, 1e-5 * sag);
  }
}

// A light bead welded to the world through a far anchor. At a lever 100 times its radius (K's
// condition, lever^2 / radius of gyration^2, about 2.5e4) the weld carries its weight, within
// the 1% of the ball joint's reaction test above. At 100 km (2 mg, condition 1e17, beyond
// float and double) the linear rows cannot be resolved from the angular ones: K's LDLT left
// rounding noise for a pivot, whose reciprocal drove the bead to NaN in its first step (the
// world fuzz target's finding). Such a direction now gets no impulse: the bead stays finite
// and within its speed caps. A 4e-18 kg bead (radius 1 um, density 1) 100 km away has K's
// anchor entries past float's range (inverse inertia 6e29 times the lever squared, 1e10):
// its K is made in double (fuzz input world-light-body-joint-block-nan, a hinge's).
TEST(JointWeld, FarAnchorOnALightBodyHoldsOrStaysFinite) {
  struct Case {
    Real radius, density, lever;
  };
  const Real bead = Real(3.6e-4);
  for (const Case c : {Case{bead, 1e4, 100 * bead}, Case{bead, 1e4, 1e5}, Case{1e-6, 1, 1e5}}) {
    World world(quietWorld());
    const BodyId body = world.createBody({});
    world.addShape(body, Sphere{c.radius}, Material{.density = c.density});
    const Real weight = world.rigidBodies().mass(body) * kG;
    const Vec3 far(0, 0, -c.lever);
    const JointId j =
        world.createJoint(WeldJointSettings{.bodyB = body, .anchorA = far, .anchorB = far});
    for (int i = 0; i < 60; ++i) {
      world.step(kDt);
      ASSERT_TRUE(world.transform(body).p.allFinite())
          << c.radius << " m at " << c.lever << " m, step " << i;
      ASSERT_LE(world.linearVelocity(body).norm(), Real(400) * (1 + 1e-6f)) << c.lever;
      ASSERT_LE(world.angularVelocity(body).norm(), Real(200) * (1 + 1e-6f)) << c.lever;
    }
    if (c.lever < 1) {
      EXPECT_NEAR(world.rigidBodies().jointForce(j).y(), weight, Real(0.01) * weight);
    }
  }
}

// A frictionless slider inclined at angle a: the body slides at g sin a along the axis
// (x = g sin a t^2 / 2) and nowhere else.
TEST(JointSlider, InclinedSliderAcceleratesAtGSinA) {
  World world(quietWorld());
  const Real a = Real(0.5);
  const Vec3 axis(std::cos(a), -std::sin(a), 0);
  const BodyId box = world.createBody({});
  world.addShape(box, Box{Vec3::Constant(Real(0.1))});
  const JointId j = world.createJoint(SliderJointSettings{.bodyB = box, .axisA = axis});
  for (int i = 0; i < 60; ++i) world.step(kDt);
  const Real t = Real(world.time());
  const Vec3 p = world.transform(box).p;
  EXPECT_NEAR(p.dot(axis) / (Real(0.5) * kG * std::sin(a) * t * t), 1, 0.01);
  EXPECT_LT((p - p.dot(axis) * axis).norm(), Real(1e-4));
  EXPECT_NEAR(world.rigidBodies().jointCoordinate(j), p.dot(axis), Real(1e-5));
  EXPECT_LT(world.angularVelocity(box).norm(), Real(1e-4));
}

// A double pendulum of two 1 m hinged links (point masses of spheres), released horizontal,
// without damping: chaotic, but its energy stays within symplectic Euler's bounded error,
// O(h omega) of the energy scale (omega = sqrt(g / L) ~ 3.1 rad/s, h omega = 0.013 at 4
// substeps), and the soft joints' dissipation, of the same order; halving h halves it.
TEST(JointPendulum, DoublePendulumKeepsItsEnergy) {
  for (int substeps : {4, 8}) {
    WorldSettings s = quietWorld();
    s.substeps = substeps;
    World world(s);
    const BodyId b1 = world.createBody({.position = Vec3(1, 0, 0)});
    world.addShape(b1, Sphere{Real(0.1)});
    const BodyId b2 = world.createBody({.position = Vec3(2, 0, 0)});
    world.addShape(b2, Sphere{Real(0.1)});
    world.createJoint(HingeJointSettings{.bodyB = b1, .anchorB = Vec3(-1, 0, 0)});
    world.createJoint(HingeJointSettings{.bodyA = b1, .bodyB = b2, .anchorB = Vec3(-1, 0, 0)});
    const RigidBodySystem& rb = world.rigidBodies();
    auto energy = [&] {
      return rb.kineticEnergy() + kG * (rb.mass(b1) * world.transform(b1).p.y() +
                                        rb.mass(b2) * world.transform(b2).p.y());
    };
    const Real e0 = energy(), scale = rb.mass(b1) * kG * 3;  // the potential energy's range
    const Real bound = Real(1.0 / 60) / Real(substeps) * std::sqrt(kG);
    for (int i = 0; i < 600; ++i) {
      world.step(kDt);
      ASSERT_LT(std::abs(energy() - e0) / scale, bound) << "substeps " << substeps << " step " << i;
    }
  }
}

// A six-DOF joint set up as a hinge or a ball joint follows the dedicated joint: the same
// pendulum's bob within 1 mm after two seconds (the two differ in their rows' formulation,
// each holding its anchors to ~2e-5 m, and the soft joints' damping).
TEST(JointSixDof, FollowsTheDedicatedJoints) {
  using Kind = SpherePendulum::Kind;
  for (auto [dedicated, six] :
       {std::pair{Kind::Hinge, Kind::SixDofHinge}, std::pair{Kind::Ball, Kind::SixDofBall}}) {
    SpherePendulum a(Real(1.2), dedicated), b(Real(1.2), six);
    for (int i = 0; i < 120; ++i) {
      a.world.step(kDt);
      b.world.step(kDt);
    }
    EXPECT_LT((a.world.transform(a.bob).p - b.world.transform(b.bob).p).norm(), Real(1e-3));
  }
  // As a slider: the inclined slider's motion.
  const Vec3 axis(std::cos(Real(0.5)), -std::sin(Real(0.5)), 0);
  World w1(quietWorld()), w2(quietWorld());
  const BodyId b1 = w1.createBody({}), b2 = w2.createBody({});
  w1.addShape(b1, Box{Vec3::Constant(Real(0.1))});
  w2.addShape(b2, Box{Vec3::Constant(Real(0.1))});
  w1.createJoint(SliderJointSettings{.bodyB = b1, .axisA = axis});
  const Quat frame = Quat::FromTwoVectors(Vec3::UnitX(), axis);
  SixDofJointSettings six{
      .bodyB = b2, .frameA = {Vec3::Zero(), frame}, .frameB = {Vec3::Zero(), frame}};
  six.axes[0].locked = false;
  w2.createJoint(six);
  for (int i = 0; i < 60; ++i) {
    w1.step(kDt);
    w2.step(kDt);
  }
  EXPECT_LT((w1.transform(b1).p - w2.transform(b2).p).norm(), Real(1e-4));
}

// A ball joint's cone: a limb (a rod 1 m long hanging from its end) swinging up to 1.2 rad from
// the vertical is stopped at the cone of 0.5 rad (the speculative limit row; soft when
// violated: the 0.01 rad). The twist limits stop a rod spun about the joint's axis.
// (The limit rows are solved apart from the anchors' block: a small body on a long massless
// arm, whose inertia about its own centre is a small part of its inertia about the pivot,
// converges between the two slowly and overshoots the limit.)
TEST(JointBall, ConeAndTwistLimitsHold) {
  World world(quietWorld());
  const Real L = 1;
  // Released from the vertical turning about the pivot at the rate that would lift it to 1.2
  // rad (I_pivot w^2 / 2 = m g L (1 - cos 1.2) / 2, I_pivot = m L^2 / 3), a little sideways.
  const Vec3 w(0, Real(0.3), std::sqrt(3 * kG * (1 - std::cos(Real(1.2))) / L));
  const BodyId limb = world.createBody({.position = Vec3(0, -L / 2, 0),
                                        .linearVelocity = w.cross(Vec3(0, -L / 2, 0)),
                                        .angularVelocity = w});
  world.addShape(limb, Box{Vec3(Real(0.05), L / 2, Real(0.05))});
  const JointId cone = world.createJoint(BallJointSettings{.bodyB = limb,
                                                           .anchorB = Vec3(0, L / 2, 0),
                                                           .axisA = -Vec3::UnitY(),
                                                           .axisB = -Vec3::UnitY(),
                                                           .coneLimit = Real(0.5)});
  Real widest = 0;
  for (int i = 0; i < 120; ++i) {
    world.step(kDt);
    const Vec3 p = world.transform(limb).p;
    widest = std::max(widest, std::acos(std::clamp(-p.y() / p.norm(), Real(-1), Real(1))));
  }
  EXPECT_GT(widest, Real(0.45));  // it reached the cone
  EXPECT_LT(widest, Real(0.51));
  EXPECT_LT(world.rigidBodies().jointError(cone).angle, Real(0.01));

  WorldSettings s = quietWorld();
  s.gravity = Vec3::Zero();
  World spin(s);
  const BodyId rod = spin.createBody({.angularVelocity = Vec3(3, 0, 0)});
  spin.addShape(rod, Box{Vec3(Real(0.5), Real(0.05), Real(0.05))});
  const JointId twist = spin.createJoint(
      BallJointSettings{.bodyB = rod, .twistLimits = JointLimits{Real(-0.3), Real(0.3)}});
  Real most = 0;
  for (int i = 0; i < 60; ++i) {
    spin.step(kDt);
    most = std::max(most, spin.rigidBodies().jointCoordinate(twist));
  }
  EXPECT_GT(most, Real(0.29));
  EXPECT_LT(most, Real(0.31));
}

// The twist limit at a wide swing (an arm raised above the shoulder, twisted): a rod hanging
// from a ball joint whose axis points down, tilted 2.5 rad from it and turned about the joint's
// axis at 2 rad/s without gravity. Turning about A's axis is pure twist: the twist grows at the
// rate of the turn. A twist row along B's own axis measures cos(2.5) = -0.8 of that rate, the
// wrong sign: it let this rod 0.03 rad through its limit, and a ragdoll's arm at the corner of
// its cone and twist limits gained energy until it spun at 30 rad/s. The limit stops it as at
// a small swing (the speculative row; 0.01 rad over, as above), and no energy is gained: the
// limit's rows are inelastic, and the anchors' rigid rows do no work but their position
// correction's, which holds the anchor to ~1e-5 m.
TEST(JointBall, TwistLimitHoldsAtAWideSwing) {
  WorldSettings s = quietWorld();
  s.gravity = Vec3::Zero();
  World world(s);
  const Real L = 1, tilt = Real(2.5), turn = 2;
  const Quat q(Eigen::AngleAxis<Real>(tilt, Vec3::UnitZ()));
  const Vec3 centre = q * Vec3(0, -L / 2, 0);
  const Vec3 w(0, -turn, 0);
  const BodyId rod = world.createBody({.position = centre,
                                       .orientation = q,
                                       .linearVelocity = w.cross(centre),
                                       .angularVelocity = w});
  world.addShape(rod, Box{Vec3(Real(0.05), L / 2, Real(0.05))});
  const JointId joint =
      world.createJoint(BallJointSettings{.bodyB = rod,
                                          .anchorB = Vec3(0, L / 2, 0),
                                          .axisA = -Vec3::UnitY(),
                                          .axisB = -Vec3::UnitY(),
                                          .twistLimits = JointLimits{Real(-0.3), Real(0.3)}});
  const Real energy = world.rigidBodies().kineticEnergy();
  Real most = 0, mostEnergy = 0;
  for (int i = 0; i < 120; ++i) {
    world.step(kDt);
    most = std::max(most, world.rigidBodies().jointCoordinate(joint));
    mostEnergy = std::max(mostEnergy, world.rigidBodies().kineticEnergy());
  }
  EXPECT_GT(most, Real(0.29));  // it reached the limit
  EXPECT_LT(most, Real(0.31));
  EXPECT_LE(mostEnergy, energy * Real(1.001));
}

// A Cardan joint between a kinematic input shaft turning at w1 about x and an output shaft
// held by a hinge along an axis at beta from x: the output turns at
// w2 = w1 cos(beta) / (1 - sin^2(beta) cos^2(theta1)), theta1 the input yoke's angle from the
// shafts' plane (Cardan's closed form). The input yoke starts along z, a quarter turn from the
// plane: cos^2(theta1) = sin^2(w1 t). The joints hold to ~1e-7 m, so 0.1% of w1 is the bound.
TEST(JointUniversal, OutputShaftFollowsCardansLaw) {
  WorldSettings s = quietWorld();
  s.gravity = Vec3::Zero();
  World world(s);
  const Real beta = Real(0.5), w1 = 1;
  const Vec3 outAxis(std::cos(beta), std::sin(beta), 0);
  const BodyId in = world.createBody(
      {.type = BodyType::Kinematic, .position = Vec3(-1, 0, 0), .angularVelocity = Vec3(w1, 0, 0)});
  world.addShape(in, Box{Vec3(Real(0.5), Real(0.05), Real(0.05))});
  const BodyId out = world.createBody(
      {.position = outAxis, .orientation = Quat::FromTwoVectors(Vec3::UnitX(), outAxis)});
  world.addShape(out, Box{Vec3(Real(0.5), Real(0.05), Real(0.05))});
  world.createJoint(HingeJointSettings{.bodyB = out,
                                       .anchorA = outAxis,
                                       .anchorB = Vec3::Zero(),
                                       .axisA = outAxis,
                                       .axisB = Vec3::UnitX()});
  // Input yoke axis: z (perpendicular to the shafts' plane); output yoke axis: in the plane.
  world.createJoint(UniversalJointSettings{.bodyA = in,
                                           .bodyB = out,
                                           .anchorA = Vec3(1, 0, 0),
                                           .anchorB = Vec3(-1, 0, 0),
                                           .axisA = Vec3::UnitZ(),
                                           .axisB = Vec3::UnitY()});
  Real worst = 0;
  for (int i = 0; i < 240; ++i) {
    world.step(kDt);
    const Real theta1 = w1 * Real(world.time());
    const Real sb = std::sin(beta), st = std::sin(theta1);
    const Real expected = w1 * std::cos(beta) / (1 - sb * sb * st * st);
    if (i > 10)
      worst = std::max(worst, std::abs(world.angularVelocity(out).dot(outAxis) - expected));
  }
  EXPECT_LT(worst, Real(0.001) * w1);
}

// A snapshot (World::saveState) carries the joints with their warm-start impulses: the
// restored world continues bit-identically.
TEST(JointWorld, RestoredStateContinuesBitIdentically) {
  CapsuleChain c(10, 5);
  for (int i = 0; i < 30; ++i) c.world.step(kDt);
  const World::State saved = c.world.saveState();
  for (int i = 0; i < 30; ++i) c.world.step(kDt);
  const Transform first = c.world.transform(c.bob);
  c.world.restoreState(saved);
  for (int i = 0; i < 30; ++i) c.world.step(kDt);
  const Transform again = c.world.transform(c.bob);
  EXPECT_EQ(0, std::memcmp(first.p.data(), again.p.data(), sizeof(Real) * 3));
  EXPECT_EQ(0, std::memcmp(first.q.coeffs().data(), again.q.coeffs().data(), sizeof(Real) * 4));
}

// A destroyed joint's slot is taken by the next joint, lowest slot first, under a new
// generation; the stale id stays invalid. (The search starts at the lowest slot that may be
// free, as for bodies and shapes, rather than at slot 0.)
TEST(JointWorld, DestroyedSlotsAreReusedLowestFirst) {
  World world(quietWorld());
  const BodyId bob = world.createBody({.position = Vec3(0, -1, 0)});
  world.addShape(bob, Sphere{Real(0.1)});
  auto make = [&] { return world.createJoint(BallJointSettings{.bodyB = bob}); };
  std::vector<JointId> ids;
  for (int i = 0; i < 4; ++i) ids.push_back(make());
  world.destroyJoint(ids[2]);
  world.destroyJoint(ids[1]);
  const JointId first = make(), second = make(), third = make();
  EXPECT_EQ(first.index, ids[1].index);
  EXPECT_EQ(second.index, ids[2].index);
  EXPECT_EQ(third.index, 4u);
  EXPECT_NE(first.generation, ids[1].generation);
  EXPECT_FALSE(world.rigidBodies().isValid(ids[1]));
  EXPECT_TRUE(world.rigidBodies().isValid(first));
  EXPECT_EQ(world.rigidBodies().jointCount(), 5);
}

// Jointed bodies are one island: a chain hanging at rest falls asleep whole, and a push on its
// last link wakes every link.
TEST(JointWorld, JointedBodiesSleepAndWakeTogether) {
  WorldSettings s = quietWorld();
  s.sleeping = true;
  World world(s);
  std::vector<BodyId> links;
  BodyId previous;
  for (int i = 0; i < 5; ++i) {
    const BodyId link = world.createBody({.position = Vec3(0, -Real(0.5) - Real(i), 0)});
    world.addShape(link, Sphere{Real(0.2)});
    world.createJoint(
        BallJointSettings{.bodyA = previous,
                          .bodyB = link,
                          .anchorA = previous.isNull() ? Vec3::Zero() : Vec3(0, Real(-0.5), 0),
                          .anchorB = Vec3(0, Real(0.5), 0)});
    links.push_back(link);
    previous = link;
  }
  for (int i = 0; i < 120; ++i) world.step(kDt);
  for (BodyId b : links) EXPECT_FALSE(world.rigidBodies().isAwake(b));
  world.rigidBodies().applyImpulse(links.back(), Vec3(1, 0, 0), world.transform(links.back()).p);
  world.step(kDt);
  for (BodyId b : links) EXPECT_TRUE(world.rigidBodies().isAwake(b));
  EXPECT_GT(world.linearVelocity(links.front()).norm(), 0);  // the push reached the top
}

// collideConnected: two boxes overlapping at their joint do not push each other apart unless
// asked to; a disabled (or broken) joint no longer filters them.
TEST(JointWorld, CollideConnectedFiltersTheJointedPair) {
  for (bool collide : {false, true}) {
    WorldSettings s = quietWorld();
    s.gravity = Vec3::Zero();
    World world(s);
    const BodyId a = world.createBody({.position = Vec3(0, 0, 0)});
    const BodyId b = world.createBody({.position = Vec3(Real(0.8), 0, 0)});
    world.addShape(a, Box{Vec3::Constant(Real(0.5))});
    world.addShape(b, Box{Vec3::Constant(Real(0.5))});
    const JointId j = world.createJoint(DistanceJointSettings{
        .bodyA = a, .bodyB = b, .minLength = 0, .maxLength = 10, .collideConnected = collide});
    for (int i = 0; i < 30; ++i) world.step(kDt);
    const Real gap = world.transform(b).p.x() - world.transform(a).p.x();
    if (collide)
      EXPECT_GT(gap, Real(0.99));  // pushed apart to touching
    else
      EXPECT_NEAR(gap, Real(0.8), Real(1e-5));
    if (!collide) {
      world.rigidBodies().setJointEnabled(j, false);
      for (int i = 0; i < 30; ++i) world.step(kDt);
      EXPECT_GT(world.transform(b).p.x() - world.transform(a).p.x(), Real(0.99));
    }
  }
}

// A kinematic body drives what it is jointed to: a box welded under a kinematic body moving at
// 1 m/s follows it, off only by the soft weld's static deflection under the box's weight,
// g / (2 pi 120 Hz)^2 = 2e-5 m, and keeps its rotation.
TEST(JointWorld, KinematicBodyDrivesItsJoint) {
  World world(quietWorld());
  const BodyId driver =
      world.createBody({.type = BodyType::Kinematic, .linearVelocity = Vec3(1, 0, 0)});
  const BodyId box = world.createBody({.position = Vec3(0, -1, 0)});
  world.addShape(box, Box{Vec3::Constant(Real(0.2))});
  const JointId j =
      world.createJoint(WeldJointSettings{.bodyA = driver, .bodyB = box, .anchorB = Vec3(0, 1, 0)});
  for (int i = 0; i < 60; ++i) world.step(kDt);
  EXPECT_NEAR(world.transform(box).p.x(), world.transform(driver).p.x(), Real(1e-3));
  EXPECT_NEAR(world.linearVelocity(box).x(), 1, Real(1e-3));
  EXPECT_LT(world.rigidBodies().jointError(j).angle, Real(1e-3));
}

namespace {

// A small jointed system whose joints and contacts form one island: a frictionless 500 kg box
// on the ground carries a pendulum on a ball joint (displaced, so it pulls the box sideways) and
// a 32 kg hinged flap that gravity (125 N m) presses against its upper limit, whose motor wants
// the other way with 5 N m (it stalls); a weight on a sprung slider hangs from the flap. Every row
// kind of the LCP: bilateral locked rows, a one-sided limit, a boxed motor, a soft spring.
struct JointedIsland {
  World world;
  std::vector<BodyId> bodies;

  explicit JointedIsland(SolverType solver, int iterations)
      : world([&] {
          WorldSettings s = quietWorld();
          s.solver.type = solver;
          s.solver.iterations = iterations;
          return s;
        }()) {
    const Material slick{.density = 1000, .friction = 0};
    const BodyId ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Plane{Vec3::UnitY(), 0}, slick);
    const BodyId box = world.createBody({.position = Vec3(0, Real(0.25), 0)});
    world.addShape(box, Box{Vec3(Real(0.5), Real(0.25), Real(0.5))}, slick);
    const BodyId bob = world.createBody({.position = Vec3(Real(0.8), Real(0.4), 0)});
    world.addShape(bob, Sphere{Real(0.1)}, slick);
    world.createJoint(BallJointSettings{.bodyA = box,
                                        .bodyB = bob,
                                        .anchorA = Vec3(0, Real(0.5), 0),
                                        .anchorB = Vec3(Real(-0.8), Real(0.35), 0)});
    const BodyId flap = world.createBody({.position = Vec3(Real(-0.9), Real(0.5), 0)});
    world.addShape(flap, Box{Vec3(Real(0.4), Real(0.05), Real(0.2))}, slick);
    world.createJoint(HingeJointSettings{.bodyA = box,
                                         .bodyB = flap,
                                         .anchorA = Vec3(Real(-0.5), Real(0.25), 0),
                                         .anchorB = Vec3(Real(0.4), 0, 0),
                                         .limits = JointLimits{-1, 0},
                                         .motor = JointMotor{.speed = -3, .maxForce = 5}});
    const BodyId weight = world.createBody({.position = Vec3(Real(-1.2), Real(0.2), 0)});
    world.addShape(weight, Sphere{Real(0.08)}, slick);
    world.createJoint(
        SliderJointSettings{.bodyA = flap,
                            .bodyB = weight,
                            .anchorA = Vec3(Real(-0.3), 0, 0),
                            .anchorB = Vec3(0, Real(0.3), 0),
                            .axisA = Vec3::UnitY(),
                            .spring = JointSpring{.frequency = 3, .dampingRatio = 0.2}});
    bodies = {box, bob, flap, weight};
  }
};

}  // namespace

// The LCP solvers take the joints' rows into each island's LCP: one step of the jointed island
// gives the velocities that pgs gives when it has converged (1,000 iterations), since the LCP
// of a positive semidefinite Delassus matrix fixes J v+ uniquely, whatever split of impulses
// the solvers pick. They agree to 1.6e-7 m/s in float, the rounding of speeds near 1 m/s; the
// bound, 1e-5 m/s, leaves rounding over the sweeps' cancellations room. At 4 iterations pgs is
// still 9e-4 m/s off (the check that the comparison can fail; the LCP solvers were 0.026 m/s
// off when they solved the joints in pgs passes of their own before the contacts' LCP).
TEST(JointLcp, SolversAgreeWithConvergedPgsOnAJointedIsland) {
  auto velocities = [](SolverType solver, int iterations) {
    JointedIsland island(solver, iterations);
    island.world.step(kDt);
    std::vector<Vec3> v;
    for (BodyId b : island.bodies) {
      v.push_back(island.world.linearVelocity(b));
      v.push_back(island.world.angularVelocity(b));
    }
    return v;
  };
  auto farthest = [](const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    Real d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a[i] - b[i]).norm());
    return d;
  };
  const std::vector<Vec3> converged = velocities(SolverType::Pgs, 1000);
  EXPECT_GT(farthest(velocities(SolverType::Pgs, 4), converged), Real(1e-4));
  for (SolverType solver : {SolverType::LcpDantzig, SolverType::LcpLemke})
    EXPECT_LT(farthest(velocities(solver, 4), converged), Real(1e-5)) << solverName(solver);
}
