// Articulations stepped in time: energy and momentum against the integrators' orders, a
// pendulum's period against the elliptic-integral closed form, a floating body against the
// rigid-body layer's free flight, and the joint effects (damping, friction, limits, velocity
// limits, drives) against their exact discrete or closed-form responses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "inertia/articulation/articulation.h"
#include "inertia/articulation/builders.h"
#include "inertia/world/world.h"

using namespace inertia::articulation;

namespace {

template <class S>
S totalEnergy(const Articulation<S>& a) {
  return kineticEnergy(a.model(), a.q(), a.qd()) + potentialEnergy(a.model(), a.q());
}

// Largest |E - E0| over `seconds` of a double pendulum released from (q1, q2) = (1.2, -0.6).
double energyError(Integrator integrator, double h, double seconds) {
  Articulation<double> a(pendulumChain<double>(2, 1.0, 1.0), {.integrator = integrator});
  VectorX<double> q(2), qd = VectorX<double>::Zero(2);
  q << 1.2, -0.6;
  a.setState(q, qd);
  const double E0 = totalEnergy(a);
  double worst = 0;
  for (int i = 0, n = int(std::lround(seconds / h)); i < n; ++i) {
    a.step(h);
    worst = std::max(worst, std::abs(totalEnergy(a) - E0));
  }
  return worst;
}

// A one-dof prismatic slider of mass m along x, without gravity.
Model<double> slider(double m, const JointSettings<double>& joint) {
  Model<double> model;
  model.gravity.setZero();
  JointSettings<double> j = joint;
  j.type = JointType::Prismatic;
  j.axis = Vector3<double>::UnitX();
  model.addLink({.name = "slider",
                 .joint = j,
                 .inertia = {m, Vector3<double>::Zero(), Matrix3<double>::Identity()}});
  return model;
}

VectorX<double> scalar(double x) { return VectorX<double>::Constant(1, x); }

}  // namespace

// RK4 is fourth order: halving h divides the energy error by 2^4 = 16 (accepted from 12, the
// asymptotic regime at these steps), and it is small in absolute terms.
TEST(Stepping, Rk4EnergyErrorIsFourthOrder) {
  const double e1 = energyError(Integrator::Rk4, 4e-3, 2.0);
  const double e2 = energyError(Integrator::Rk4, 2e-3, 2.0);
  EXPECT_GT(e1 / e2, 12.0) << e1 << " " << e2;
  EXPECT_LT(e2, 1e-7);  // E0 is about 15 J
  std::printf("RK4 energy error: %.3g J at h = 4 ms, %.3g J at 2 ms\n", e1, e2);
}

// Semi-implicit Euler is first order: halving h halves the energy error of the double pendulum
// (accepted 1.6..2.5).
TEST(Stepping, SemiImplicitEulerEnergyErrorIsFirstOrder) {
  const double e1 = energyError(Integrator::SemiImplicitEuler, 2e-3, 5.0);
  const double e2 = energyError(Integrator::SemiImplicitEuler, 1e-3, 5.0);
  EXPECT_GT(e1 / e2, 1.6) << e1 << " " << e2;
  EXPECT_LT(e1 / e2, 2.5) << e1 << " " << e2;
}

// It is also symplectic: on an integrable system (a simple pendulum at 2 rad) a modified energy
// is conserved, so the energy error oscillates with one amplitude, without drift: its largest
// value over the last 10 s equals that over the first 10 s (both windows hold many periods, so
// each samples the peak to O((w h)^2) ~ 1e-5 relative). Explicit Euler, not symplectic, drifts.
TEST(Stepping, SemiImplicitEulerEnergyErrorDoesNotDrift) {
  Articulation<double> a(pendulumChain<double>(1, 1.0, 1.0));
  a.setState(VectorX<double>::Constant(1, 2.0), VectorX<double>::Zero(1));
  const double E0 = totalEnergy(a), h = 1e-3;
  double first = 0, last = 0;
  for (int n = 1; n <= 100000; ++n) {
    a.step(h);
    const double e = std::abs(totalEnergy(a) - E0);
    if (n <= 10000) first = std::max(first, e);
    if (n > 90000) last = std::max(last, e);
  }
  EXPECT_NEAR(last, first, 1e-3 * first) << first << " " << last;
}

