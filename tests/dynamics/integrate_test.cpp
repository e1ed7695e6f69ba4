// The rotational integrators against the conservation laws of torque-free motion.
#include "dynamics/integrate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <type_traits>

#include "../epsilon.h"

using namespace inertia;
using namespace inertia::detail;
using inertia::test::kRealEps;

namespace {
Real energy(const Quat& principal, const Vec3& moments, const Vec3& L) {
  const Vec3 Lb = principal.conjugate() * L;
  return Real(0.5) * (Lb.array().square() / moments.array()).sum();
}
}  // namespace

// The splitting moves the body, not L: |L_body| is an invariant of each sub-flow, and the
// energy error stays bounded at O((w h)^2) instead of drifting (here w h = 0.05).
TEST(Integrate, SplittingKeepsMomentumAndBoundsEnergy) {
  const Vec3 moments(1, 2, 3);
  const Vec3 L(Real(0.1), 4, Real(0.2));  // near the intermediate axis: the body tumbles
  Quat principal = Quat::Identity();
  const Real E0 = energy(principal, moments, L);
  Real worst = 0;
  for (int i = 0; i < 20000; ++i) {
    splitFreeRotation(principal, moments, L, Real(0.025));
    worst = std::max(worst, std::abs(energy(principal, moments, L) - E0) / E0);
  }
  EXPECT_NEAR(principal.norm(), 1, 8 * kRealEps);
  EXPECT_LT(worst, Real(0.01));  // (w h)^2 = 2.5e-3 times an O(1) factor
}

// A body with isotropic inertia feels no gyroscopic torque: w is unchanged.
TEST(Integrate, ImplicitGyroscopicLeavesASphereAlone) {
  const Quat q(Eigen::AngleAxis<Real>(Real(0.7), Vec3(1, 2, 3).normalized()));
  const Vec3 w(3, -1, 2);
  const Vec3 out = implicitGyroscopic(q, Mat3::Identity() * Real(0.4), w, Real(1.0 / 240.0));
  EXPECT_LT((out - w).norm(), 16 * kRealEps * w.norm());
}

// Backward Euler on Euler's equations is dissipative: a thin fast spinner never gains
// kinetic energy step after step (the explicit update would), and keeps spinning.
TEST(Integrate, ImplicitGyroscopicNeverGainsEnergy) {
  const Mat3 I = Vec3(Real(0.01), 1, 1).asDiagonal();  // a thin rod along x
  Quat q = Quat::Identity();
  Vec3 w(Real(50), Real(5), Real(0));
  const Real h = Real(1.0 / 240.0);
  auto ke = [&](const Quat& qq, const Vec3& ww) {
    const Vec3 wb = qq.conjugate() * ww;
    return Real(0.5) * wb.dot(I * wb);
  };
  Real previous = ke(q, w);
  for (int i = 0; i < 2000; ++i) {
    w = implicitGyroscopic(q, I, w, h);
    q = (q * Quat(Eigen::AngleAxis<Real>(h * (q.conjugate() * w).norm(),
                                         (q.conjugate() * w).normalized())))
            .normalized();
    const Real e = ke(q, w);
    ASSERT_LE(e, previous * (1 + 64 * kRealEps)) << "step " << i;
    previous = e;
  }
  EXPECT_GT(previous, 0);
}

// The gyroscopic step does not depend on the body's size: a rod of inertia scaled by 2^-44
// (5.7e-14 kg m^2, a half-millimetre capsule's) turns exactly as the full-size rod. Scaling by a
// power of two is exact, and so is every step after the Newton matrix's normalisation; without
// it, the determinant's bound (2^-132) fell below float's smallest normal and the step was
// dropped as singular.
TEST(Integrate, ImplicitGyroscopicOfATinyBodyIsTheLargeOnesScaled) {
  const Mat3 I = Vec3(Real(0.01), 1, 1).asDiagonal();
  const Quat q(Eigen::AngleAxis<Real>(Real(0.3), Vec3(1, -2, 1).normalized()));
  const Vec3 w(Real(50), Real(5), Real(0));
  const Real h = Real(1.0 / 240.0);
  const Vec3 large = implicitGyroscopic(q, I, w, h);
  EXPECT_GT((large - w).norm(), Real(0.1));  // h |w x I w| / I_z = 1 rad/s: the term acts
  EXPECT_EQ(implicitGyroscopic(q, I * std::ldexp(Real(1), -44), w, h), large);
}

// A Newton matrix J = I + h ([w] I - [I w]) singular within rounding keeps w for the substep, the
// explicit step without the gyroscopic term. First the world fuzz target's input
// world-micro-body-gyroscopic-nan, bit for bit: a light needle (principal moments about 6e-10,
// 6e-10 and 1e-17 kg m^2) spinning at 25 rad/s at h = 0.05 s, whose J is singular in float's
// rounding (two rows proportional); the old code's solve gave NaN for it. Then a J singular in
// any precision (no inertia at all).
TEST(Integrate, ImplicitGyroscopicOfASingularNewtonMatrixKeepsW) {
  const Quat q(-0x1.2ec9dep-2f, -0x1.15c61ap-1f, -0x1.2b4366p-1f, 0x1.0d456cp-1f);
  const Vec3 w(0x1.a905p+3f, -0x1.307ep+3f, -0x1.3a3dp+4f);
  Mat3 I;
  I << 0x1.4a339cp-31f, -0x1.2p-93f, 0, -0x1.2p-93f, 0x1.361e86p-32f, -0x1.49972p-32f, 0,
      -0x1.49972p-32f, 0x1.5e48b2p-32f;
  const Vec3 out = implicitGyroscopic(q, I, w, 0x1.99999ap-5f);
  EXPECT_TRUE(out.allFinite());
  if constexpr (std::is_same_v<Real, float>) {  // singular in float's rounding only
    EXPECT_EQ(out, w);
  }
  EXPECT_EQ(implicitGyroscopic(q, Mat3::Zero(), w, Real(0.05)), w);
}
