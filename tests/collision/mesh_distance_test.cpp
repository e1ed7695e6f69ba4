// triangleDistance and meshDistance: analytic triangle pairs, an independent double-precision
// oracle (dense sampling against an exact point-triangle distance; brute force over every pair of
// triangles of two meshes), separated, touching and intersecting meshes, degenerate triangles.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "collision_test_util.h"
#include "inertia/collision/distance.h"
#include "inertia/core/error.h"

using namespace inertia;
using namespace inertia::test;

namespace {

using Tri = TriangleD;

// ---- Double-precision oracle, written apart from the library ------------------------------

// Distance of a point to a triangle: the plane when the projection lies inside, else the
// nearest edge (a zero-area triangle is its edges).
double pointTriDistance(const Vec3d& p, const Tri& t) {
  double best = 1e300;
  for (std::size_t k = 0; k < 3; ++k)
    best = std::min(best, segmentDistance2(p, p, t[k], t[(k + 1) % 3]));
  const Vec3d n = (t[1] - t[0]).cross(t[2] - t[0]);
  if (n.squaredNorm() > 1e-30) {
    const Vec3d u = n.normalized();
    const Vec3d q = p - u.dot(p - t[0]) * u;
    bool inside = true;
    for (std::size_t k = 0; k < 3; ++k)
      inside = inside && (t[(k + 1) % 3] - t[k]).cross(q - t[k]).dot(n) >= 0;
    if (inside) best = std::min(best, (p - q).squaredNorm());
  }
  return std::sqrt(best);
}

// Exact triangle distance in double: 0 when the separating-axis gap says they intersect, else
// the nearest of the 6 vertex-face and 9 edge-edge pairs.
double triangleDistanceD(const Tri& a, const Tri& b) {
  if (triangleGap(a, b) <= 0) return 0;
  double best = 1e300;
  for (std::size_t k = 0; k < 3; ++k) {
    best = std::min({best, pointTriDistance(a[k], b), pointTriDistance(b[k], a)});
    for (std::size_t j = 0; j < 3; ++j)
      best = std::min(best, std::sqrt(segmentDistance2(a[k], a[(k + 1) % 3], b[j], b[(j + 1) % 3])));
  }
  return best;
}

// Dense sampling: the minimum over an n-step barycentric grid of each triangle of the exact
// distance to the other. An upper bound of the distance, above it by at most the grid spacing
// (the distance to a triangle is 1-Lipschitz): min(longest edge of A, of B) / n.
double sampledDistance(const Tri& a, const Tri& b, int n) {
  double best = 1e300;
  for (int pass = 0; pass < 2; ++pass) {
    const Tri& s = pass ? b : a;
    const Tri& o = pass ? a : b;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = double(i) / n, v = double(j) / n;
        best = std::min(best, pointTriDistance(s[0] + u * (s[1] - s[0]) + v * (s[2] - s[0]), o));
      }
  }
  return best;
}

double longestEdge(const Tri& t) {
  return std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
}

Tri toTri(const Vec3 (&t)[3]) { return {toD(t[0]), toD(t[1]), toD(t[2])}; }

TriangleDistance libDistance(const Vec3 (&a)[3], const Vec3 (&b)[3]) {
  return triangleDistance(a[0], a[1], a[2], b[0], b[1], b[2]);
}

// Coordinates of a few metres through a rotation: a few ulps of 4 m. The distance is
// 1-Lipschitz in the corners, so it inherits that error, plus the rounding of the feature
// computations (also a few ulps of the coordinates): 16 ulps of 4 m = 7.6e-6 m in float
// (2e-6 of the scale; 1.4e-14 m in double).
const double kMeshDistanceTol = 16 * kEps * 4;

Transform randomPoseAround(std::mt19937_64& rng, double spread) { return randomPose(rng, spread); }

Tri worldTri(const TriangleMesh& m, std::uint32_t t, const Transform& p) {
  Tri w;
  for (std::size_t k = 0; k < 3; ++k)
    w[k] = p.q.cast<double>() * toD(m.vertices()[m.triangles()[t][k]]) + toD(p.p);
  return w;
}

struct Brute {
  double distance = 1e300;
  std::uint32_t a = 0, b = 0;
};