// The same orders on a random fixed-base tree with every joint type under gravity, so that the
// spherical joints' quaternion updates are in the measurement: RK4's energy error divides by
// about 16 when h halves (accepted from 12), semi-implicit Euler's by about 2 (1.6..2.5).
TEST(Stepping, EnergyOrdersHoldWithSphericalJoints) {
  auto error = [](Integrator integrator, double h) {
    const Model<double> model = randomTree<double>({.links = 6, .seed = 31});
    VectorX<double> q, qd;
    randomState(model, 32, q, qd);
    Articulation<double> a(model, {.integrator = integrator});
    a.setState(q, qd);
    const double E0 = totalEnergy(a);
    double worst = 0;
    for (int i = 0, n = int(std::lround(0.5 / h)); i < n; ++i) {
      a.step(h);
      worst = std::max(worst, std::abs(totalEnergy(a) - E0));
    }
    return worst;
  };
  const double r1 = error(Integrator::Rk4, 2e-3), r2 = error(Integrator::Rk4, 1e-3);
  EXPECT_GT(r1 / r2, 12.0) << r1 << " " << r2;
  const double s1 = error(Integrator::SemiImplicitEuler, 1e-3);
  const double s2 = error(Integrator::SemiImplicitEuler, 5e-4);
  EXPECT_GT(s1 / s2, 1.6) << s1 << " " << s2;
  EXPECT_LT(s1 / s2, 2.5) << s1 << " " << s2;
}

// Large-amplitude pendulum: T = 4 sqrt(J / (m g l)) K(sin(theta0 / 2)), J = m l^2 + I, K the
// complete elliptic integral of the first kind. Half-periods from sign changes of theta, located
// by linear interpolation (error O(h^2) ~ 1e-6 s at h = 1e-3); RK4's phase error is ~1e-11.
TEST(Stepping, PendulumPeriodMatchesTheEllipticIntegral) {
  const double l = 1.0, m = 1.0, g = 9.81, I = 1e-6 * m, theta0 = 2.0, h = 1e-3;
  Articulation<double> a(pendulumChain<double>(1, l, m), {.integrator = Integrator::Rk4});
  a.setState(scalar(theta0), scalar(0));
  const double T =
      4 * std::sqrt((m * l * l + I) / (m * g * l)) * std::comp_ellint_1(std::sin(theta0 / 2));
  std::vector<double> crossings;
  double t = 0, previous = theta0;
  while (crossings.size() < 5) {
    a.step(h);
    t += h;
    const double now = a.q()(0);
    if ((previous > 0) != (now > 0)) crossings.push_back(t - h * now / (now - previous));
    previous = now;
  }
  const double measured = (crossings[4] - crossings[0]) / 2;
  EXPECT_NEAR(measured, T, 1e-3 * T);  // the 0.1 %
  EXPECT_NEAR(measured, T, 1e-5);      // what the method allows
  std::printf("pendulum period %.9f s, closed form %.9f s\n", measured, T);
}

// A floating random tree in zero gravity: spatial momentum about the base origin is conserved
// by the dynamics; RK4 keeps it to its O(h^4) error (halving h divides the error by about 16).
TEST(Stepping, FloatingTreeKeepsItsMomentum) {
  auto drift = [](double h) {
    Model<double> model = randomTree<double>({.links = 8, .floatingBase = true, .seed = 21});
    model.gravity.setZero();
    VectorX<double> q, qd;
    randomState(model, 22, q, qd);
    Articulation<double> a(model, {.integrator = Integrator::Rk4});
    a.setState(q, qd);
    const Vector6<double> h0 = momentum(a.model(), a.q(), a.qd());
    for (int i = 0, n = int(std::lround(1.0 / h)); i < n; ++i) a.step(h);
    return (momentum(a.model(), a.q(), a.qd()) - h0).norm() / h0.norm();
  };
  const double d1 = drift(4e-3), d2 = drift(2e-3);
  EXPECT_GT(d1 / d2, 12.0) << d1 << " " << d2;
  EXPECT_LT(d2, 1e-8);
  std::printf("momentum drift (relative) over 1 s: %.3g at h = 4 ms, %.3g at 2 ms\n", d1, d2);
}

