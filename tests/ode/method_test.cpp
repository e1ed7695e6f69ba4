// The Method enum and its names, the generic entry point's dispatch, Verlet's start and restart,
// and input checks at the boundary.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <string>

#include "inertia/ode/ode.h"

namespace ode = inertia::ode;

namespace {

void spring(double, ode::ConstView<double> x, ode::ConstView<double> v, ode::View<double> a) {
  a = -4 * x - 0.1 * v;
}
void decay(double, ode::ConstView<double> y, ode::View<double> dy) { dy = -y; }

template <class F>
std::string thrownMessage(F f) {
  try {
    f();
  } catch (const inertia::InvalidArgument& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

}  // namespace

TEST(Method, NamesRoundTripAndAreTheSceneFileNames) {
  const std::string_view expected[] = {
      "explicit_euler",  "midpoint",         "heun",          "rk4", "verlet",
      "velocity_verlet", "symplectic_euler", "backward_euler"};
  ASSERT_EQ(ode::kMethods.size(), std::size(expected));
  for (std::size_t i = 0; i < ode::kMethods.size(); ++i) {
    EXPECT_EQ(ode::methodName(ode::kMethods[i]), expected[i]);
    EXPECT_EQ(ode::kMethodNames[i], expected[i]);
    EXPECT_EQ(ode::methodFromName(expected[i]), ode::kMethods[i]);
  }
  EXPECT_EQ(ode::methodFromName("RK4"), std::nullopt);  // exact, lower case
  EXPECT_EQ(ode::methodFromName("euler"), std::nullopt);
  EXPECT_EQ(ode::methodFromName(""), std::nullopt);
  static_assert(ode::methodFromName("rk4") == ode::Method::Rk4);  // usable at compile time
  static_assert(ode::methodName(ode::Method::VelocityVerlet) == "velocity_verlet");
}

TEST(Method, TheoreticalOrders) {
  EXPECT_EQ(ode::methodOrder(ode::Method::ExplicitEuler), 1);
  EXPECT_EQ(ode::methodOrder(ode::Method::Midpoint), 2);
  EXPECT_EQ(ode::methodOrder(ode::Method::Heun), 2);
  EXPECT_EQ(ode::methodOrder(ode::Method::Rk4), 4);
  EXPECT_EQ(ode::methodOrder(ode::Method::Verlet), 2);
  EXPECT_EQ(ode::methodOrder(ode::Method::VelocityVerlet), 2);
  EXPECT_EQ(ode::methodOrder(ode::Method::SymplecticEuler), 1);
  EXPECT_EQ(ode::methodOrder(ode::Method::BackwardEuler), 1);
  // The stepper objects carry the same orders.
  static_assert(decltype(ode::rk4)::order == 4 && decltype(ode::dormandPrince5)::order == 5);
  static_assert(decltype(ode::stacked(ode::heun))::order == 2);
  EXPECT_TRUE(ode::isImplicit(ode::Method::BackwardEuler));
  EXPECT_FALSE(ode::isImplicit(ode::Method::Rk4));
}

// ode::step(method, ...) performs exactly the step of the corresponding stepper.
TEST(GenericStep, DispatchesToTheNamedMethod) {
  const auto direct = [](ode::Method m, Eigen::VectorXd& x, Eigen::VectorXd& v,
                         ode::Workspace<double>& ws) {
    switch (m) {
      case ode::Method::ExplicitEuler:
        ode::stacked(ode::explicitEuler)(spring, 0.0, 0.1, x, v, ws);
        break;
      case ode::Method::Midpoint:
        ode::stacked(ode::midpoint)(spring, 0.0, 0.1, x, v, ws);
        break;
      case ode::Method::Heun:
        ode::stacked(ode::heun)(spring, 0.0, 0.1, x, v, ws);
        break;
      case ode::Method::Rk4:
        ode::stacked(ode::rk4)(spring, 0.0, 0.1, x, v, ws);
        break;
      case ode::Method::Verlet:
        ode::verlet(spring, 0.0, 0.1, x, v, ws);
        break;
      case ode::Method::VelocityVerlet:
        ode::velocityVerlet(spring, 0.0, 0.1, x, v, ws);
        break;
      case ode::Method::SymplecticEuler:
        ode::symplecticEuler(spring, 0.0, 0.1, x, v, ws);
        break;
      case ode::Method::BackwardEuler:
        break;
    }
  };
  for (ode::Method m : ode::kMethods) {
    if (m == ode::Method::BackwardEuler) continue;
    Eigen::VectorXd x1 = Eigen::VectorXd::LinSpaced(5, -1, 1), v1 = Eigen::VectorXd::Ones(5);
    Eigen::VectorXd x2 = x1, v2 = v1;
    ode::Workspace<double> ws1, ws2;
    ode::step(m, spring, 0.0, 0.1, x1, v1, ws1);
    direct(m, x2, v2, ws2);
    EXPECT_EQ(x1, x2) << ode::methodName(m);
    EXPECT_EQ(v1, v2) << ode::methodName(m);
    EXPECT_NE(x1, Eigen::VectorXd::LinSpaced(5, -1, 1)) << ode::methodName(m);  // it moved
  }
}

TEST(GenericStep, FirstStepsMatchTheirFormulas) {
  // One step from x = 1, v = 0.5 of x'' = -4x - 0.1 v, h = 0.1: the textbook updates.
  const double h = 0.1, x0 = 1, v0 = 0.5, a0 = -4 * x0 - 0.1 * v0;
  const auto run = [&](ode::Method m) {
    Eigen::VectorXd x = Eigen::VectorXd::Constant(1, x0), v = Eigen::VectorXd::Constant(1, v0);
    ode::Workspace<double> ws;
    ode::step(m, spring, 0.0, h, x, v, ws);
    return Eigen::Vector2d(x[0], v[0]);
  };
  // Symplectic Euler: v first, then x with the new v.
  const double vSe = v0 + h * a0;
  EXPECT_DOUBLE_EQ(run(ode::Method::SymplecticEuler)[1], vSe);
  EXPECT_DOUBLE_EQ(run(ode::Method::SymplecticEuler)[0], x0 + h * vSe);
  // Explicit Euler: both from the old state.
  EXPECT_DOUBLE_EQ(run(ode::Method::ExplicitEuler)[0], x0 + h * v0);
  EXPECT_DOUBLE_EQ(run(ode::Method::ExplicitEuler)[1], v0 + h * a0);
  // Velocity Verlet, with the Euler-predicted velocity in the second evaluation.
  const double xVv = x0 + h * v0 + h * h / 2 * a0;
  const double a1 = -4 * xVv - 0.1 * (v0 + h * a0);
  EXPECT_DOUBLE_EQ(run(ode::Method::VelocityVerlet)[0], xVv);
  EXPECT_DOUBLE_EQ(run(ode::Method::VelocityVerlet)[1], v0 + h / 2 * (a0 + a1));
  // Verlet starts with the Taylor step, and outputs v = (x1 - x0) / h + h/2 a0.
  // (Verlet forms x1 as 2 x0 - x_{-1} + h^2 a0, which rounds differently from xVv by ~eps |x|;
  // the velocity divides that by h: 1e-14 = a few eps / h.)
  EXPECT_NEAR(run(ode::Method::Verlet)[0], xVv, 4e-16);
  EXPECT_NEAR(run(ode::Method::Verlet)[1], (xVv - x0) / h + h / 2 * a0, 1e-14);
}

TEST(Verlet, SecondStepUsesThePreviousPositionAndRestartsChangedComponents) {
  const double h = 0.1;
  Eigen::Vector2d x(1, 2), v(0.5, -0.5);
  ode::Workspace<double> ws;
  const auto acc = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    return Eigen::Vector2d(-4 * p - 0.1 * q);
  };
  const auto a2 = [](double, ode::ConstView<double, 2> p, ode::ConstView<double, 2> q,
                     ode::View<double, 2> a) { a = -4 * p - 0.1 * q; };
  ode::verlet(a2, 0.0, h, x, v, ws);
  const Eigen::Vector2d x1 = x, v1 = v;
  const Eigen::Vector2d x0(1, 2);
  // Uninterrupted second step: x2 = 2 x1 - x0 + h^2 a(x1, v1).
  ode::verlet(a2, h, h, x, v, ws);
  const Eigen::Vector2d expected = 2 * x1 - x0 + h * h * acc(x1, v1);
  EXPECT_DOUBLE_EQ(x[0], expected[0]);
  EXPECT_DOUBLE_EQ(x[1], expected[1]);

  // The caller reflects the second component's velocity (a collision): that component
  // restarts with a Taylor step from its new (x, v); the first continues the recurrence.
  const Eigen::Vector2d x2 = x;
  v[1] = -v[1];
  const Eigen::Vector2d vChanged = v;
  ode::verlet(a2, 2 * h, h, x, v, ws);
  const Eigen::Vector2d a = acc(x2, vChanged);
  EXPECT_DOUBLE_EQ(x[0], 2 * x2[0] - x1[0] + h * h * a[0]);
  // The restart forms x2 + h v + h^2/2 a as 2 x2 - (x2 - h v + h^2/2 a) + h^2 a: the same up to
  // a few roundings of numbers ~2, so 1e-15.
  EXPECT_NEAR(x[1], x2[1] + h * vChanged[1] + h * h / 2 * a[1], 1e-15);

  // A different h restarts everything.
  const Eigen::Vector2d x3 = x, v3 = v;
  ode::verlet(a2, 3 * h, h / 2, x, v, ws);
  const Eigen::Vector2d a3 = acc(x3, v3);
  EXPECT_NEAR(x[0], x3[0] + h / 2 * v3[0] + h * h / 8 * a3[0], 1e-15);
  EXPECT_NEAR(x[1], x3[1] + h / 2 * v3[1] + h * h / 8 * a3[1], 1e-15);
}

TEST(GenericStep, BackwardEulerWithoutJacobiansThrowsNamingTheMissingOne) {
  Eigen::VectorXd x = Eigen::VectorXd::Ones(3), v = Eigen::VectorXd::Zero(3);
  ode::Workspace<double> ws;
  EXPECT_NE(thrownMessage([&] {
              ode::step(ode::Method::BackwardEuler, spring, 0.0, 0.1, x, v, ws);
            }).find("dadx"),
            std::string::npos);
  const auto dadx = [](double, ode::ConstView<double>, ode::ConstView<double>,
                       ode::ConstView<double> w, ode::View<double> out) { out = -4 * w; };
  const ode::SecondOrderSystem onlyX{.acceleration = spring, .dadx = dadx};
  EXPECT_NE(thrownMessage([&] {
              ode::step(ode::Method::BackwardEuler, onlyX, 0.0, 0.1, x, v, ws);
            }).find("dadv"),
            std::string::npos);
  EXPECT_EQ(x, Eigen::VectorXd::Ones(3));  // nothing was changed

  // With both (dadv = -0.1 I) it runs; explicit methods never need them.
  const auto dadv = [](double, ode::ConstView<double>, ode::ConstView<double>,
                       ode::ConstView<double> w, ode::View<double> out) { out = -0.1 * w; };
  const ode::SecondOrderSystem full{.acceleration = spring, .dadx = dadx, .dadv = dadv};
  EXPECT_TRUE(ode::step(ode::Method::BackwardEuler, full, 0.0, 0.1, x, v, ws).converged);
  EXPECT_NO_THROW(ode::step(ode::Method::Rk4, onlyX, 0.0, 0.1, x, v, ws));
}

TEST(InputChecks, NonPositiveOrNonFiniteStepThrowsForEveryMethod) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::VectorXd y = Eigen::VectorXd::Ones(2), x = y, v = y;
  ode::Workspace<double> ws;
  const auto jacobian = [](double, ode::ConstView<double>, ode::JacobianView<double> J) {
    J.diagonal().setConstant(-1);
  };
  const auto jacobianTimes = [](double, ode::ConstView<double>, ode::ConstView<double> w,
                                ode::View<double> out) { out = -w; };
  for (double h : {0.0, -0.01, nan, inf}) {
    for (ode::Method m : ode::kMethods)
      EXPECT_THROW(ode::step(m, spring, 0.0, h, x, v, ws), inertia::InvalidArgument)
          << ode::methodName(m) << " h = " << h;
    EXPECT_THROW(ode::explicitEuler(decay, 0.0, h, y, ws), inertia::InvalidArgument);
    EXPECT_THROW(ode::midpoint(decay, 0.0, h, y, ws), inertia::InvalidArgument);
    EXPECT_THROW(ode::heun(decay, 0.0, h, y, ws), inertia::InvalidArgument);
    EXPECT_THROW(ode::rk4(decay, 0.0, h, y, ws), inertia::InvalidArgument);
    EXPECT_THROW(ode::dormandPrince5(decay, 0.0, h, y, ws), inertia::InvalidArgument);
    EXPECT_THROW(ode::backwardEuler(decay, jacobian, 0.0, h, y, ws), inertia::InvalidArgument);
    EXPECT_THROW(ode::backwardEulerMatrixFree(decay, jacobianTimes, 0.0, h, y, ws),
                 inertia::InvalidArgument);
  }
  EXPECT_EQ(y, Eigen::VectorXd::Ones(2));  // rejected before touching the state
  EXPECT_NE(thrownMessage([&] { ode::rk4(decay, 0.0, -1.0, y, ws); }).find("step size h"),
            std::string::npos);
  EXPECT_THROW(ode::rk4(decay, nan, 0.1, y, ws), inertia::InvalidArgument);  // t too
}

