// Joints against their oracles: a physical pendulum's period (the complete elliptic integral),
// a chain's joint error at rest, limits, motors, springs, reaction forces and breaking, an
// inclined slider's acceleration, and the same bits at one and two threads.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "inertia/world/world.h"

using namespace inertia;

namespace {

constexpr Real kPi = Real(std::numbers::pi);
constexpr Real kG = Real(9.81);
constexpr Real kDt = Real(1.0 / 60);

WorldSettings quietWorld() {
  WorldSettings s;
  s.sleeping = false;
  s.threads = 1;
  return s;
}

// A sphere of radius r and density 1000 whose centre hangs at distance L from a pivot at the
// origin, released at angle theta0 from the vertical in the x-y plane, on a hinge (axis z) or a
// ball joint.
struct Pendulum {
  World world{quietWorld()};
  BodyId bob;
  JointId joint;
  Real L = 1, r = Real(0.1);

  Pendulum(Real theta0, bool ball) {
    const Vec3 at(L * std::sin(theta0), -L * std::cos(theta0), 0);
    bob = world.createBody({.position = at});
    world.addShape(bob, Sphere{r});
    if (ball)
      joint = world.createJoint(BallJointSettings{.bodyB = bob, .anchorB = -at});
    else
      joint = world.createJoint(HingeJointSettings{.bodyB = bob, .anchorB = -at});
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
// and the soft joint's compliance at 120 Hz against a 0.5 Hz swing, (0.5/120)^2 ~ 2e-5: far
// under the 0.5% asked; the 0.5% allows for the soft joint's damping of the amplitude (the
// large-amplitude period depends on it) over the ten periods measured.
TEST(JointPendulum, HingePeriodMatchesEllipticIntegral) {
  for (Real theta0 : {Real(0.1), Real(1.5)}) {
    Pendulum p(theta0, false);
    const double measured = p.period(11);
    EXPECT_NEAR(measured / p.exactPeriod(theta0), 1, 0.005) << "theta0 " << theta0;
  }
}

TEST(JointPendulum, BallPeriodMatchesEllipticIntegral) {
  for (Real theta0 : {Real(0.1), Real(1.5)}) {
    Pendulum p(theta0, true);
    const double measured = p.period(11);
    EXPECT_NEAR(measured / p.exactPeriod(theta0), 1, 0.005) << "theta0 " << theta0;
  }
}

}  // namespace