// A free box on a floating joint against the same box as a rigid body of the world (Real
// precision, its second-order free-rotation splitting at 240 Hz). Reference: this articulation
// with RK4 at 1 ms (error ~1e-12). The rigid-body layer's error is estimated by Richardson from
// its own runs at 4 and 8 substeps (second order: err(4) ~ 4/3 |x4 - x8|), plus its rounding.
TEST(Stepping, FloatingBodyMatchesRigidBodyFreeFlight) {
  using inertia::Real;
  const inertia::Box box{inertia::Vec3(0.5f, 0.2f, 0.1f)};
  const LinkShape shapes[] = {{box, {}, 800}};
  const LinkInertia<double> inertia = inertiaFromShapes<double>(shapes);
  Model<double> model;
  model.gravity.setZero();
  model.addLink({.name = "box", .joint = {.type = JointType::Floating}, .inertia = inertia});
  const Vector3<double> w0(0.3, 4.0, 0.2), v0(1.0, -2.0, 0.5);
  VectorX<double> q = model.neutralConfiguration(), qd(6);
  qd << w0, v0;
  Articulation<double> a(model, {.integrator = Integrator::Rk4});
  a.setState(q, qd);
  for (int i = 0; i < 1000; ++i) a.step(1e-3);
  const Quaternion<double> r(a.q()(3), a.q()(4), a.q()(5), a.q()(6));

  auto fly = [&](int substeps) {
    inertia::World world({.gravity = inertia::Vec3::Zero(), .substeps = substeps});
    const inertia::BodyId b = world.createBody({.linearVelocity = v0.cast<Real>(),
                                                .angularVelocity = w0.cast<Real>(),
                                                .allowSleep = false});
    world.addShape(b, box, inertia::Material{.density = 800});
    for (int i = 0; i < 60; ++i) world.step(Real(1.0 / 60.0));
    return world.transform(b);
  };
  const inertia::Transform x4 = fly(4), x8 = fly(8);
  const double angleError = r.angularDistance(x4.q.cast<double>());
  const double richardson = 4.0 / 3.0 * double(x4.q.angularDistance(x8.q));
  const double rounding = 240 * 8 * double(std::numeric_limits<Real>::epsilon());
  EXPECT_LT(angleError, 2 * richardson + rounding) << richardson;
  std::printf(
      "free flight: orientation %.3g rad from the rigid-body layer (its error ~%.3g), "
      "position %.3g m\n",
      angleError, richardson, (a.q().head<3>() - x4.p.cast<double>()).norm());
  // The rigid body's centre moves by exactly h v each substep; ours carries v in the body's
  // axes, so RK4's rotation error, ~1000 (w h)^5 / 120 ~ 1e-11 rad, moves it by up to |v| T
  // times that, ~3e-11 m (visible in double builds).
  EXPECT_LT((a.q().head<3>() - x4.p.cast<double>()).norm(), rounding * 3 + 1e-10);
}

// Implicit damping c on a mass m: each step solves m (v' - v) = -h c v', so v_n = v0 / (1 +
// h c / m)^n exactly (the continuous e^(-c t / m) within O(h)).
TEST(Stepping, DampingIsImplicitAndExact) {
  const double m = 2, c = 3, h = 0.01, v0 = 1.5;
  Articulation<double> a(slider(m, {.damping = c}));
  a.setState(scalar(0), scalar(v0));
  for (int n = 1; n <= 100; ++n) {
    a.step(h);
    EXPECT_NEAR(a.qd()(0), v0 / std::pow(1 + h * c / m, n), 1e-14);
  }
  // Stable for any gain: a huge damping stops the slider in one step, no overshoot.
  Articulation<double> stiff(slider(m, {.damping = 1e9}));
  stiff.setState(scalar(0), scalar(v0));
  stiff.step(h);
  EXPECT_GE(stiff.qd()(0), 0.0);
  EXPECT_LT(stiff.qd()(0), 1e-6);
}

// Coulomb friction F decelerates at F/m and then holds: v_n = max(0, v0 - n h F / m).
TEST(Stepping, CoulombFrictionStopsAndHolds) {
  const double m = 2, F = 4, h = 0.01, v0 = 1.0;
  Articulation<double> a(slider(m, {.friction = F}));
  a.setState(scalar(0), scalar(v0));
  for (int n = 1; n <= 100; ++n) {
    a.step(h);
    EXPECT_NEAR(a.qd()(0), std::max(0.0, v0 - n * h * F / m), 1e-13);
  }
  // A force below the friction bound does not move it; above, it accelerates by the difference.
  a.setJointForces(scalar(3.9));
  a.step(h);
  EXPECT_EQ(a.qd()(0), 0.0);
  a.setJointForces(scalar(5.0));
  a.step(h);
  EXPECT_NEAR(a.qd()(0), h * (5.0 - F) / m, 1e-14);
}

