// The triangle primitives against independent oracles, and no NaN anywhere: 10^5 random and
// degenerate queries (points on faces, edges, vertices; rays along faces, through edges).
#include <gtest/gtest.h>

#include "collision_test_util.h"
#include "inertia/collision/triangle.h"

using namespace inertia;
using namespace inertia::test;

// Oracle: the closest point is the minimum of |p - x| over a dense barycentric grid of the
// triangle (n = 200 steps): the grid is within h = max edge / n of every triangle point, so the
// grid minimum exceeds the true distance by at most h, and never undercuts it.
TEST(Triangle, ClosestPointMatchesDenseSampling) {
  std::mt19937_64 rng(1);
  for (int k = 0; k < 300; ++k) {
    const Vec3 a = randomVec(rng, -1, 1), b = randomVec(rng, -1, 1), c = randomVec(rng, -1, 1);
    const Vec3 p = randomVec(rng, -2, 2);
    const auto q = closestPointOnTriangle(p, a, b, c);
    const double d = (toD(p) - toD(q.point)).norm();
    const int n = 200;
    double best = 1e300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = double(i) / n, v = double(j) / n;
        const Vec3d x = toD(a) + u * (toD(b) - toD(a)) + v * (toD(c) - toD(a));
        best = std::min(best, (toD(p) - x).norm());
      }
    const double h = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()}) / n;
    ASSERT_LE(d, best + 16 * kEps * 4);
    ASSERT_GE(d, best - h - 16 * kEps * 4);
    // The point lies in the triangle's plane, within its edges (barycentric >= -tol).
    const Vec3d nrm = (toD(b) - toD(a)).cross(toD(c) - toD(a));
    ASSERT_NEAR(nrm.normalized().dot(toD(q.point) - toD(a)), 0, 64 * kEps);
  }
}

// Oracle: the plane crossing s = (n . (a - o)) / (n . d) in double, inside when the three
// sub-triangle orientations agree.
TEST(Triangle, RayMatchesPlaneCrossingAndBarycentrics) {
  std::mt19937_64 rng(2);
  int hits = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 a = randomVec(rng, -1, 1), b = randomVec(rng, -1, 1), c = randomVec(rng, -1, 1);
    const Vec3 o = randomVec(rng, -2, 2);
    const Vec3 offset = randomVec(rng, -0.5, 0.5);  // before the scale, as GCC drew them
    const Vec3 d = Real(uniform(rng, 0.5, 1.5)) * ((a + b + c) / 3 + offset - o);
    const Real t = intersectRayTriangle(o, d, 1, a, b, c);
    const Vec3d n = (toD(b) - toD(a)).cross(toD(c) - toD(a));
    const double rate = n.dot(toD(d));
    if (std::abs(rate) < 1e-3) continue;  // near-parallel: ill-conditioned
    const double s = n.dot(toD(a) - toD(o)) / rate;
    const Vec3d x = toD(o) + s * toD(d);
    const double w0 = n.dot((toD(b) - x).cross(toD(c) - x)),
                 w1 = n.dot((toD(c) - x).cross(toD(a) - x));
    const double w2 = n.dot((toD(a) - x).cross(toD(b) - x));
    const double margin = 1e3 * kEps * n.squaredNorm();
    const bool inside = w0 > margin && w1 > margin && w2 > margin;
    const bool outside = w0 < -margin || w1 < -margin || w2 < -margin;
    if (inside && s > 1e-3 && s < 1 - 1e-3) {
      ASSERT_GE(t, 0);
      ASSERT_NEAR(t, s, 1e3 * kEps / std::abs(rate) * n.norm());
      ++hits;
    } else if (outside || s < -1e-3 || s > 1 + 1e-3) {
      ASSERT_LT(t, 0);
    }
  }
  EXPECT_GT(hits, 500);
}

namespace {

bool finite(const PointQuery& q) {
  return std::isfinite(q.distance) && q.point.allFinite() && q.normal.allFinite() &&
         std::abs(q.normal.norm() - 1) < 1e-3;
}
bool finite(const std::optional<RayHit>& h, Real maxFraction) {
  return !h ||
         (std::isfinite(h->fraction) && h->point.allFinite() && h->normal.allFinite() &&
          std::abs(h->normal.norm() - 1) < 1e-3 && h->fraction >= 0 && h->fraction <= maxFraction);
}

// Points snapped to the features of a shape: coordinates rounded to a coarse lattice that
// contains the primitives' faces, edges and corners, so many land exactly on them.
Vec3 snapped(std::mt19937_64& rng) {
  Vec3 p = randomVec(rng, -2, 2);
  const int mode = int(rng() % 4);
  for (int i = 0; i < 3; ++i)
    if (mode == 0 || (mode == 1 && i == 0) || (mode == 2 && i != 1))
      p[i] = std::round(p[i] * 4) / 4;
  if (mode == 3) p = Vec3::Zero();
  return p;
}

}  // namespace

TEST(Robustness, NoNaNOnDegenerateAndRandomInputs) {
  std::mt19937_64 rng(3);
  std::vector<std::vector<Real>> heights{{0, 0, 0}, {0, 1, 0}, {0, 0, 0}};
  std::vector<Vec3> cube;
  for (int i = 0; i < 8; ++i)
    cube.emplace_back((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
  const std::vector<Collider> colliders{
      Collider(Plane{Vec3::UnitY(), 0}),
      Collider(Sphere{1}),
      Collider(Capsule{Real(0.5), Real(0.5)}),
      Collider(Box{Vec3(1, Real(0.5), Real(0.25))}),
      Collider(Cylinder{1, Real(0.5)}),
      Collider(Shape(ConvexHull(cube))),
      Collider(Shape(boxMesh(Vec3(1, Real(0.5), Real(0.25))))),
      Collider(Shape(HeightField(heights, Real(0.5)))),
      Collider(
          Shape(Compound({{Sphere{Real(0.5)}, Transform{Vec3(Real(0.5), 0, 0), Quat::Identity()}},
                          {Box{Vec3(Real(0.5), Real(0.5), Real(0.5))}, Transform{}}}))),
  };
  int queries = 0;
  for (const Collider& c : colliders) {
    for (int k = 0; k < 6000; ++k) {
      const Transform pose = k % 2 ? Transform{} : randomPose(rng, 0.5);
      const Vec3 p = pose.apply(snapped(rng));
      const PointQuery q = queryPoint(c, pose, p);
      ASSERT_TRUE(finite(q)) << shapeTypeName(c.type()) << " at " << p.transpose();
      const Vec3 to = snapped(rng);  // the right operand first, as GCC drew it
      Vec3 d = snapped(rng) - to;
      if (k % 7 == 0) d = Vec3(d.x(), 0, 0);  // axis-parallel, along faces
      const Ray ray{p, pose.rotate(d), Real(k % 3 == 0 ? 1 : 2)};
      const auto hit = castRay(c, pose, ray);
      ASSERT_TRUE(finite(hit, ray.maxFraction)) << shapeTypeName(c.type());
      queries += 2;
    }
  }
  EXPECT_GE(queries, 100000);
}