// Every pair of triangles (pairs whose boxes are farther than the best so far skipped: still
// exhaustive), by the double oracle.
Brute bruteForce(const TriangleMesh& ma, const Transform& pa, const TriangleMesh& mb,
                 const Transform& pb) {
  std::vector<Tri> ta, tb;
  std::vector<std::pair<Vec3d, Vec3d>> boxA, boxB;
  const auto fill = [](const TriangleMesh& m, const Transform& p, std::vector<Tri>& t,
                       std::vector<std::pair<Vec3d, Vec3d>>& box) {
    for (std::uint32_t i = 0; i < m.triangles().size(); ++i) {
      t.push_back(worldTri(m, i, p));
      box.push_back({t.back()[0].cwiseMin(t.back()[1]).cwiseMin(t.back()[2]),
                     t.back()[0].cwiseMax(t.back()[1]).cwiseMax(t.back()[2])});
    }
  };
  fill(ma, pa, ta, boxA);
  fill(mb, pb, tb, boxB);
  Brute out;
  for (std::uint32_t i = 0; i < ta.size(); ++i)
    for (std::uint32_t j = 0; j < tb.size(); ++j) {
      const Vec3d gap = (boxB[j].first - boxA[i].second)
                            .cwiseMax(boxA[i].first - boxB[j].second)
                            .cwiseMax(Vec3d::Zero());
      if (gap.norm() > out.distance) continue;
      const double d = triangleDistanceD(ta[i], tb[j]);
      if (d < out.distance) out = {d, i, j};
    }
  return out;
}

}  // namespace

// ---- Triangle against triangle -------------------------------------------------------------

TEST(TriangleDistance, ParallelOffsetTrianglesAreTheirPlaneGapApart) {
  std::mt19937_64 rng(1);
  for (int it = 0; it < 20; ++it) {
    const Transform pose = randomPose(rng, 1);
    const double h = uniform(rng, 0.01, 0.5);
    // B over A's interior: the plane gap. B shifted sideways past A's edge x + y = 1: the
    // distance from B's corner to that edge (in the plane, 0.5 / sqrt 2 from (0.75, 0.75)).
    const Vec3 a[3] = {pose.apply(Vec3(0, 0, 0)), pose.apply(Vec3(1, 0, 0)),
                       pose.apply(Vec3(0, 1, 0))};
    const Vec3 b[3] = {pose.apply(Vec3(0.1f, 0.1f, Real(h))), pose.apply(Vec3(0.6f, 0.1f, Real(h))),
                       pose.apply(Vec3(0.1f, 0.6f, Real(h)))};
    EXPECT_NEAR(double(libDistance(a, b).distance), h, kMeshDistanceTol) << it;
    const Vec3 c[3] = {pose.apply(Vec3(0.75f, 0.75f, Real(h))),
                       pose.apply(Vec3(1.5f, 0.75f, Real(h))),
                       pose.apply(Vec3(0.75f, 1.5f, Real(h)))};
    const double side = 0.5 / std::sqrt(2.0);
    const TriangleDistance d = libDistance(a, c);
    EXPECT_NEAR(double(d.distance), std::sqrt(side * side + h * h), kMeshDistanceTol) << it;
    EXPECT_NEAR(double((d.pointB - d.pointA).norm()), double(d.distance), kMeshDistanceTol);
  }
}

TEST(TriangleDistance, SkewEdgesAreClosestAtTheirInteriors) {
  // A's edge on the x axis, the rest of A going down (y, z < 0); B's edge along y at height h,
  // the rest of B above it: the closest points are (0, 0, 0) and (0, 0, h), edge interiors.
  std::mt19937_64 rng(2);
  for (int it = 0; it < 20; ++it) {
    const Transform pose = randomPose(rng, 1);
    const double h = uniform(rng, 0.001, 0.5);
    const Vec3 a[3] = {pose.apply(Vec3(-1, 0, 0)), pose.apply(Vec3(1, 0, 0)),
                       pose.apply(Vec3(0, -1, -1))};
    const Vec3 b[3] = {pose.apply(Vec3(0, -1, Real(h))), pose.apply(Vec3(0, 1, Real(h))),
                       pose.apply(Vec3(0, 0, Real(h + 1)))};
    const TriangleDistance d = libDistance(a, b);
    EXPECT_NEAR(double(d.distance), h, kMeshDistanceTol) << it;
    EXPECT_NEAR((toD(d.pointA) - toD(pose.apply(Vec3::Zero()))).norm(), 0, 10 * kMeshDistanceTol)
        << it;
    EXPECT_NEAR((toD(d.pointB) - toD(pose.apply(Vec3(0, 0, Real(h))))).norm(), 0,
                10 * kMeshDistanceTol)
        << it;
  }
}