TEST(Stepping, VelocityLimitCapsTheSpeed) {
  Articulation<double> a(slider(1, {.velocityLimit = 0.5}));
  a.setJointForces(scalar(10));
  for (int n = 0; n < 100; ++n) {
    a.step(0.01);
    EXPECT_LE(a.qd()(0), 0.5 + 1e-15);
  }
  EXPECT_NEAR(a.qd()(0), 0.5, 1e-15);
}

// The speed guards scale each joint's speed down before the position update, the way a rigid
// body's caps do: a slider pushed past its guard moves exactly h maxLinearSpeed a step, and a
// floating link spun at 1e6 rad/s (struck by something fast) turns by h maxAngularSpeed, where
// semi-implicit Euler's explicit centrifugal terms at |w| h = 10 rad would diverge.
TEST(Stepping, SpeedGuardsCapEveryJointsSpeed) {
  Articulation<double> a(slider(1, {}), {.maxLinearSpeed = 2});
  a.setState(scalar(0), scalar(5));
  a.step(0.01);
  EXPECT_NEAR(a.q()(0), 0.01 * 2, 1e-15);
  EXPECT_NEAR(a.qd()(0), 2, 1e-15);

  Model<double> model;
  model.gravity.setZero();
  model.addLink(
      {.name = "rod",
       .joint = {.type = JointType::Floating},
       .inertia = {1, Vector3<double>::Zero(), Vector3<double>(1, 0.01, 1).asDiagonal()}});
  Articulation<double> spun(model);
  VectorX<double> qd(6);
  qd << 6e5, 8e5, 0, 3e5, 0, -4e5;  // |w| = 1e6 rad/s, |v| = 5e5 m/s
  spun.setState(model.neutralConfiguration(), qd);
  for (int i = 0; i < 10; ++i) spun.step(1e-5);
  ASSERT_TRUE(spun.q().allFinite() && spun.qd().allFinite());
  EXPECT_LE(spun.qd().head<3>().norm(), 200 * (1 + 1e-12));
  EXPECT_LE(spun.qd().tail<3>().norm(), 400 * (1 + 1e-12));
  // The first step moves the origin by h v, v the initial velocity's direction at 400 m/s.
  EXPECT_LE(spun.q().head<3>().norm(), 10 * 1e-5 * 400 * (1 + 1e-12));
  EXPECT_THROW(Articulation<double>(model, {.maxAngularSpeed = 0}), inertia::InvalidArgument);
}

// A double pendulum thrown against limits on both joints, under gravity: each step ends at the
// limit (an inelastic stop), the two rows coupled through the mass matrix. Gauss-Seidel on two
// rows contracts the error by c^2 per sweep, c = |M12| / sqrt(M11 M22) of M = H^-1; with c^2
// below 0.9 over the limits' range (checked), 300 sweeps leave 0.9^300 ~ 2e-14 of a residual of
// at most a step's motion, far below the 1e-9 rad asserted.
TEST(Stepping, LimitsHold) {
  Model<double> model;
  for (int i = 0; i < 2; ++i)
    model.addLink({.name = "l" + std::to_string(i),
                   .parent = i - 1,
                   .joint = {.originPosition = Vector3<double>(0, i == 0 ? 0 : -1, 0),
                             .lower = -0.3,
                             .upper = 0.4},
                   .inertia = {1, Vector3<double>(0, -1, 0), 0.01 * Matrix3<double>::Identity()}});
  for (double q2 = -0.3; q2 <= 0.4; q2 += 0.01) {
    const MatrixX<double> M = crba(model, Eigen::Vector2d(0, q2)).inverse();
    EXPECT_LT(M(0, 1) * M(0, 1) / (M(0, 0) * M(1, 1)), 0.9);
  }
  for (Integrator integrator : {Integrator::SemiImplicitEuler, Integrator::Rk4}) {
    Articulation<double> a(model, {.integrator = integrator, .constraintIterations = 300});
    VectorX<double> qd(2);
    qd << 5, -4;
    a.setState(VectorX<double>::Zero(2), qd);
    bool touched[2] = {false, false};
    for (int n = 0; n < 2000; ++n) {
      a.step(1e-3);
      for (int k = 0; k < 2; ++k) {
        EXPECT_GE(a.q()(k) + 0.3, -1e-9) << n;
        EXPECT_LE(a.q()(k) - 0.4, 1e-9) << n;
        touched[k] |= std::abs(a.q()(k) - 0.4) < 1e-9 || std::abs(a.q()(k) + 0.3) < 1e-9;
      }
    }
    EXPECT_TRUE(touched[0] && touched[1]);  // the limits were reached, the test means something
  }
}

