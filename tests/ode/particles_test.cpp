// Structure-of-arrays particle data integrated in place through std::span and Eigen::Map:
// 1000 independent oscillators x_i'' = -omega_i^2 x_i - c v_i stepped together give the same
// numbers as each stepped alone. Float data, as a particle system stores it.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <span>
#include <vector>

#include "inertia/ode/ode.h"

namespace ode = inertia::ode;

namespace {

constexpr int kParticles = 1000;
constexpr float kParticleH = 0.01f;
constexpr float kDamping = 0.1f;
constexpr int kParticleSteps = 200;

std::vector<float> omegaSquared() {
  std::vector<float> w2(kParticles);
  for (int i = 0; i < kParticles; ++i) w2[i] = 1.0f + 0.05f * static_cast<float>(i);
  return w2;
}

/// The acceleration of particles [first, first + n) of the full set (n = size of x).
struct Springs {
  const float* omega2;
  void operator()(float, ode::ConstView<float> x, ode::ConstView<float> v,
                  ode::View<float> a) const {
    a = -(ode::ConstView<float>(omega2, x.size()).array() * x.array()).matrix() - kDamping * v;
  }
};
struct SpringsDadx {
  const float* omega2;
  void operator()(float, ode::ConstView<float>, ode::ConstView<float>, ode::ConstView<float> w,
                  ode::View<float> out) const {
    out = -(ode::ConstView<float>(omega2, w.size()).array() * w.array()).matrix();
  }
};
struct SpringsDadv {
  void operator()(float, ode::ConstView<float>, ode::ConstView<float>, ode::ConstView<float> w,
                  ode::View<float> out) const {
    out = -kDamping * w;
  }
};

struct Particles {
  std::vector<float> x, v;
  Particles() : x(kParticles), v(kParticles) {
    for (int i = 0; i < kParticles; ++i) {
      x[i] = std::sin(0.1f * static_cast<float>(i));
      v[i] = std::cos(0.3f * static_cast<float>(i));
    }
  }
};

}  // namespace

class ParticleBatch : public testing::TestWithParam<ode::Method> {};

// Every operation of the explicit and second-order methods is element-wise (each result
// component is computed from the same component of its inputs by the same IEEE operations,
// vectorised or not; -ffp-contract=off forbids fusing), so batch and single runs agree
// exactly. Backward Euler's conjugate gradients couple the components through the Krylov
// iteration's dot products, so it agrees to its solve tolerance only (checked below).
TEST_P(ParticleBatch, SpanAndMapGiveTheSameNumbersAsOneParticleAtATime) {
  const ode::Method method = GetParam();
  const std::vector<float> w2 = omegaSquared();
  const ode::SecondOrderSystem system{
      .acceleration = Springs{w2.data()}, .dadx = SpringsDadx{w2.data()}, .dadv = SpringsDadv{}};
  const ode::LinearSolverOptions<float> linear{.tolerance = 1e-6f};

  Particles viaSpan, viaMap;
  ode::Workspace<float> wsSpan(kParticles), wsMap(kParticles);
  for (int n = 0; n < kParticleSteps; ++n) {
    const float t = static_cast<float>(n) * kParticleH;
    ode::step(method, system, t, kParticleH, std::span<float>(viaSpan.x),
              std::span<float>(viaSpan.v), wsSpan, linear);
    ode::step(method, system, t, kParticleH,
              Eigen::Map<Eigen::VectorXf>(viaMap.x.data(), kParticles),
              Eigen::Map<Eigen::VectorXf>(viaMap.v.data(), kParticles), wsMap, linear);
  }

  Particles alone;
  for (int i = 0; i < kParticles; ++i) {
    const ode::SecondOrderSystem one{
        .acceleration = Springs{&w2[i]}, .dadx = SpringsDadx{&w2[i]}, .dadv = SpringsDadv{}};
    ode::Workspace<float> ws(1);  // each particle its own workspace (Verlet keeps history)
    for (int n = 0; n < kParticleSteps; ++n)
      ode::step(method, one, static_cast<float>(n) * kParticleH, kParticleH,
                std::span<float>(&alone.x[i], 1), std::span<float>(&alone.v[i], 1), ws, linear);
  }

  for (int i = 0; i < kParticles; ++i) {
    ASSERT_EQ(viaSpan.x[i], viaMap.x[i]) << i;  // the same code path: always identical
    ASSERT_EQ(viaSpan.v[i], viaMap.v[i]) << i;
    if (method == ode::Method::BackwardEuler) {
      // The solve's relative residual <= 1e-6 on I - h^2 A_x - h A_v (condition number
      // < 1.01) bounds each step's dv error by ~1e-6 |dv|; over 200 steps, 2e-4 |v| at most,
      // plus float round-off (~200 * 1.2e-7 relative).
      ASSERT_NEAR(viaSpan.x[i], alone.x[i], 3e-4f) << i;
      ASSERT_NEAR(viaSpan.v[i], alone.v[i], 3e-4f) << i;
    } else {
      ASSERT_EQ(viaSpan.x[i], alone.x[i]) << ode::methodName(method) << " particle " << i;
      ASSERT_EQ(viaSpan.v[i], alone.v[i]) << ode::methodName(method) << " particle " << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllMethods, ParticleBatch, testing::ValuesIn(ode::kMethods),
                         [](const testing::TestParamInfo<ode::Method>& info) {
                           return std::string(ode::methodName(info.param));
                         });

// A sub-range of a particle buffer (the live particles of a pool) steps alone, in place, and
// leaves the rest untouched.
TEST(ParticleBatch, SubrangeOfABufferStepsInPlace) {
  const std::vector<float> w2 = omegaSquared();
  Particles all, copy;
  ode::Workspace<float> ws(kParticles);
  const std::span<float> x(all.x), v(all.v);
  ode::step(ode::Method::SymplecticEuler, Springs{w2.data()}, 0.0f, kParticleH, x.first(500),
            v.first(500), ws);
  for (int i = 0; i < kParticles; ++i) {
    if (i < 500) {
      const float vi = copy.v[i] + kParticleH * (-w2[i] * copy.x[i] - kDamping * copy.v[i]);
      ASSERT_EQ(all.v[i], vi);
      ASSERT_EQ(all.x[i], copy.x[i] + kParticleH * vi);
    } else {
      ASSERT_EQ(all.x[i], copy.x[i]);
      ASSERT_EQ(all.v[i], copy.v[i]);
    }
  }
}
