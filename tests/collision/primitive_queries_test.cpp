// Point queries and ray casts on plane, sphere, capsule, box and cylinder against exact signed
// distances and sphere-traced hits computed independently in double.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "collision_test_util.h"

using namespace inertia;
using namespace inertia::test;

namespace {

// Tolerance for lengths (m) near coordinates of magnitude `scale`: the library maps the point
// into the local frame (a quaternion rotation, ~20 roundings of values <= scale) and evaluates
// a few more operations; 64 eps * scale bounds that with room (float: 7.6e-6 per metre).
double lengthTol(double scale) { return 64 * kEps * scale; }

template <class S>
void checkPointQueries(const S& shape, std::uint64_t seed, int count = 4000) {
  std::mt19937_64 rng(seed);
  const Collider collider{Shape(shape)};
  int inside = 0, outside = 0;
  for (int k = 0; k < count; ++k) {
    const Transform pose = randomPose(rng);
    const Vec3 p = pose.apply(k % 2 ? randomVec(rng, -1, 1) : randomVec(rng, -2.5, 2.5));
    const PointQuery q = queryPoint(collider, pose, p);
    const Sdf exact = sdf(shape, toLocal(pose, p));
    const double tol = lengthTol(5);
    ASSERT_NEAR(q.distance, exact.distance, tol) << "point " << p.transpose();
    ASSERT_NEAR(q.normal.cast<double>().norm(), 1.0, 16 * kEps);
    // The closest point lies on the surface ...
    ASSERT_NEAR(sdf(shape, toLocal(pose, q.point)).distance, 0.0, tol);
    // ... and the point is reached from it along the normal: p - d n = closest.
    ASSERT_LE((toD(p) - q.distance * toD(q.normal) - toD(q.point)).norm(), 2 * tol);
    // Away from the medial axis, the normal is the exact gradient.
    if (std::abs(exact.distance) > 1e-2 && exact.distance > 0) {
      ASSERT_LE((toD(q.normal) - rotateD(pose, exact.gradient)).norm(), 1e3 * kEps / 1e-2);
    }
    (exact.distance < 0 ? inside : outside)++;
  }
  EXPECT_GT(inside, count / 20);
  EXPECT_GT(outside, count / 20);
}

template <class S>
void checkRayCasts(const S& shape, std::uint64_t seed, int count = 4000) {
  std::mt19937_64 rng(seed);
  const Collider collider{Shape(shape)};
  int hits = 0, misses = 0, fromInside = 0, skipped = 0;
  for (int k = 0; k < count; ++k) {
    const Transform pose = randomPose(rng);
    const Vec3 o = pose.apply(randomVec(rng, -3, 3));
    const Vec3 target = pose.apply(randomVec(rng, -1.2, 1.2));
    const Ray ray{o, Real(uniform(rng, 0.3, 1.6)) * (target - o), 1};
    const Vec3d od = toLocal(pose, ray.origin);
    const Vec3d dd = pose.q.cast<double>().conjugate() * toD(ray.direction);
    const double t = traceRay(shape, od, dd, ray.maxFraction);
    const auto hit = castRay(collider, pose, ray);
    if (t == -3) {
      ++skipped;
      continue;
    }
    if (t == -2) {
      ++fromInside;
      ASSERT_FALSE(hit) << "a ray from inside must report nothing";
      continue;
    }
    // Skip rays that graze the surface or end at it: there, hit-or-miss is decided by
    // rounding (the fraction of a tangent ray is only determined to sqrt(eps)).
    if (t >= 0) {
      const Sdf at = sdf(shape, od + t * dd);
      const double cosine = std::abs(at.gradient.dot(dd.normalized()));
      if (cosine < 1e-2 || std::abs(t - ray.maxFraction) < 1e-3) {
        ++skipped;
        continue;
      }
      ASSERT_TRUE(hit) << "missed a hit at " << t;
      // Fraction error: the library's length error lengthTol(5) plus the oracle's (tracing
      // stops within 1e-13 m of the surface), over the ray's speed |d| and the incidence.
      ASSERT_NEAR(hit->fraction, t, (lengthTol(5) + 1e-13) / (dd.norm() * cosine));
      ASSERT_NEAR(hit->normal.cast<double>().norm(), 1.0, 16 * kEps);
      ASSERT_LE((toD(hit->point) - (toD(ray.origin) + hit->fraction * toD(ray.direction))).norm(),
                lengthTol(5));
      // The normal is the surface gradient there and faces the origin.
      ASSERT_LE((toD(hit->normal) - rotateD(pose, at.gradient)).norm(), 1e3 * kEps / cosine);
      ASSERT_LT(hit->normal.dot(ray.direction), 0);
      ++hits;
    } else {
      // A miss: make sure it is not a grazing one before demanding no hit.
      if (hit) {
        const double closest = sdf(shape, od + double(hit->fraction) * dd).distance;
        ASSERT_LE(std::abs(closest), lengthTol(5)) << "reported a hit where the ray misses";
      }
      ++misses;
    }
  }
  EXPECT_GT(hits, count / 10);
  EXPECT_GT(misses, count / 20);
  EXPECT_LT(skipped, count / 50);
  (void)fromInside;
}

}  // namespace