// A joint started beyond its limit returns by limitBaumgarte of the error per step, without
// overshooting into a bounce.
TEST(Stepping, ViolatedLimitRecoversGeometrically) {
  Articulation<double> a(slider(1, {.lower = 0, .upper = 1}), {.limitBaumgarte = 0.2});
  a.setState(scalar(-0.1), scalar(0));
  for (int n = 1; n <= 10; ++n) {
    a.step(0.01);
    EXPECT_NEAR(a.q()(0), -0.1 * std::pow(0.8, n), 1e-15);
  }
}

// A PD drive on a mass m is the damped oscillator m x'' = k (x_t - x) - c x'. Critically damped
// (c = 2 sqrt(k m)) from rest at 0: x(t) = x_t (1 - (1 + w t) e^(-w t)), w = sqrt(k / m). The
// soft row is backward Euler on this system, O(h) accurate: halving h halves the error.
TEST(Stepping, DriveFollowsItsSecondOrderResponse) {
  const double m = 2, k = 50, xt = 0.3, w = std::sqrt(k / m);
  auto run = [&](double h) {
    Articulation<double> a(slider(
        m, {.drive = {.stiffness = k, .damping = 2 * std::sqrt(k * m), .targetPosition = xt}}));
    double worst = 0;
    for (int n = 1; n <= int(std::lround(2.0 / h)); ++n) {
      a.step(h);
      const double t = n * h;
      worst = std::max(worst, std::abs(a.q()(0) - xt * (1 - (1 + w * t) * std::exp(-w * t))));
    }
    EXPECT_NEAR(a.q()(0), xt, 2e-3 * xt);  // it reaches its target (e^-10 of the way left)
    return worst;
  };
  const double e1 = run(2e-3), e2 = run(1e-3);
  EXPECT_GT(e1 / e2, 1.8) << e1 << " " << e2;
  EXPECT_LT(e1 / e2, 2.2) << e1 << " " << e2;
  EXPECT_LT(e2, 5e-3 * xt);
}

// A saturated drive pushes with exactly its maximum force: from rest, v_n = n h F / m and
// x_n = h^2 F / m n (n + 1) / 2 (semi-implicit Euler's sum), far from a distant target.
TEST(Stepping, SaturatedDrivePushesWithItsMaximumForce) {
  const double m = 2, F = 3, h = 0.01;
  Articulation<double> a(slider(
      m, {.drive = {.stiffness = 1e4, .damping = 100, .targetPosition = 100, .maxForce = F}}));
  for (int n = 1; n <= 50; ++n) {
    a.step(h);
    EXPECT_NEAR(a.qd()(0), n * h * F / m, 1e-13);
    EXPECT_NEAR(a.q()(0), h * h * F / m * n * (n + 1) / 2, 1e-13);
  }
}

// A stiff drive stays stable at a coarse step (implicit): a 7-DOF arm driven to a pose under
// gravity, with gains that an explicit step could not take (k h^2 / J >> 4).
TEST(Stepping, StiffDrivesHoldAnArmAtItsTarget) {
  Model<double> model = sevenDofArm<double>();
  model.gravity = Vector3<double>(0, 0, -9.81);
  Articulation<double> a(model, {.constraintIterations = 50});
  const double target[7] = {0.5, -0.3, 0.2, -1.5, 0.1, 1.2, 0.4};
  for (int k = 0; k < 7; ++k)
    a.setDrive(k, {.stiffness = 1e6, .damping = 1e4, .targetPosition = target[k]});
  for (int n = 0; n < 500; ++n) a.step(0.01);
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(a.q()(k), target[k], 1e-3) << k;
  EXPECT_LT(a.qd().norm(), 1e-3);
}

