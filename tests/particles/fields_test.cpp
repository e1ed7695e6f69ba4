#include "inertia/particles/fields.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "inertia/core/error.h"
#include "../draws.h"

using namespace inertia;

namespace {

// The acceleration the fields give one particle.
Vec3 accelerationOf(const std::vector<ForceField>& fields, const Vec3& x, const Vec3& v, Real m = 1,
                    Real t = 0) {
  Real xs[3] = {x.x(), x.y(), x.z()}, vs[3] = {v.x(), v.y(), v.z()}, a[3] = {0, 0, 0};
  applyFields(fields, FieldBatch{t, xs, vs, std::span<const Real>(&m, 1), a});
  return {a[0], a[1], a[2]};
}

constexpr Real kEps = std::numeric_limits<Real>::epsilon();

}  // namespace

TEST(Fields, DragAndWindFollowTheirLaws) {
  const Vec3 v(3, -4, 0);  // |v| = 5
  const Real m = 2;
  EXPECT_LE((accelerationOf({{LinearDragField{Real(0.5)}}}, Vec3::Zero(), v, m) - (-0.5f / m) * v).norm(), 10 * kEps);
  EXPECT_LE((accelerationOf({{QuadraticDragField{Real(0.5)}}}, Vec3::Zero(), v, m) - (-0.5f * 5 / m) * v).norm(), 50 * kEps);
  const Vec3 wind(1, 0, 0);
  EXPECT_LE((accelerationOf({{WindField{wind, 2}}}, Vec3::Zero(), v, m) - (-2 / m) * (v - wind)).norm(), 10 * kEps);
}

TEST(Fields, AttractorFalloffsAndCutoff) {
  AttractorField a{.position = Vec3(0, 0, 0), .strength = 8, .cutoff = 10};
  // Inverse square at r = 2: |a| = 8 / 4 = 2, towards the attractor.
  EXPECT_LE((accelerationOf({{a}}, Vec3(2, 0, 0), Vec3::Zero()) - Vec3(-2, 0, 0)).norm(), 10 * kEps);
  // Inside minDistance the magnitude is clamped to strength / minDistance^2.
  const Vec3 close = accelerationOf({{a}}, Vec3(0.01f, 0, 0), Vec3::Zero());
  EXPECT_NEAR(close.norm(), 8 / (0.05 * 0.05), 1e-2);
  // Beyond the cutoff: nothing. Negative strength repels.
  EXPECT_EQ(accelerationOf({{a}}, Vec3(11, 0, 0), Vec3::Zero()), Vec3::Zero());
  a.strength = -8;
  EXPECT_GT(accelerationOf({{a}}, Vec3(2, 0, 0), Vec3::Zero()).x(), 0);
  a.falloff = Falloff::Linear;
  a.strength = 3;
  EXPECT_LE((accelerationOf({{a}}, Vec3(0, 2, 0), Vec3::Zero()) - Vec3(0, -6, 0)).norm(), 10 * kEps);
}

TEST(Fields, RegionLimitsAField) {
  ForceField f{GravityField{Vec3(0, -10, 0)}, Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)}};
  EXPECT_EQ(accelerationOf({f}, Vec3(0, 0, 0), Vec3::Zero()), Vec3(0, -10, 0));
  EXPECT_EQ(accelerationOf({f}, Vec3(2, 0, 0), Vec3::Zero()), Vec3::Zero());
}

TEST(Fields, VortexHoldsAParticleMovingWithTheFlowOnItsCircle) {
  // Inside the core a particle moving at omega x r feels exactly the centripetal acceleration.
  VortexField v{.angularSpeed = 2, .coreRadius = 3, .tightness = 5};
  const Vec3 x(1.5f, 0.7f, 0), flow = Real(2) * Vec3::UnitY().cross(Vec3(1.5f, 0, 0));
  const Vec3 a = accelerationOf({{v}}, x, flow);
  EXPECT_LE((a - Vec3(-4 * 1.5f, 0, 0)).norm(), 100 * kEps);
  // Outside the core, omega falls as (core / r)^2.
  const Vec3 far(6, 0, 0), farFlow = Real(2 * 0.25) * Vec3::UnitY().cross(far);
  EXPECT_LE((accelerationOf({{v}}, far, farFlow) - Vec3(-0.25f * 0.25f * 4 * 6, 0, 0)).norm(), 100 * kEps);
}

TEST(Fields, TurbulenceIsDivergenceFree) {
  // Central differences of the flow: the divergence is zero up to O(d^2) truncation and
  // rounding ~ eps |a| / d; compare with the gradient's own size.
  const TurbulenceField t{.amplitude = 3, .scale = Real(0.7), .modes = 12, .seed = 9};
  std::mt19937 rng(5);
  std::uniform_real_distribution<Real> u(-5, 5);
  const Real d = Real(1e-2);
  for (int i = 0; i < 50; ++i) {
    const Vec3 x = inertia::test::draw3<Vec3>([&] { return u(rng); });
    Real divergence = 0, gradient = 0;
    for (int k = 0; k < 3; ++k) {
      Vec3 e = Vec3::Zero();
      e[k] = d;
      const Vec3 diff = (turbulenceAt(t, x + e, 0) - turbulenceAt(t, x - e, 0)) / (2 * d);
      divergence += diff[k];
      gradient += diff.norm();
    }
    ASSERT_GT(gradient, 0.1);
    EXPECT_LE(std::fabs(divergence), 0.01 * gradient) << "at " << x.transpose();
  }
}

TEST(Fields, RejectsBadParameters) {
  EXPECT_THROW(validate({LinearDragField{-1}}), InvalidArgument);
  EXPECT_THROW(validate({VortexField{.axis = Vec3::Zero()}}), InvalidArgument);
  EXPECT_THROW(validate({VortexField{.coreRadius = 0}}), InvalidArgument);
  EXPECT_THROW(validate({TurbulenceField{.modes = 0}}), InvalidArgument);
  EXPECT_THROW(validate({GravityField{Vec3(0, std::nanf(""), 0)}}), InvalidArgument);
  EXPECT_THROW(validate({CustomField{}}), InvalidArgument);
}