TEST(PrimitivePointQuery, Sphere) { checkPointQueries(Sphere{Real(0.8)}, 1); }
TEST(PrimitivePointQuery, Capsule) { checkPointQueries(Capsule{Real(0.5), Real(0.7)}, 2); }
TEST(PrimitivePointQuery, Box) { checkPointQueries(Box{Vec3(Real(0.3), 1, Real(0.6))}, 3); }
TEST(PrimitivePointQuery, Cylinder) { checkPointQueries(Cylinder{Real(0.7), Real(0.4)}, 4); }

TEST(PrimitiveRayCast, Sphere) { checkRayCasts(Sphere{Real(0.8)}, 11); }
TEST(PrimitiveRayCast, Capsule) { checkRayCasts(Capsule{Real(0.5), Real(0.7)}, 12); }
TEST(PrimitiveRayCast, Box) { checkRayCasts(Box{Vec3(Real(0.3), 1, Real(0.6))}, 13); }
TEST(PrimitiveRayCast, Cylinder) { checkRayCasts(Cylinder{Real(0.7), Real(0.4)}, 14); }

TEST(PlaneQuery, PointAndRayMatchTheHalfSpace) {
  std::mt19937_64 rng(21);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 n = randomVec(rng, -1, 1).normalized();
    const Real offset = Real(uniform(rng, -1, 1));
    const Collider plane{Shape(Plane{n, offset})};
    const Transform pose = randomPose(rng);
    const Vec3d nw = rotateD(pose, toD(n));
    const double ow = double(offset) + nw.dot(toD(pose.p));
    const Vec3 p = randomVec(rng, -3, 3);
    const PointQuery q = queryPoint(plane, pose, p);
    ASSERT_NEAR(q.distance, nw.dot(toD(p)) - ow, lengthTol(6));
    ASSERT_LE((toD(q.normal) - nw).norm(), 16 * kEps);
    ASSERT_NEAR(nw.dot(toD(q.point)) - ow, 0.0, lengthTol(6));

    const Ray ray{p, randomVec(rng, -3, 3), 1};
    const auto hit = castRay(plane, pose, ray);
    const double d0 = nw.dot(toD(p)) - ow, rate = nw.dot(toD(ray.direction));
    const double t = -d0 / rate;
    if (d0 < -lengthTol(6)) {
      ASSERT_FALSE(hit) << "from inside the half-space";
    } else if (rate < -1e-3 && t < 1 - 1e-3 && d0 > lengthTol(6)) {
      ASSERT_TRUE(hit);
      ASSERT_NEAR(hit->fraction, t, lengthTol(6) / -rate);
      ASSERT_LE((toD(hit->normal) - nw).norm(), 16 * kEps);
    } else if (rate > 0 || t > 1 + 1e-3) {
      ASSERT_FALSE(hit);
    }
  }
}

// Fixed, documented answers at the degenerate points.
TEST(PrimitivePointQuery, DegeneratePointsHaveDocumentedNormals) {
  const Transform id;
  const PointQuery s = queryPoint(Collider(Sphere{1}), id, Vec3::Zero());
  EXPECT_EQ(s.distance, -1);
  EXPECT_EQ(s.normal, Vec3::UnitY());
  const PointQuery c = queryPoint(Collider(Capsule{Real(0.5), 1}), id, Vec3(0, Real(0.3), 0));
  EXPECT_EQ(c.distance, Real(-0.5));
  EXPECT_EQ(c.normal, Vec3::UnitX());
  const PointQuery ce = queryPoint(Collider(Capsule{Real(0.5), 1}), id, Vec3(0, 1, 0));
  EXPECT_EQ(ce.distance, Real(-0.5));
  const PointQuery b = queryPoint(Collider(Box{Vec3(1, 1, 1)}), id, Vec3::Zero());
  EXPECT_EQ(b.distance, -1);
  EXPECT_EQ(b.normal, Vec3::UnitX());
  EXPECT_EQ(b.point, Vec3::UnitX());
  const PointQuery corner = queryPoint(Collider(Box{Vec3(1, 2, 3)}), id, Vec3(1, 2, 3));
  EXPECT_EQ(corner.distance, 0);
  EXPECT_NEAR(corner.normal.norm(), 1, 4 * kEps);
  const PointQuery cyl = queryPoint(Collider(Cylinder{1, 2}), id, Vec3::Zero());
  EXPECT_EQ(cyl.distance, -1);
  EXPECT_EQ(cyl.normal, Vec3::UnitX());  // side (gap 1) nearer than the caps (gap 2)
  const PointQuery rim = queryPoint(Collider(Cylinder{1, 2}), id, Vec3(1, 2, 0));
  EXPECT_EQ(rim.distance, 0);
  EXPECT_NEAR(rim.normal.norm(), 1, 4 * kEps);
}