TEST(TriangleDistance, RandomPairsMatchDenseSamplingAndTheExactOracle) {
  std::mt19937_64 rng(3);
  const int n = 40;
  int crossing = 0;
  double worst = 0;
  for (int it = 0; it < 120; ++it) {
    Vec3 a[3], b[3];
    const Vec3 shift = randomVec(rng, -0.8, 0.8);
    for (int k = 0; k < 3; ++k) a[k] = randomVec(rng, -1, 1), b[k] = randomVec(rng, -1, 1) + shift;
    const Tri ta = toTri(a), tb = toTri(b);
    const TriangleDistance d = libDistance(a, b);
    const double exact = triangleDistanceD(ta, tb), sampled = sampledDistance(ta, tb, n);
    crossing += exact == 0;
    worst = std::max(worst, std::abs(double(d.distance) - exact));
    EXPECT_NEAR(double(d.distance), exact, kMeshDistanceTol) << it;
    // The sampled upper bound is at most one grid step above the true distance.
    EXPECT_LE(double(d.distance), sampled + kMeshDistanceTol) << it;
    EXPECT_GE(double(d.distance),
              sampled - std::min(longestEdge(ta), longestEdge(tb)) / n - kMeshDistanceTol)
        << it;
    // The points lie on their triangles and are `distance` apart.
    EXPECT_NEAR(pointTriDistance(toD(d.pointA), ta), 0, kMeshDistanceTol) << it;
    EXPECT_NEAR(pointTriDistance(toD(d.pointB), tb), 0, kMeshDistanceTol) << it;
    EXPECT_NEAR((toD(d.pointB) - toD(d.pointA)).norm(), double(d.distance), kMeshDistanceTol) << it;
  }
  EXPECT_GT(crossing, 5);  // both kinds of pair were exercised
  EXPECT_LT(crossing, 115);
  std::printf("triangle pairs: %d crossing, worst |error| %.3g m\n", crossing, worst);
}

TEST(TriangleDistance, ZeroAreaTrianglesNeverGiveNaN) {
  std::mt19937_64 rng(4);
  for (int it = 0; it < 40; ++it) {
    Vec3 b[3];
    for (int k = 0; k < 3; ++k) b[k] = randomVec(rng, -1, 1);
    const Vec3 p = randomVec(rng, -1, 1), q = randomVec(rng, -1, 1);
    // A point, a segment with a repeated corner, and a sliver (collinear corners).
    const Vec3 degenerate[3][3] = {{p, p, p}, {p, q, q}, {p, q, Real(0.5) * (p + q)}};
    for (const auto& a : degenerate) {
      for (int swap = 0; swap < 2; ++swap) {
        const TriangleDistance d = swap ? libDistance(b, a) : libDistance(a, b);
        ASSERT_TRUE(std::isfinite(d.distance) && d.pointA.allFinite() && d.pointB.allFinite())
            << it;
        EXPECT_NEAR(double(d.distance), triangleDistanceD(toTri(a), toTri(b)), kMeshDistanceTol)
            << it;
      }
    }
    const TriangleDistance both = libDistance(degenerate[1], degenerate[2]);
    EXPECT_TRUE(std::isfinite(both.distance)) << it;
    EXPECT_NEAR(double(both.distance), 0, kMeshDistanceTol) << it;  // same segment
  }
}

// ---- Mesh against mesh ---------------------------------------------------------------------

TEST(MeshDistance, MatchesBruteForceOverAllTrianglePairs) {
  const TriangleMesh ma = sphereMesh(1, 10, 20, 0.05, 1), mb = sphereMesh(0.7, 8, 16, 0.1, 2);
  const Collider a{Shape(ma)}, b{Shape(mb)};
  std::mt19937_64 rng(5);
  int separated = 0, intersecting = 0;
  double worstAbs = 0, worstRel = 0;
  for (int it = 0; it < 24; ++it) {
    const Transform pa = randomPoseAround(rng, 0.3), pb = randomPoseAround(rng, 1.6);
    const auto d = meshDistance(a, pa, b, pb);
    ASSERT_TRUE(d.has_value());
    const Brute brute = bruteForce(ma, pa, mb, pb);
    const double err = std::abs(double(d->distance) - brute.distance);
    worstAbs = std::max(worstAbs, err);
    if (brute.distance > 0.01) worstRel = std::max(worstRel, err / brute.distance);
    EXPECT_NEAR(double(d->distance), brute.distance, kMeshDistanceTol) << it;
    // The reported triangles are that far apart, the points lie on them.
    const Tri ta = worldTri(ma, d->triangleA, pa), tb = worldTri(mb, d->triangleB, pb);
    EXPECT_NEAR(triangleDistanceD(ta, tb), brute.distance, kMeshDistanceTol) << it;
    EXPECT_NEAR(pointTriDistance(toD(d->pointA), ta), 0, kMeshDistanceTol) << it;
    EXPECT_NEAR(pointTriDistance(toD(d->pointB), tb), 0, kMeshDistanceTol) << it;
    EXPECT_NEAR((toD(d->pointB) - toD(d->pointA)).norm(), double(d->distance), kMeshDistanceTol)
        << it;
    EXPECT_EQ(meshesOverlap(a, pa, b, pb), d->distance == 0) << it;
    (brute.distance > 0 ? separated : intersecting)++;
    // maxDistance: nothing below the distance, the same answer above it.
    if (d->distance > 0) {
      EXPECT_FALSE(meshDistance(a, pa, b, pb, d->distance * Real(0.99)).has_value()) << it;
      const auto capped = meshDistance(a, pa, b, pb, d->distance * Real(1.01));
      ASSERT_TRUE(capped.has_value()) << it;
      EXPECT_EQ(capped->distance, d->distance) << it;
    }
  }
  EXPECT_GE(separated, 4);
  EXPECT_GE(intersecting, 4);
  std::printf("%d separated, %d intersecting; worst |error| %.3g m, relative %.3g (d > 1 cm)\n",
              separated, intersecting, worstAbs, worstRel);
}

