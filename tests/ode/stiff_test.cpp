// The stiff system of seed 002: x' = -x, y' = -k y with k = 10^4 and h = 0.1 (h k = 1000).
// Backward Euler's exact map is (x, y) -> (x / (1 + h), y / (1 + h k)): stable, monotone decay.
// Explicit Euler's is (x, y) -> ((1 - h) x, (1 - h k) y): |1 - h k| = 999, divergence.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "../epsilon.h"
#include "inertia/ode/ode.h"

namespace ode = inertia::ode;
using inertia::test::kDoubleEps;

namespace {

constexpr double kK = 1e4;
constexpr double kStiffH = 0.1;
constexpr int kStiffSteps = 20;  // (1 + h k)^-20 = 1e-60: far from underflow

void stiff(double, ode::ConstView<double, 2> y, ode::View<double, 2> dy) {
  dy << -y[0], -kK * y[1];
}
void stiffJacobian(double, ode::ConstView<double, 2>, ode::JacobianView<double, 2> J) {
  J(0, 0) = -1;  // J is zeroed before the call: only the non-zeros are set
  J(1, 1) = -kK;
}
void stiffJacobianTimes(double, ode::ConstView<double, 2>, ode::ConstView<double, 2> w,
                        ode::View<double, 2> out) {
  out << -w[0], -kK * w[1];
}

// y_{n+1} = y_n + dy with dy = -h k y_n / (1 + h k) cancels all but 1/1001 of y_n, which
// magnifies dy's few-eps rounding by (1 + h k): relative error ~4 (1 + h k) eps per step.
constexpr double kRelativeTolerance = 4 * (1 + kStiffH * kK) * kDoubleEps * kStiffSteps;

template <class Step>
void expectClosedFormDecay(Step step) {
  Eigen::Vector2d y(1, 1);
  ode::Workspace<double> ws;
  for (int n = 1; n <= kStiffSteps; ++n) {
    const Eigen::Vector2d before = y;
    step(y, ws, (n - 1) * kStiffH);
    const double x = std::pow(1 + kStiffH, -n), z = std::pow(1 + kStiffH * kK, -n);
    ASSERT_NEAR(y[0] / x, 1.0, kRelativeTolerance) << "step " << n;
    ASSERT_NEAR(y[1] / z, 1.0, kRelativeTolerance) << "step " << n;
    // Bounded and monotone toward 0: positive and strictly smaller every step.
    ASSERT_GT(y[0], 0);
    ASSERT_GT(y[1], 0);
    ASSERT_LT(y[0], before[0]);
    ASSERT_LT(y[1], before[1]);
  }
}

}  // namespace

TEST(Stiff, BackwardEulerDenseDecaysAsOneOverOnePlusHkToTheN) {
  expectClosedFormDecay([](Eigen::Vector2d& y, ode::Workspace<double>& ws, double t) {
    ASSERT_TRUE(ode::backwardEuler(stiff, stiffJacobian, t, kStiffH, y, ws).converged);
  });
}

// A Krylov solve is accurate in norm, not per component: once y has decayed below round-off of
// x (|y| < eps |x|, from step 5), y is noise of that size. So here the closed form is checked in
// norm, and the stiff component only for staying below the closed form plus that noise.
TEST(Stiff, BackwardEulerConjugateGradientDecaysAsOneOverOnePlusHkToTheN) {
  Eigen::Vector2d y(1, 1);
  ode::Workspace<double> ws;
  for (int n = 1; n <= kStiffSteps; ++n) {
    const double normBefore = y.norm();
    // I - h J = diag(1.1, 1001) is SPD with 2 distinct eigenvalues: CG is exact after 2
    // iterations, and a tolerance of 1e-14 makes it take them.
    const ode::LinearSolveReport r = ode::backwardEulerMatrixFree(
        stiff, stiffJacobianTimes, (n - 1) * kStiffH, kStiffH, y, ws, {.tolerance = 1e-14});
    ASSERT_TRUE(r.converged);
    ASSERT_LE(r.iterations, 2);
    const Eigen::Vector2d closed(std::pow(1 + kStiffH, -n), std::pow(1 + kStiffH * kK, -n));
    ASSERT_LE((y - closed).norm(), kRelativeTolerance * closed.norm()) << "step " << n;
    ASSERT_LE(std::abs(y[1]), closed[1] + kRelativeTolerance * closed.norm()) << "step " << n;
    ASSERT_LT(y.norm(), normBefore) << "step " << n;
  }
}

TEST(Stiff, ExplicitEulerDivergesBy999PerStep) {
  Eigen::Vector2d y(1, 1);
  ode::Workspace<double> ws;
  for (int n = 1; n <= kStiffSteps; ++n) {
    ode::explicitEuler(stiff, (n - 1) * kStiffH, kStiffH, y, ws);
    // y_n = (1 - h k)^n = (-999)^n: alternating sign, growing 999-fold; each step rounds
    // y - 1000 y once (relative 2 eps).
    ASSERT_NEAR(y[1] / std::pow(1 - kStiffH * kK, n), 1.0, 2 * kDoubleEps * n) << "step " << n;
  }
  EXPECT_GT(std::abs(y[1]), 1e59);  // 999^20 = 9.8e59
  // The slow component alone would be fine with this h: (1 - h)^n.
  EXPECT_NEAR(y[0] / std::pow(1 - kStiffH, kStiffSteps), 1.0, 2 * kDoubleEps * kStiffSteps);
}
