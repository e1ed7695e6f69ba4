// The measured global order of convergence of every method: the error at a fixed end time T
// against a known solution, for step sizes h = T / N halving 4 times, and the least-squares
// slope of log(error) against log(h). Asserted within 0.2 of the theoretical order.
//
// Step sizes are chosen in the asymptotic range (successive error ratios already within a few
// percent of 2^p) and with errors far above round-off: the smallest error is ~1e-12 for DP5
// (N = 80), ~1e-8 for RK4, where the accumulated round-off, ~N eps |y| < 1e-13, is below 1%.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "inertia/ode/ode.h"

namespace ode = inertia::ode;

namespace {

constexpr double kT = 2.0;
// A method of order p has error C h^p (1 + O(h)); over the chosen ranges the O(h) term shifts
// the fitted slope by < 0.1 (see the printed errors), so 0.2 separates order p from p +- 1.
constexpr double kOrderTolerance = 0.2;

/// Least-squares slope of log(error) against log(h).
double fittedOrder(const std::vector<double>& h, const std::vector<double>& error) {
  const std::size_t n = h.size();
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    mx += std::log(h[i]) / n;
    my += std::log(error[i]) / n;
  }
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxy += (std::log(h[i]) - mx) * (std::log(error[i]) - my);
    sxx += (std::log(h[i]) - mx) * (std::log(h[i]) - mx);
  }
  return sxy / sxx;
}

/// Runs `stepN(N)` (which integrates over [0, T] in N steps and returns the error) for
/// N = n0, 2 n0, 4 n0, 8 n0 and returns the fitted order.
template <class StepN>
double measureOrder(int n0, StepN stepN) {
  std::vector<double> hs, errors;
  for (int N = n0; N <= 8 * n0; N *= 2) {
    hs.push_back(kT / N);
    errors.push_back(stepN(N));
    EXPECT_GT(errors.back(), 1e-13) << "error at N = " << N << " is in the round-off range";
  }
  const double order = fittedOrder(hs, errors);
  std::printf("    N from %d: errors", n0);
  for (double e : errors) std::printf(" %.3e", e);
  std::printf("  -> order %.3f\n", order);
  return order;
}

// Problem 1, a forced oscillator as a first-order system y = (x, v):
// x'' = -x + cos 2t, x(0) = 1, v(0) = 0; x = (4/3) cos t - (1/3) cos 2t. Explicit in t, so
// a stage evaluated at a wrong time shows up as a lost order.
void forced(double t, ode::ConstView<double, 2> y, ode::View<double, 2> dy) {
  dy << y[1], -y[0] + std::cos(2 * t);
}
Eigen::Vector2d forcedExact(double t) {
  return {4.0 / 3 * std::cos(t) - std::cos(2 * t) / 3,
          -4.0 / 3 * std::sin(t) + 2.0 / 3 * std::sin(2 * t)};
}

template <class Stepper>
double forcedError(Stepper stepper, int N) {
  Eigen::Vector2d y(1, 0);
  ode::Workspace<double> ws;
  const double h = kT / N;
  for (int i = 0; i < N; ++i) stepper(forced, i * h, h, y, ws);
  return (y - forcedExact(kT)).norm();
}

// Problem 2, for backward Euler: y' = A y + g(t) with A = [[-2, 1], [1, -2]] symmetric negative
// definite (so I - h A is SPD: conjugate gradients apply), g chosen so that y = (cos t, sin t).
const Eigen::Matrix2d kA = (Eigen::Matrix2d() << -2, 1, 1, -2).finished();
void symmetric(double t, ode::ConstView<double> y, ode::View<double> dy) {
  dy = kA * y + Eigen::Vector2d(2 * std::cos(t) - 2 * std::sin(t), 2 * std::sin(t));
}
Eigen::Vector2d symmetricExact(double t) { return {std::cos(t), std::sin(t)}; }

// Problem 3, a second-order system for ode::step: a forced damped oscillator
// x'' = -(17/16) x - v/2 + g(t), g = cos 2t - (47/16) sin 2t, whose solution is
// x = e^{-t/4} cos t + sin 2t (x(0) = 1, v(0) = 7/4). a depends on t, x and v.
void damped(double t, ode::ConstView<double> x, ode::ConstView<double> v, ode::View<double> a) {
  a = -(17.0 / 16) * x - 0.5 * v;
  a.array() += std::cos(2 * t) - 47.0 / 16 * std::sin(2 * t);
}
void dampedDadx(double, ode::ConstView<double>, ode::ConstView<double>, ode::ConstView<double> w,
                ode::View<double> out) {
  out = -(17.0 / 16) * w;
}
void dampedDadv(double, ode::ConstView<double>, ode::ConstView<double>, ode::ConstView<double> w,
                ode::View<double> out) {
  out = -0.5 * w;
}
double dampedError(ode::Method method, int N) {
  const ode::SecondOrderSystem system{
      .acceleration = damped, .dadx = dampedDadx, .dadv = dampedDadv};
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 1.0);
  Eigen::VectorXd v = Eigen::VectorXd::Constant(1, 1.75);
  ode::Workspace<double> ws;
  const double h = kT / N;
  for (int i = 0; i < N; ++i) ode::step(method, system, i * h, h, x, v, ws, {.tolerance = 1e-12});
  const double e = std::exp(-kT / 4);
  const double xe = e * std::cos(kT) + std::sin(2 * kT);
  const double ve = e * (-std::cos(kT) / 4 - std::sin(kT)) + 2 * std::cos(2 * kT);
  // Both components: an x error alone can cross zero as h varies (Verlet's does near N = 100).
  return std::hypot(x[0] - xe, v[0] - ve);
}

}  // namespace