TEST(PrimitiveRayCast, ZeroDirectionAndNegativeMaxFractionGiveNothing) {
  const Collider ball{Shape(Sphere{1})};
  EXPECT_FALSE(castRay(ball, {}, Ray{Vec3(-5, 0, 0), Vec3::Zero(), 1}));
  EXPECT_FALSE(castRay(ball, {}, Ray{Vec3(-5, 0, 0), Vec3(10, 0, 0), -1}));
  const auto hit = castRay(ball, {}, Ray{Vec3(-5, 0, 0), Vec3(10, 0, 0), 1});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->fraction, Real(0.4), 4 * kEps);
  EXPECT_FALSE(castRay(ball, {}, Ray{Vec3(-5, 0, 0), Vec3(10, 0, 0), Real(0.39)}));
}

// A ray whose squared length overflows Real (the world fuzz target's: a vertex swept against a
// body thrown to 1e22 m/s, which put the origin at 3e34 m in the body's frame) made every
// primitive's roots NaN, and a NaN fraction passed their range tests: a hit at NaN. Such a
// ray reports no hit now, and a ray that fits still hits.
TEST(PrimitiveRayCast, RaysPastRealsRangeGiveNoHitRatherThanNaN) {
  const Real huge = std::numeric_limits<Real>::max() / 1e4f;
  const Vec3 far(-huge, huge / 8, huge / 2);
  for (const Shape& shape : {Shape(Sphere{Real(0.5)}), Shape(Capsule{Real(0.5), Real(0.5)}),
                             Shape(Box{Vec3::Constant(Real(0.5))}),
                             Shape(Cylinder{Real(0.5), Real(0.5)})}) {
    const Collider collider(shape);
    const auto hit = castRay(collider, {}, Ray{far, -far, 1});
    EXPECT_TRUE(!hit || (std::isfinite(hit->fraction) && hit->point.allFinite()));
    const auto near = castRay(collider, {}, Ray{Vec3(-5, 0, 0), Vec3(10, 0, 0), 1});
    ASSERT_TRUE(near);
    EXPECT_NEAR(near->fraction, Real(0.45), Real(1e-6));
  }
}

TEST(PrimitiveRayCast, OriginOnTheSurfaceMovingInHitsAtZero) {
  const Transform id;
  for (const Shape& s :
       {Shape(Sphere{1}), Shape(Box{Vec3(1, 1, 1)}), Shape(Capsule{1, 1}), Shape(Cylinder{1, 1})}) {
    const auto hit = castRay(Collider(s), id, Ray{Vec3(-1, 0, 0), Vec3(1, 0, 0), 1});
    ASSERT_TRUE(hit) << shapeTypeName(s.type());
    EXPECT_EQ(hit->fraction, 0);
    EXPECT_EQ(hit->normal, Vec3(-1, 0, 0));
    // Leaving from the surface is not a hit.
    EXPECT_FALSE(castRay(Collider(s), id, Ray{Vec3(-1, 0, 0), Vec3(-1, 0, 0), 1}));
  }
}

TEST(PrimitiveRayCast, RaysAlongFacesAndThroughEdges) {
  const Collider box{Shape(Box{Vec3(1, 1, 1)})};
  // Parallel to a face, in its plane: grazing, either answer is allowed, but finite.
  const auto graze = castRay(box, {}, Ray{Vec3(-3, 1, 0), Vec3(6, 0, 0), 1});
  if (graze) {
    EXPECT_TRUE(graze->normal.allFinite());
  }
  // Exactly through an edge and a corner.
  const auto edge = castRay(box, {}, Ray{Vec3(-3, -3, 0), Vec3(6, 6, 0), 1});
  ASSERT_TRUE(edge);
  EXPECT_NEAR(edge->fraction, Real(1) / 3, 4 * kEps);
  EXPECT_NEAR(edge->normal.norm(), 1, 4 * kEps);
  const auto corner = castRay(box, {}, Ray{Vec3(-3, -3, -3), Vec3(6, 6, 6), 1});
  ASSERT_TRUE(corner);
  EXPECT_NEAR(corner->fraction, Real(1) / 3, 4 * kEps);
  // Along the capsule's and cylinder's axes.
  const auto cap =
      castRay(Collider(Capsule{Real(0.5), 1}), {}, Ray{Vec3(0, 5, 0), Vec3(0, -10, 0), 1});
  ASSERT_TRUE(cap);
  EXPECT_NEAR(cap->fraction, Real(0.35), 4 * kEps);
  EXPECT_EQ(cap->normal, Vec3::UnitY());
  const auto cyl =
      castRay(Collider(Cylinder{Real(0.5), 1}), {}, Ray{Vec3(0, -5, 0), Vec3(0, 10, 0), 1});
  ASSERT_TRUE(cyl);
  EXPECT_NEAR(cyl->fraction, Real(0.4), 4 * kEps);
  EXPECT_EQ(cyl->normal, -Vec3::UnitY());
}
