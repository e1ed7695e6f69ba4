// Height fields (DDA ray walk and local point search) against brute force over all cell
// triangles; compounds against the minimum over their children.
#include <gtest/gtest.h>

#include "collision_test_util.h"
#include "inertia/collision/triangle.h"

using namespace inertia;
using namespace inertia::test;

namespace {

HeightField randomField(std::mt19937_64& rng, std::size_t rows, std::size_t cols, Real spacing) {
  std::vector<std::vector<Real>> h(rows, std::vector<Real>(cols));
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t j = 0; j < cols; ++j)
      h[i][j] =
          Real(std::sin(0.3 * double(i)) + std::cos(0.4 * double(j)) + uniform(rng, -0.3, 0.3));
  return HeightField(h, spacing);
}

}  // namespace

TEST(HeightFieldQuery, RayCastsEqualBruteForceOverCells) {
  std::mt19937_64 rng(1);
  const HeightField field = randomField(rng, 23, 31, Real(0.5));
  const Collider collider{Shape(field)};
  const Vec3 extent(Real(30 * 0.5), 0, Real(22 * 0.5));
  int hits = 0;
  for (int k = 0; k < 3000; ++k) {
    Vec3 o = randomVec(rng, -2, 17);
    o.z() = Real(uniform(rng, -2, 13));
    o.y() = Real(uniform(rng, -2, 4));
    Vec3 target = randomVec(rng, 0, 15);
    target.z() = Real(uniform(rng, 0, 11));
    target.y() = Real(uniform(rng, -1.5, 1.5));
    Vec3 d = (target - o) * Real(uniform(rng, 0.5, 2));
    if (k % 10 == 0) d = Vec3(0, d.y(), 0);  // vertical rays
    if (k % 10 == 1) d.y() = 0;              // horizontal rays
    const Ray ray{o, d, 1};
    if (ray.direction.squaredNorm() == 0) continue;
    Real best = 1;
    bool found = false;
    Vec3 normal = Vec3::UnitY();
    for (std::size_t i = 0; i + 1 < field.rows(); ++i)
      for (std::size_t j = 0; j + 1 < field.cols(); ++j)
        for (const auto& t : field.cellTriangles(i, j)) {
          const Real s = intersectRayTriangle(o, d, best, t[0], t[1], t[2]);
          if (s >= 0 && (!found || s < best)) {
            best = s;
            found = true;
            normal = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
          }
        }
    const auto hit = castRay(collider, {}, ray);
    ASSERT_EQ(hit.has_value(), found) << "ray " << k;
    if (!hit) continue;
    ++hits;
    ASSERT_EQ(hit->fraction, best);  // same triangles, same arithmetic
    if (normal.dot(d) > 0) normal = -normal;
    // The normal is the hit triangle's, facing the origin (another triangle's only when the
    // ray meets a shared edge exactly, at the same fraction).
    ASSERT_NEAR(hit->normal.cast<double>().norm(), 1, 16 * kEps);
    ASSERT_LE(hit->normal.dot(d), 0);
    if (k % 10 >= 2) {
      ASSERT_LE((hit->normal - normal).norm(), 16 * kEps) << "ray " << k;
    }
  }
  EXPECT_GT(hits, 1000);
  (void)extent;
}