TEST(Stepping, BadInputIsRejected) {
  Articulation<double> a(pendulumChain<double>(2, 1.0, 1.0));
  EXPECT_THROW(a.step(0), inertia::InvalidArgument);
  EXPECT_THROW(a.step(std::nan("")), inertia::InvalidArgument);
  EXPECT_THROW(a.setState(VectorX<double>::Zero(3), VectorX<double>::Zero(2)),
               inertia::InvalidArgument);
  EXPECT_THROW(a.setJointForces(VectorX<double>::Constant(2, std::nan(""))),
               inertia::InvalidArgument);
  EXPECT_THROW(a.setDriveTarget(5, 0), inertia::InvalidArgument);
  Model<double> model;
  EXPECT_THROW(model.addLink({.name = "a", .parent = 0}), inertia::InvalidArgument);
  EXPECT_THROW(model.addLink({.name = "a", .inertia = {.mass = -1}}), inertia::InvalidArgument);
  EXPECT_THROW(model.addLink({.name = "a", .joint = {.lower = 1, .upper = 0}}),
               inertia::InvalidArgument);
  EXPECT_THROW(model.addLink({.name = "a", .joint = {.type = JointType::Spherical, .lower = 0}}),
               inertia::InvalidArgument);
  model.addLink({.name = "root"});
  EXPECT_THROW(model.addLink({.name = "a", .parent = 0, .joint = {.type = JointType::Floating}}),
               inertia::InvalidArgument);
  try {
    model.addLink(
        {.name = "elbow", .parent = 0, .inertia = {.inertia = -Matrix3<double>::Identity()}});
    FAIL();
  } catch (const inertia::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("'elbow'.inertia"), std::string::npos) << e.what();
  }
}

// The float instantiation steps as the double one: a double pendulum released from the same
// state follows the double run to float rounding, a few roundings of |q| per step accumulated
// over 200 steps at worst linearly (0.2 s is too short for the chaos to amplify them much):
// 200 x 8 eps_float |q| ~ 2.5e-4 rad (measured: 6e-7).
TEST(Stepping, FloatFollowsDouble) {
  Articulation<float> f(pendulumChain<float>(2, 1.0f, 1.0f));
  Articulation<double> d(pendulumChain<double>(2, 1.0, 1.0));
  f.setState(Eigen::Vector2f(1.2f, -0.6f), Eigen::Vector2f::Zero());
  d.setState(Eigen::Vector2d(1.2, -0.6), Eigen::Vector2d::Zero());
  for (int n = 0; n < 200; ++n) {
    f.step(1e-3f);
    d.step(1e-3);
  }
  const double tol = 200 * 8 * double(std::numeric_limits<float>::epsilon()) * d.q().norm();
  EXPECT_LT((f.q().cast<double>() - d.q()).norm(), tol);
  EXPECT_GT((d.q() - Eigen::Vector2d(1.2, -0.6)).norm(), 0.1);  // it moved
}

// A velocity drive (no stiffness) with gain c towards vt: each step solves
// m (v' - v) = h c (vt - v'), so v_n = vt + (v0 - vt) / (1 + h c / m)^n exactly.
TEST(Stepping, VelocityDriveIsExactBackwardEuler) {
  const double m = 2, c = 5, h = 0.01, vt = 0.8;
  Articulation<double> a(slider(m, {.drive = {.damping = c, .targetVelocity = vt}}));
  for (int n = 1; n <= 100; ++n) {
    a.step(h);
    EXPECT_NEAR(a.qd()(0), vt - vt / std::pow(1 + h * c / m, n), 1e-14);
  }
}

// Armature Ja adds to the joint's inertia: (m l^2 + I + Ja) theta'' = -m g l sin(theta).
TEST(Stepping, ArmatureAddsToTheJointInertia) {
  const double l = 0.7, m = 1.5, g = 9.81, I = 0.02, Ja = 0.3, theta = 0.9;
  Model<double> model;
  model.addLink({.name = "rod",
                 .joint = {.armature = Ja},
                 .inertia = {m, Vector3<double>(0, -l, 0), I * Matrix3<double>::Identity()}});
  const double expected = -m * g * l * std::sin(theta) / (m * l * l + I + Ja);
  const VectorX<double> zero = VectorX<double>::Zero(1);
  EXPECT_NEAR(aba(model, scalar(theta), zero, zero)(0), expected, 1e-14);
  EXPECT_NEAR(forwardDynamicsCrba(model, scalar(theta), zero, zero)(0), expected, 1e-14);
  EXPECT_NEAR(rnea(model, scalar(theta), zero, scalar(expected))(0), 0.0, 1e-14);
}
