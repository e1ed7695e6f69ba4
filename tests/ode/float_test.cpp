// Single precision (Real = float by default): every stepper and controller instantiated with
// float states (VectorXf, fixed-size Vector3f, std::span<float>, Map<VectorXf>) builds without
// warnings and gives float-accurate results.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "inertia/core/types.h"
#include "inertia/ode/ode.h"

namespace ode = inertia::ode;

namespace {

constexpr float kFloatEps = std::numeric_limits<float>::epsilon();

void floatDecay(float, ode::ConstView<float> y, ode::View<float> dy) { dy = -y; }
void floatDecay3(float, ode::ConstView<float, 3> y, ode::View<float, 3> dy) { dy = -y; }

}  // namespace

TEST(Float, FirstOrderSteppersOnEveryStateType) {
  // y' = -y to t = 1 with h = 0.01: RK4's and DP5's truncation errors (~1e-10) are far below
  // float round-off, ~100 steps * a few eps relative, so 1e-5 is a round-off bound.
  const float exact = std::exp(-1.0f);
  ode::Workspace<float> ws(8);
  Eigen::VectorXf a = Eigen::VectorXf::Ones(4);
  Eigen::Vector3f b = Eigen::Vector3f::Ones();
  std::vector<float> c(5, 1.0f);
  std::vector<float> d(6, 1.0f);
  for (int i = 0; i < 100; ++i) {
    const float t = 0.01f * static_cast<float>(i);
    ode::rk4(floatDecay, t, 0.01f, a, ws);
    ode::dormandPrince5(floatDecay3, t, 0.01f, b, ws);
    ode::rk4(floatDecay, t, 0.01f, std::span<float>(c), ws);
    ode::rk4(floatDecay, t, 0.01f, Eigen::Map<Eigen::VectorXf>(d.data(), 6), ws);
  }
  EXPECT_NEAR(a[0], exact, 1e-5f);
  EXPECT_NEAR(b[2], exact, 1e-5f);
  EXPECT_NEAR(c[4], exact, 1e-5f);
  EXPECT_NEAR(d[5], exact, 1e-5f);

  // The remaining first-order steppers, once each: instantiation and a sane first step.
  Eigen::VectorXf y = Eigen::VectorXf::Ones(2);
  ode::explicitEuler(floatDecay, 0.0f, 0.1f, y, ws);
  ode::midpoint(floatDecay, 0.0f, 0.1f, y, ws);
  ode::heun(floatDecay, 0.0f, 0.1f, y, ws);
  ode::backwardEuler(
      floatDecay,
      [](float, ode::ConstView<float>, ode::JacobianView<float> J) {
        J.diagonal().setConstant(-1);
      },
      0.0f, 0.1f, y, ws);
  ode::backwardEulerMatrixFree(
      floatDecay,
      [](float, ode::ConstView<float>, ode::ConstView<float> w, ode::View<float> out) { out = -w; },
      0.0f, 0.1f, y, ws);
  // 0.9 * 0.905 * 0.905 / 1.1 / 1.1 in exact arithmetic.
  EXPECT_NEAR(y[0], 0.9f * 0.905f * 0.905f / 1.1f / 1.1f, 20 * kFloatEps);
}

TEST(Float, GenericStepOnSpansWithRealScalar) {
  // inertia::Real is float unless INERTIA_DOUBLE: the library's own scalar works too.
  using inertia::Real;
  const auto a = [](Real, ode::ConstView<Real> x, ode::ConstView<Real>, ode::View<Real> acc) {
    acc = -x;
  };
  const auto dadx = [](Real, ode::ConstView<Real>, ode::ConstView<Real>, ode::ConstView<Real> w,
                       ode::View<Real> out) { out = -w; };
  const ode::SecondOrderSystem system{.acceleration = a, .dadx = dadx, .dadv = ode::ZeroJacobian{}};
  for (ode::Method m : ode::kMethods) {
    std::vector<Real> x(9, Real(1)), v(9, Real(0));
    ode::Workspace<Real> ws(9);
    // A quarter period of x'' = -x in 157 steps of 0.01: x ~ cos(1.57) ~ 0 for every method
    // of order >= 1 (global error ~ h = 0.01, backward and explicit Euler's energy drift
    // factor (1 +- h^2)^157 ~ 1 +- 0.016 included).
    for (int n = 0; n < 157; ++n)
      ode::step(m, system, Real(0.01) * static_cast<Real>(n), Real(0.01), std::span<Real>(x),
                std::span<Real>(v), ws);
    EXPECT_NEAR(x[8], std::cos(Real(1.57)), Real(0.02)) << ode::methodName(m);
    EXPECT_NEAR(v[8], -std::sin(Real(1.57)), Real(0.02)) << ode::methodName(m);
  }
}

TEST(Float, AdaptiveControllers) {
  ode::DormandPrince45<float> dp;
  ode::StepDoubling<float> sd;
  const ode::AdaptiveOptions<float> options{.absoluteTolerance = 1e-5f, .relativeTolerance = 1e-5f};
  const auto r1 = dp.integrate(floatDecay, 0.0f, Eigen::VectorXf::Ones(3).eval(), 2.0f, options);
  std::vector<float> y(3, 1.0f);
  const auto r2 = sd.integrateInPlace(floatDecay, 0.0f, std::span<float>(y), 2.0f, options);
  ASSERT_TRUE(r1.stats.ok()) << r1.stats.message;
  ASSERT_TRUE(r2.ok()) << r2.message;
  // Contractive problem: global error <= sum of per-step tolerances (each <= 2e-5) over the
  // accepted steps, plus float round-off.
  EXPECT_NEAR(r1.y[0], std::exp(-2.0f), 2e-5f * static_cast<float>(r1.stats.accepted));
  EXPECT_NEAR(y[0], std::exp(-2.0f), 2e-5f * static_cast<float>(r2.accepted));
}