TEST(HeightFieldQuery, PointQueriesEqualBruteForce) {
  std::mt19937_64 rng(2);
  const HeightField field = randomField(rng, 15, 12, Real(0.7));
  const Collider collider{Shape(field)};
  const Transform pose = randomPose(rng);
  for (int k = 0; k < 3000; ++k) {
    Vec3 local(Real(uniform(rng, -1.5, 9)), Real(uniform(rng, -3, 4)),
               Real(uniform(rng, -1.5, 11)));
    const PointQuery q = queryPoint(collider, pose, pose.apply(local));
    const Vec3 p = pose.applyInverse(pose.apply(local));
    Real best = std::numeric_limits<Real>::infinity();
    for (std::size_t i = 0; i + 1 < field.rows(); ++i)
      for (std::size_t j = 0; j + 1 < field.cols(); ++j)
        for (const auto& t : field.cellTriangles(i, j))
          best = std::min(best, (p - closestPointOnTriangle(p, t[0], t[1], t[2]).point).norm());
    // Below the surface inside the footprint is inside: the sign from a vertical ray upward.
    const Real xMax = Real(11 * 0.7), zMax = Real(14 * 0.7);
    bool below = false;
    if (p.x() >= 0 && p.x() <= xMax && p.z() >= 0 && p.z() <= zMax) {
      for (std::size_t i = 0; i + 1 < field.rows() && !below; ++i)
        for (std::size_t j = 0; j + 1 < field.cols() && !below; ++j)
          for (const auto& t : field.cellTriangles(i, j))
            below |= intersectRayTriangle(p, Vec3(0, 100, 0), 1, t[0], t[1], t[2]) > 0;
    }
    const double tol = 64 * kEps * 12;  // coordinates up to ~12 m, one pose round trip
    if (best > tol) {
      ASSERT_EQ(q.distance < 0, below) << local.transpose();
    }
    ASSERT_NEAR(std::abs(q.distance), best, tol) << local.transpose();
    ASSERT_NEAR(q.normal.cast<double>().norm(), 1, 16 * kEps);
    ASSERT_LE((pose.apply(local) - q.distance * q.normal - q.point).cast<double>().norm(), 2 * tol);
  }
}

TEST(CompoundQuery, MinimumOverChildrenAndNearestHit) {
  std::mt19937_64 rng(3);
  const Transform ta{Vec3(-1, 0, 0), randomRotation(rng)},
      tb{Vec3(1, Real(0.2), 0), randomRotation(rng)};
  const Shape boxShape = Box{Vec3(Real(0.4), Real(0.5), Real(0.3))};
  const Shape capsuleShape = Capsule{Real(0.3), Real(0.6)};
  const Compound inner({{capsuleShape, tb}});
  const Collider compound{Shape(Compound({{boxShape, ta}, {Shape(inner), Transform{}}}))};
  const Collider box{boxShape}, capsule{capsuleShape};
  int hits = 0;
  for (int k = 0; k < 4000; ++k) {
    const Transform pose = randomPose(rng);
    const Vec3 p = pose.apply(randomVec(rng, -3, 3));
    const PointQuery q = queryPoint(compound, pose, p);
    const PointQuery a = queryPoint(box, pose * ta, p), b = queryPoint(capsule, pose * tb, p);
    const PointQuery& m = a.distance <= b.distance ? a : b;
    const double tol = 64 * kEps * 6;
    ASSERT_NEAR(q.distance, m.distance, tol);
    ASSERT_LE((q.point - m.point).cast<double>().norm(), 2 * tol);

    const Vec3 target = pose.apply(randomVec(rng, -1.5, 1.5));
    const Ray ray{p, Real(uniform(rng, 0.5, 1.5)) * (target - p), 1};
    const auto hit = castRay(compound, pose, ray);
    const auto ha = castRay(box, pose * ta, ray), hb = castRay(capsule, pose * tb, ray);
    if (a.distance < -tol || b.distance < -tol) {
      ASSERT_FALSE(hit) << "origin inside a child";
      continue;
    }
    if (a.distance < tol || b.distance < tol) continue;  // on a surface
    Real expected = 2;
    if (ha) expected = ha->fraction;
    if (hb) expected = std::min(expected, hb->fraction);
    ASSERT_EQ(hit.has_value(), expected <= 1);
    if (hit) {
      ++hits;
      ASSERT_NEAR(hit->fraction, expected, 1e2 * tol / ray.direction.norm());
    }
  }
  EXPECT_GT(hits, 300);
}
