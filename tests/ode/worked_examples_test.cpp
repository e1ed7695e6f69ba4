// The worked examples of seed 001 ("ODE basics", Euler / mid-point / Runge-Kutta), reproduced
// digit for digit.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>

#include "inertia/ode/explicit.h"

namespace ode = inertia::ode;

namespace {

// dy/dx = -2x^3 + 12x^2 - 20x + 8.5, y(0) = 1; exact y = -0.5x^4 + 4x^3 - 10x^2 + 8.5x + 1.
void polynomial(double x, ode::ConstView<double, 1>, ode::View<double, 1> dydx) {
  dydx[0] = -2 * x * x * x + 12 * x * x - 20 * x + 8.5;
}

// dy/dx = 4 e^{0.8x} - 0.5 y, y(0) = 2.
void exponential(double x, ode::ConstView<double, 1> y, ode::View<double, 1> dydx) {
  dydx[0] = 4 * std::exp(0.8 * x) - 0.5 * y[0];
}

}  // namespace

// Every value below is a dyadic rational with a few significant bits (8.5 * 0.5, f(0.5) = 1.25,
// f(0.25) = 4.21875, ...), so each product and sum is exact in binary floating point; only
// RK4's final (h / 6) * sum rounds, once, hence EXPECT_DOUBLE_EQ (4 ulp) rather than equality.

TEST(WorkedExamples, EulerTwoStepsOfHalf) {
  Eigen::Matrix<double, 1, 1> y(1.0);
  ode::Workspace<double> ws;
  ode::explicitEuler(polynomial, 0.0, 0.5, y, ws);
  EXPECT_DOUBLE_EQ(y[0], 5.25);  // 1 + 8.5 * 0.5
  ode::explicitEuler(polynomial, 0.5, 0.5, y, ws);
  EXPECT_DOUBLE_EQ(y[0], 5.875);  // 5.25 + 1.25 * 0.5
}

TEST(WorkedExamples, MidpointOneStepOfHalf) {
  Eigen::Matrix<double, 1, 1> y(1.0);
  ode::Workspace<double> ws;
  ode::midpoint(polynomial, 0.0, 0.5, y, ws);
  EXPECT_DOUBLE_EQ(y[0], 3.109375);  // 1 + f(0.25, 3.125) * 0.5 = 1 + 4.21875 * 0.5
}

TEST(WorkedExamples, Rk4OneStepOfHalfIsExactOnAQuartic) {
  Eigen::Matrix<double, 1, 1> y(1.0);
  ode::Workspace<double> ws;
  ode::rk4(polynomial, 0.0, 0.5, y, ws);
  EXPECT_DOUBLE_EQ(y[0], 3.21875);
  // "RKn is exact up to polynomials of degree n": y(0.5) of the quartic solution.
  const double x = 0.5;
  EXPECT_DOUBLE_EQ(y[0], -0.5 * x * x * x * x + 4 * x * x * x - 10 * x * x + 8.5 * x + 1);
}

TEST(WorkedExamples, Rk4OneStepOfHalfOnExponentialMatchesTheDeckToSixDigits) {
  Eigen::Matrix<double, 1, 1> y(2.0);
  ode::Workspace<double> ws;
  ode::rk4(exponential, 0.0, 0.5, y, ws);
  // The deck prints 3.751699 from k1..k4 rounded to 6 decimals. Unrounded RK4 gives
  // 3.7516994999648 (in double, good to ~1e-15), which rounds to the same 6 decimals: it lies
  // within half a unit of the 6th decimal, 5e-7, of the deck's value.
  EXPECT_NEAR(y[0], 3.751699, 5e-7);
  EXPECT_EQ(std::round(y[0] * 1e6) / 1e6, 3.751699);
  // The deck's increment function phi = (y1 - y0) / h = 3.503399, also to 6 decimals.
  EXPECT_EQ(std::round((y[0] - 2.0) / 0.5 * 1e6) / 1e6, 3.503399);
}
