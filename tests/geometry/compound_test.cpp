// Compounds: mass by the parallel-axis sum of moved children, bounds as the union.
#include <gtest/gtest.h>

#include "geometry_test_util.h"
#include "inertia/core/error.h"

using namespace inertia;
using namespace inertia::test;

TEST(CompoundMass, TwoBoxesSideBySideAreOneBox) {
  const Vec3 h(Real(0.5), Real(0.4), Real(0.3));
  const Compound pair({{Box{h}, Transform{Vec3(Real(-0.5), 0, 0), Quat::Identity()}},
                       {Box{h}, Transform{Vec3(Real(0.5), 0, 0), Quat::Identity()}}});
  const auto a = massProperties(Shape(pair), 700);
  const auto b = massProperties(Box{Vec3(1, h.y(), h.z())}, 700);
  // A few Real operations (sum, parallel-axis shift of exactly representable offsets).
  EXPECT_NEAR(a.mass, b.mass, 8 * kEps * b.mass);
  EXPECT_NEAR(a.volume, b.volume, 8 * kEps * b.volume);
  EXPECT_LE(a.centerOfMass.norm(), 8 * kEps);
  EXPECT_LE(relativeError(a.inertia.cast<double>(), b.inertia.cast<double>()), 16 * kEps);
  // And its bounds are the joint box.
  const Aabb bounds = localBounds(Shape(pair));
  EXPECT_LE((bounds.upper - Vec3(1, h.y(), h.z())).norm(), 4 * kEps);
  EXPECT_LE((bounds.lower + Vec3(1, h.y(), h.z())).norm(), 4 * kEps);
}

// Brute force, written independently of transformed()/combine(): every child's raw second
// moment about the origin J = integral rho x x^T is summed, then the total is re-centred.
// The rotated box's J comes from the hull of its moved corners (tetrahedron integrals in the
// world frame); the shifted sphere's from the textbook m (r^2 / 5 E + c c^T).
TEST(CompoundMass, RotatedChildrenMatchBruteForceSecondMoments) {
  std::mt19937_64 rng(31);
  const double rho = 250;
  for (int trial = 0; trial < 20; ++trial) {
    const Box box{randomVec(rng, 0.1, 1)};
    const Sphere ball{Real(0.4)};
    const Transform boxPose{randomVec(rng, -2, 2), randomRotation(rng)};
    const Transform ballPose{randomVec(rng, -2, 2), randomRotation(rng)};
    const Transform outer{randomVec(rng, -1, 1), randomRotation(rng)};
    // The compound is nested once to exercise composition of child transforms.
    const Compound inner({{box, boxPose}});
    const Compound compound({{Shape(inner), outer}, {ball, ballPose}});
    const auto p = massProperties(Shape(compound), Real(rho));

    std::vector<Vec3> corners;
    for (int i = 0; i < 8; ++i) {
      const Vec3& h = box.halfExtents;
      corners.push_back(
          (outer * boxPose)
              .apply(Vec3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z())));
    }
    auto secondMoment = [](const MassProperties& m) {  // J about the origin
      const Mat3d i = m.inertia.cast<double>();
      const Vec3d c = m.centerOfMass.cast<double>();
      return Mat3d(i.trace() / 2 * Mat3d::Identity() - i + double(m.mass) * c * c.transpose());
    };
    const auto boxWorld = massProperties(ConvexHull(corners), Real(rho));
    const double r = ball.radius, mBall = rho * 4.0 / 3.0 * kPi * r * r * r;
    const Vec3d cBall = ballPose.p.cast<double>();
    const double mass = double(boxWorld.mass) + mBall;
    const Vec3d com =
        (double(boxWorld.mass) * boxWorld.centerOfMass.cast<double>() + mBall * cBall) / mass;
    const Mat3d j = secondMoment(boxWorld) +
                    mBall * (r * r / 5 * Mat3d::Identity() + cBall * cBall.transpose()) -
                    mass * com * com.transpose();
    const Mat3d expected = j.trace() * Mat3d::Identity() - j;

    // The moved corners and the composed transforms carry ~ 8 eps |x| (|x| <= 6) rounding.
    EXPECT_NEAR(p.mass, mass, 256 * kEps * mass);
    EXPECT_LE((p.centerOfMass.cast<double>() - com).norm(), 256 * kEps * 6);
    EXPECT_LE(relativeError(p.inertia.cast<double>(), expected), 512 * kEps) << trial;
  }
}

TEST(CompoundErrors, InvalidCompoundsAreRejected) {
  EXPECT_THROW(Compound({}), InvalidArgument);
  EXPECT_THROW(Compound({{Sphere{1}, Transform{Vec3(0, 0, 0), Quat(2, 0, 0, 0)}}}),
               InvalidArgument);
  EXPECT_THROW(Compound({{Sphere{1}, Transform{Vec3(0, std::nanf(""), 0), Quat::Identity()}}}),
               InvalidArgument);
  // A static child makes the compound massless: asking is an error.
  const Compound withPlane({{Sphere{1}, {}}, {Plane{}, {}}});
  EXPECT_THROW(massProperties(Shape(withPlane), 1000), InvalidArgument);
  // Nearly unit quaternions are accepted and renormalised.
  const Compound ok({{Sphere{1}, Transform{Vec3::Zero(), Quat(Real(1.00001), 0, 0, 0)}}});
  EXPECT_NEAR(ok.children()[0].transform.q.norm(), 1, 4 * kEps);
}