TEST(InputChecks, MismatchedSizesAndUnknownMethodThrow) {
  Eigen::VectorXd x = Eigen::VectorXd::Ones(3), v = Eigen::VectorXd::Ones(2);
  ode::Workspace<double> ws;
  EXPECT_NE(thrownMessage([&] {
              ode::step(ode::Method::Rk4, spring, 0.0, 0.1, x, v, ws);
            }).find("same size"),
            std::string::npos);
  v = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(ode::step(static_cast<ode::Method>(42), spring, 0.0, 0.1, x, v, ws),
               inertia::InvalidArgument);
  EXPECT_EQ(ode::methodName(static_cast<ode::Method>(42)), "");
  EXPECT_THROW(
      ode::backwardEulerMatrixFree(decay,
                                   [](double, ode::ConstView<double>, ode::ConstView<double> w,
                                      ode::View<double> out) { out = -w; },
                                   0.0, 0.1, x, ws, {.tolerance = -1}),
      inertia::InvalidArgument);
}

TEST(ImplicitSteps, SingularSystemLeavesTheStateAndReportsFailure) {
  // f = y, J = 1 and h = 1 make I - h J = 0: the dense solve cannot succeed.
  Eigen::VectorXd y = Eigen::VectorXd::Ones(1);
  ode::Workspace<double> ws;
  const auto grow = [](double, ode::ConstView<double> yy, ode::View<double> dy) { dy = yy; };
  const auto jacobian = [](double, ode::ConstView<double>, ode::JacobianView<double> J) {
    J(0, 0) = 1;
  };
  EXPECT_FALSE(ode::backwardEuler(grow, jacobian, 0.0, 1.0, y, ws).converged);
  EXPECT_EQ(y[0], 1.0);
}