TEST(MeshDistance, SmallSphereInsideALargeOneIsAtItsSurfaceDistance) {
  // Surfaces, not volumes: a mesh inside a closed mesh is apart from it.
  const TriangleMesh ma = sphereMesh(1, 10, 20, 0.05, 1), mb = sphereMesh(0.3, 6, 12, 0.1, 3);
  const Collider a{Shape(ma)}, b{Shape(mb)};
  const Transform pb{Vec3(0.2f, -0.1f, 0.3f), Quat(Eigen::AngleAxis<Real>(1, Vec3::UnitX()))};
  const auto d = meshDistance(a, {}, b, pb);
  ASSERT_TRUE(d.has_value());
  EXPECT_GT(d->distance, Real(0.1));
  EXPECT_NEAR(double(d->distance), bruteForce(ma, {}, mb, pb).distance, kMeshDistanceTol);
}

TEST(MeshDistance, SeparatedTouchingAndIntersectingCubes) {
  const TriangleMesh cube = boxMesh(Vec3::Constant(Real(0.5)));
  const Collider a{Shape(cube)}, b{Shape(cube)};
  const auto at = [](double x, double y, double z) {
    return Transform{Vec3(Real(x), Real(y), Real(z)), Quat::Identity()};
  };
  // Apart by 0.25 along x: A's +x face and B's -x face.
  const auto apart = meshDistance(a, {}, b, at(1.25, 0.2, 0.1));
  ASSERT_TRUE(apart.has_value());
  EXPECT_NEAR(double(apart->distance), 0.25, kMeshDistanceTol);
  EXPECT_NEAR(double(apart->pointA.x()), 0.5, kMeshDistanceTol);
  EXPECT_NEAR(double(apart->pointB.x()), 0.75, kMeshDistanceTol);
  EXPECT_FALSE(meshDistance(a, {}, b, at(1.25, 0.2, 0.1), Real(0.2)).has_value());
  EXPECT_TRUE(meshDistance(a, {}, b, at(1.25, 0.2, 0.1), Real(0.3)).has_value());
  EXPECT_FALSE(meshesOverlap(a, {}, b, at(1.25, 0.2, 0.1)));
  // Corner to corner along the diagonal: sqrt(3) * 0.1.
  const auto corner = meshDistance(a, {}, b, at(1.1, 1.1, 1.1));
  ASSERT_TRUE(corner.has_value());
  EXPECT_NEAR(double(corner->distance), std::sqrt(3.0) * 0.1, kMeshDistanceTol);
  // Touching face to face: 0 within rounding.
  const auto touching = meshDistance(a, {}, b, at(1, 0.2, 0.1));
  ASSERT_TRUE(touching.has_value());
  EXPECT_NEAR(double(touching->distance), 0, kMeshDistanceTol);
  // Interpenetrating by 2 cm: the surfaces cross, distance exactly 0 at a common point.
  const auto crossing = meshDistance(a, {}, b, at(0.98, 0.2, 0.1));
  ASSERT_TRUE(crossing.has_value());
  EXPECT_EQ(crossing->distance, 0);
  EXPECT_EQ(crossing->pointA, crossing->pointB);
  EXPECT_NEAR(pointTriDistance(toD(crossing->pointA), worldTri(cube, crossing->triangleA, {})), 0,
              kMeshDistanceTol);
  EXPECT_NEAR(pointTriDistance(toD(crossing->pointB),
                               worldTri(cube, crossing->triangleB, at(0.98, 0.2, 0.1))),
              0, kMeshDistanceTol);
  EXPECT_TRUE(meshesOverlap(a, {}, b, at(0.98, 0.2, 0.1)));
}

TEST(MeshDistance, NonMeshCollidersAreRejected) {
  const Collider mesh{Shape(boxMesh(Vec3::Constant(Real(0.5))))};
  const Collider box{Shape(Box{Vec3::Constant(Real(0.5))})};
  EXPECT_THROW(meshDistance(mesh, {}, box, {}), InvalidArgument);
  EXPECT_THROW(meshDistance(box, {}, mesh, {}), InvalidArgument);
  EXPECT_THROW(meshDistance(mesh, {}, mesh, {}, Real(-1)), InvalidArgument);
}
