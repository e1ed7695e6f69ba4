// Convex hull queries: a hull of a box's corners answers as the box does; a hull of random
// points answers as brute force over its faces' triangles does.
#include <gtest/gtest.h>

#include "collision_test_util.h"
#include "inertia/collision/triangle.h"

using namespace inertia;
using namespace inertia::test;

namespace {
// Lengths near coordinates of ~5 m: the hull and the box route the same point through different
// formulas (face planes from Qhull versus halfExtents), each a few dozen roundings.
const double kHullTol = 64 * kEps * 5;
}  // namespace

TEST(HullQuery, BoxCornersHullEqualsBoxForPoints) {
  std::mt19937_64 rng(5);
  const Vec3 h(Real(0.4), Real(0.9), Real(0.6));
  const auto corners = boxCorners(h);
  const Collider hull{Shape(ConvexHull(corners))};
  const Collider box{Shape(Box{h})};
  for (int k = 0; k < 5000; ++k) {
    const Transform pose = randomPose(rng);
    const Vec3 p = pose.apply(randomVec(rng, -2, 2));
    const PointQuery a = queryPoint(hull, pose, p), b = queryPoint(box, pose, p);
    ASSERT_NEAR(a.distance, b.distance, kHullTol);
    ASSERT_LE((a.point - b.point).cast<double>().norm(), 2 * kHullTol);
    // Normals agree except where the nearest face of an inside point is ambiguous.
    const Vec3d local = toLocal(pose, p);
    const Vec3d gaps = toD(h) - local.cwiseAbs();
    std::array<double, 3> g{gaps.x(), gaps.y(), gaps.z()};
    std::sort(g.begin(), g.end());
    if (b.distance > 1e-2 || (b.distance < 0 && g[1] - g[0] > 1e-3)) {
      ASSERT_LE((a.normal - b.normal).cast<double>().norm(), 1e3 * kEps / 1e-3) << p.transpose();
    }
  }
}

TEST(HullQuery, BoxCornersHullEqualsBoxForRays) {
  std::mt19937_64 rng(6);
  const Vec3 h(Real(0.4), Real(0.9), Real(0.6));
  const Collider hull{Shape(ConvexHull(boxCorners(h)))};
  const Collider box{Shape(Box{h})};
  int hits = 0;
  for (int k = 0; k < 5000; ++k) {
    const Transform pose = randomPose(rng);
    const Vec3 o = pose.apply(randomVec(rng, -3, 3)), target = pose.apply(randomVec(rng, -1, 1));
    const Ray ray{o, Real(uniform(rng, 0.5, 1.5)) * (target - o), 1};
    const auto a = castRay(hull, pose, ray), b = castRay(box, pose, ray);
    if (a.has_value() != b.has_value()) {
      // Only a ray grazing an edge or ending on the surface may disagree.
      const auto& h1 = a ? a : b;
      const Real speed = ray.direction.norm();
      const bool endsOnSurface = std::abs(h1->fraction - 1) * speed < 1e2 * kHullTol;
      const bool grazes = std::abs(h1->normal.dot(ray.direction)) < 1e-3 * speed;
      ASSERT_TRUE(endsOnSurface || grazes) << "fraction " << h1->fraction;
      continue;
    }
    if (!a) continue;
    ++hits;
    ASSERT_NEAR(a->fraction, b->fraction, 1e2 * kHullTol / ray.direction.norm());
    if (std::abs(a->normal.dot(b->normal)) < 0.5) {
      // Different faces: the hit lies on an edge (within rounding).
      const Vec3d local = toLocal(pose, b->point);
      const Vec3d gaps = toD(h) - local.cwiseAbs();
      int onFace = 0;
      for (int i = 0; i < 3; ++i) onFace += std::abs(gaps[i]) < 1e2 * kHullTol;
      ASSERT_GE(onFace, 2);
    }
  }
  EXPECT_GT(hits, 1000);
}

// The exact distance to a convex polytope: outside, the minimum over its faces' triangles;
// inside, minus the distance to the nearest face plane.
TEST(HullQuery, RandomHullsMatchBruteForceOverFaces) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec3> pts;
    for (int i = 0; i < 40; ++i) pts.push_back(randomVec(rng, -1, 1));
    const ConvexHull hullShape(pts);
    const Collider hull{Shape(hullShape)};
    const auto& verts = hullShape.vertices();
    for (int k = 0; k < 500; ++k) {
      const Vec3 p = randomVec(rng, -2.5, 2.5);
      const PointQuery q = queryPoint(hull, {}, p);
      double outside = std::numeric_limits<double>::infinity();
      double inside = -std::numeric_limits<double>::infinity();
      for (std::size_t f = 0; f < hullShape.faces().size(); ++f) {
        const auto loop = hullShape.faceEdges(f);
        inside = std::max(inside,
                          double(hullShape.faces()[f].normal.dot(p) - hullShape.faces()[f].offset));
        for (std::size_t e = 1; e + 1 < loop.size(); ++e) {
          const auto c = closestPointOnTriangle(p, verts[loop[0].origin], verts[loop[e].origin],
                                                verts[loop[e + 1].origin]);
          outside = std::min(outside, (p - c.point).cast<double>().norm());
        }
      }
      const double expected = inside > 0 ? outside : inside;
      ASSERT_NEAR(q.distance, expected, kHullTol) << p.transpose();
      ASSERT_NEAR(q.normal.cast<double>().norm(), 1, 16 * kEps);
      ASSERT_LE((p - q.distance * q.normal - q.point).cast<double>().norm(), 2 * kHullTol);

      // A ray from p: brute force over the face triangles, unless p is inside.
      const Ray ray{p, randomVec(rng, -3, 3), 1};
      const auto hit = castRay(hull, {}, ray);
      if (expected < -kHullTol) {
        ASSERT_FALSE(hit);
        continue;
      }
      if (expected < kHullTol) continue;  // on the surface: either answer
      Real best = 2;
      for (std::size_t f = 0; f < hullShape.faces().size(); ++f) {
        const auto loop = hullShape.faceEdges(f);
        for (std::size_t e = 1; e + 1 < loop.size(); ++e) {
          const Real t = intersectRayTriangle(ray.origin, ray.direction, ray.maxFraction,
                                              verts[loop[0].origin], verts[loop[e].origin],
                                              verts[loop[e + 1].origin]);
          if (t >= 0) best = std::min(best, t);
        }
      }
      if (best <= 1) {
        if (!hit) {
          // Only a grazing contact may be missed: the ray passes within rounding of an edge.
          const Vec3 x = ray.origin + best * ray.direction;
          ASSERT_LE(std::abs(queryPoint(hull, {}, x).distance), kHullTol);
          continue;
        }
        ASSERT_NEAR(hit->fraction, best, 1e2 * kHullTol / ray.direction.norm());
      } else if (hit) {
        ASSERT_LE(std::abs(queryPoint(hull, {}, hit->point).distance), 1e2 * kHullTol);
      }
    }
  }
}