TEST(ImplicitSteps, BiCgStabHandlesANonSymmetricJacobian) {
  // y' = J y with J a rotation generator (non-symmetric): backward Euler is exactly
  // y1 = (I - h J)^{-1} y0; CG is not applicable, BiCGSTAB is.
  Eigen::Matrix2d J;
  J << -0.5, 2, -2, -0.5;
  const auto f = [&](double, ode::ConstView<double, 2> y, ode::View<double, 2> dy) { dy = J * y; };
  const auto jv = [&](double, ode::ConstView<double, 2>, ode::ConstView<double, 2> w,
                      ode::View<double, 2> out) { out = J * w; };
  Eigen::Vector2d y(1, 0);
  ode::Workspace<double> ws;
  const ode::LinearSolveReport r = ode::backwardEulerMatrixFree(
      f, jv, 0.0, 0.1, y, ws, {.solver = ode::LinearSolver::BiCgStab, .tolerance = 1e-14});
  EXPECT_TRUE(r.converged);
  const Eigen::Vector2d exact =
      (Eigen::Matrix2d::Identity() - 0.1 * J).inverse() * Eigen::Vector2d(1, 0);
  // Relative residual 1e-14 on a matrix of condition ~1.2: error ~1e-14.
  EXPECT_NEAR((y - exact).norm(), 0.0, 1e-13);
}
