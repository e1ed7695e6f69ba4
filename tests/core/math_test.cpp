#include "inertia/core/math.h"

#include <cmath>
#include <numbers>
#include <random>
#include <type_traits>

#include <gtest/gtest.h>

#include "inertia/core/error.h"
#include "../draws.h"

using namespace inertia;

namespace {
// Machine epsilon of Real: float-build tolerances scale with it.
constexpr Real kEps = std::numeric_limits<Real>::epsilon();
}  // namespace

TEST(Skew, MatchesCrossProduct) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<Real> u(-10, 10);
  for (int i = 0; i < 100; ++i) {
    const auto draw = [&] { return u(rng); };
    Vec3 a = inertia::test::draw3<Vec3>(draw), b = inertia::test::draw3<Vec3>(draw);
    // Each component is a difference of two products of magnitude <= 100: error ~ 2 * 100 eps.
    EXPECT_LE((skew(a) * b - a.cross(b)).norm(), 400 * kEps);
    EXPECT_LE((skew(a) + skew(a).transpose()).norm(), 0);  // exactly antisymmetric
  }
}

TEST(Times, GivesEigensProductsBits) {
  // times() replaces `m * v` in the solver's passes without changing a recording: the same
  // products summed in the same order. Entries of mixed signs and magnitudes make the order
  // show: summed left to right instead, about a third of these components differ.
  std::mt19937 rng(2);
  std::uniform_real_distribution<Real> u(-1, 1), e(-6, 6);
  const auto draw = [&] { return u(rng) * std::pow(Real(10), e(rng)); };
  for (int i = 0; i < 1000; ++i) {
    Mat3 m;
    for (int k = 0; k < 9; ++k) m(k / 3, k % 3) = draw();
    const Vec3 v = inertia::test::draw3<Vec3>(draw);
    const Vec3 expected = m * v, got = times(m, v);
    for (int k = 0; k < 3; ++k) {
      if constexpr (std::is_same_v<Real, float>) {
        EXPECT_EQ(got(k), expected(k)) << "draw " << i << ", row " << k;
      } else {
        // Double: Eigen sums rows 0 and 1 in another order. Two sums of three products, each
        // within 2 eps of the sum of the products' magnitudes: 4 eps between them.
        const Real scale = m.row(k).cwiseAbs().dot(v.cwiseAbs());
        EXPECT_LE(std::abs(got(k) - expected(k)), 4 * kEps * scale) << "draw " << i;
      }
    }
  }
}

TEST(Rotation, ExactIntegrationOfConstantSpin) {
  // Spinning at w about z for time T rotates by angle w T about z.
  const Vec3 w(0, 0, 2);
  Quat q = Quat::Identity();
  for (int i = 0; i < 100; ++i) q = integrateRotationExact(q, w, Real(0.01));
  Quat expected(Eigen::AngleAxis<Real>(Real(2.0), Vec3::UnitZ()));
  // 100 compositions of unit quaternions, each rounding ~eps.
  EXPECT_LE(q.angularDistance(expected), 200 * kEps);
}

TEST(Rotation, FirstOrderIntegrationConvergesAndStaysUnit) {
  // The first-order update has a local error O(h^2): halving h halves the global angle error.
  const Vec3 w(1, -2, 0.5);
  const Real T = 1;
  Quat expected = quatFromRotationVector(w * T);
  auto errorFor = [&](int n) {
    Quat q = Quat::Identity();
    for (int i = 0; i < n; ++i) q = integrateRotation(q, w, T / Real(n));
    EXPECT_NEAR(q.norm(), 1, 10 * kEps);
    return double(q.angularDistance(expected));
  };
  double e1 = errorFor(10), e2 = errorFor(20);
  // Renormalising a constant-axis rotation leaves only the angle error tan^-1(|w|h/2) - |w|h/2,
  // which is O(h^3) per step, O(h^2) globally: the ratio is 4, less a relative (|w|h)^2 ~ 5%
  // from the next term of atan (9.9e-3 and 2.5e-3 rad here, ratio 3.98, far above float rounding).
  EXPECT_GT(e1, 0);
  EXPECT_NEAR(e1 / e2, 4.0, 0.1);
}

TEST(Rotation, RotationVectorRoundTrips) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<Real> u(-3, 3);
  for (int i = 0; i < 100; ++i) {
    Vec3 v = inertia::test::draw3<Vec3>([&] { return u(rng); });
    if (v.norm() >= std::numbers::pi_v<Real>) continue;  // the principal branch is |v| < pi
    EXPECT_LE((rotationVector(quatFromRotationVector(v)) - v).norm(), 100 * kEps);
  }
  EXPECT_EQ(rotationVector(Quat::Identity()), Vec3::Zero());
  EXPECT_TRUE(allFinite(quatFromRotationVector(Vec3::Zero())));
}

TEST(Transform, ComposesAndInverts) {
  Transform a{Vec3(1, 2, 3), Quat(Eigen::AngleAxis<Real>(Real(0.7), Vec3(1, 1, 0).normalized()))};
  Transform b{Vec3(-2, 0.5, 1), Quat(Eigen::AngleAxis<Real>(Real(-1.2), Vec3::UnitZ()))};
  Vec3 x(0.3f, -0.4f, 2);
  EXPECT_LE(((a * b).apply(x) - a.apply(b.apply(x))).norm(), 50 * kEps);
  EXPECT_LE((a.inverse().apply(a.apply(x)) - x).norm(), 50 * kEps);
  EXPECT_LE((a.applyInverse(a.apply(x)) - x).norm(), 50 * kEps);
}

TEST(Require, ThrowsInvalidArgumentWithTheMessage) {
  EXPECT_NO_THROW(require(true, "fine"));
  try {
    require(false, "mass must be > 0");
    FAIL() << "require(false) did not throw";
  } catch (const InvalidArgument& e) {
    EXPECT_STREQ(e.what(), "mass must be > 0");
  }
}