TEST(Convergence, ExplicitEulerIsFirstOrder) {
  EXPECT_NEAR(measureOrder(40, [](int N) { return forcedError(ode::explicitEuler, N); }), 1.0,
              kOrderTolerance);
}

TEST(Convergence, MidpointIsSecondOrder) {
  EXPECT_NEAR(measureOrder(40, [](int N) { return forcedError(ode::midpoint, N); }), 2.0,
              kOrderTolerance);
}

TEST(Convergence, HeunIsSecondOrder) {
  EXPECT_NEAR(measureOrder(40, [](int N) { return forcedError(ode::heun, N); }), 2.0,
              kOrderTolerance);
}

TEST(Convergence, Rk4IsFourthOrder) {
  EXPECT_NEAR(measureOrder(10, [](int N) { return forcedError(ode::rk4, N); }), 4.0,
              kOrderTolerance);
}

TEST(Convergence, DormandPrinceFifthOrderSolutionAtFixedStepIsFifthOrder) {
  EXPECT_NEAR(measureOrder(10, [](int N) { return forcedError(ode::dormandPrince5, N); }), 5.0,
              kOrderTolerance);
}

TEST(Convergence, BackwardEulerDenseIsFirstOrder) {
  const auto jacobian = [](double, ode::ConstView<double>, ode::JacobianView<double> J) { J = kA; };
  const double order = measureOrder(40, [&](int N) {
    Eigen::VectorXd y = symmetricExact(0);
    ode::Workspace<double> ws;
    const double h = kT / N;
    for (int i = 0; i < N; ++i) {
      const ode::LinearSolveReport r = ode::backwardEuler(symmetric, jacobian, i * h, h, y, ws);
      EXPECT_TRUE(r.converged);
    }
    return (y - symmetricExact(kT)).norm();
  });
  EXPECT_NEAR(order, 1.0, kOrderTolerance);
}

TEST(Convergence, BackwardEulerConjugateGradientIsFirstOrder) {
  const auto jacobianTimes = [](double, ode::ConstView<double>, ode::ConstView<double> w,
                                ode::View<double> out) { out = kA * w; };
  const double order = measureOrder(40, [&](int N) {
    Eigen::VectorXd y = symmetricExact(0);
    ode::Workspace<double> ws;
    const double h = kT / N;
    for (int i = 0; i < N; ++i) {
      // 1e-12 keeps the solve's error ~1e-12 h far below the method's O(h^2) local error.
      const ode::LinearSolveReport r = ode::backwardEulerMatrixFree(symmetric, jacobianTimes, i * h,
                                                                    h, y, ws, {.tolerance = 1e-12});
      EXPECT_TRUE(r.converged);
      EXPECT_LE(r.iterations, 2);  // CG is exact after n = 2 iterations on a 2 x 2 SPD system
    }
    return (y - symmetricExact(kT)).norm();
  });
  EXPECT_NEAR(order, 1.0, kOrderTolerance);
}

TEST(Convergence, BackwardEulerBiCgStabIsFirstOrder) {
  const auto jacobianTimes = [](double, ode::ConstView<double>, ode::ConstView<double> w,
                                ode::View<double> out) { out = kA * w; };
  const double order = measureOrder(40, [&](int N) {
    Eigen::VectorXd y = symmetricExact(0);
    ode::Workspace<double> ws;
    const double h = kT / N;
    for (int i = 0; i < N; ++i)
      ode::backwardEulerMatrixFree(symmetric, jacobianTimes, i * h, h, y, ws,
                                   {.solver = ode::LinearSolver::BiCgStab, .tolerance = 1e-12});
    return (y - symmetricExact(kT)).norm();
  });
  EXPECT_NEAR(order, 1.0, kOrderTolerance);
}

// Every Method through the generic second-order entry point (the first-order methods on the
// stacked state (x, v)), against its theoretical order.
class SecondOrderConvergence : public testing::TestWithParam<ode::Method> {};

TEST_P(SecondOrderConvergence, MatchesTheoreticalOrder) {
  const ode::Method method = GetParam();
  // RK4 reaches 1e-8 by N = 80; the others stay in their asymptotic range from N = 40.
  const int n0 = ode::methodOrder(method) >= 4 ? 10 : 40;
  const double order = measureOrder(n0, [&](int N) { return dampedError(method, N); });
  EXPECT_NEAR(order, ode::methodOrder(method), kOrderTolerance) << ode::methodName(method);
}

INSTANTIATE_TEST_SUITE_P(AllMethods, SecondOrderConvergence, testing::ValuesIn(ode::kMethods),
                         [](const testing::TestParamInfo<ode::Method>& info) {
                           return std::string(ode::methodName(info.param));
                         });
