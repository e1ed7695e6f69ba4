// The mesh BVH and mesh queries: tree invariants, brute-force equality of ray casts, closest
// points and box overlaps, and signed distances of closed meshes.
#include <gtest/gtest.h>

#include <set>

#include "collision_test_util.h"
#include "inertia/collision/mesh_bvh.h"
#include "inertia/collision/triangle.h"

using namespace inertia;
using namespace inertia::test;

namespace {

bool boxContains(const MeshBvh::Node& n, const Vec3& lo, const Vec3& hi) {
  return (n.lower.array() <= lo.array()).all() && (hi.array() <= n.upper.array()).all();
}

// Every node's box contains its children (inner) or its triangles (leaf); every triangle sits
// in exactly one leaf; leaves hold 1..kMaxLeafSize triangles; the depth respects kMaxDepth.
void checkInvariants(const TriangleMesh& mesh, const MeshBvh& bvh) {
  const auto& nodes = bvh.nodes();
  std::vector<int> seen(mesh.triangles().size(), 0);
  std::vector<int> visited(nodes.size(), 0);
  std::vector<std::pair<std::uint32_t, int>> stack{{0u, 0}};
  int maxDepth = 0;
  while (!stack.empty()) {
    const auto [i, depth] = stack.back();
    stack.pop_back();
    ASSERT_LT(i, nodes.size());
    ++visited[i];
    maxDepth = std::max(maxDepth, depth);
    const auto& n = nodes[i];
    if (n.isLeaf()) {
      ASSERT_LE(n.count, MeshBvh::kMaxLeafSize);
      for (std::uint32_t s = n.index; s < n.index + n.count; ++s) {
        const std::uint32_t t = bvh.slotTriangles()[s];
        ++seen[t];
        for (int k = 0; k < 3; ++k) {
          const Vec3& v = mesh.vertices()[mesh.triangles()[t][k]];
          ASSERT_TRUE(boxContains(n, v, v));
          ASSERT_EQ(bvh.slotCorners(s)[k], v);
        }
      }
    } else {
      for (const std::uint32_t c : {i + 1, n.index}) {
        ASSERT_TRUE(boxContains(n, nodes[c].lower, nodes[c].upper));
        stack.push_back({c, depth + 1});
      }
    }
  }
  for (int s : seen) ASSERT_EQ(s, 1);
  for (int v : visited) ASSERT_EQ(v, 1);  // every node reachable once: a tree
  EXPECT_EQ(maxDepth, bvh.depth());
  EXPECT_LE(bvh.depth(), MeshBvh::kMaxDepth);
}

}  // namespace

TEST(MeshBvh, InvariantsOnRandomAndStructuredMeshes) {
  std::mt19937_64 rng(1);
  for (int n : {1, 2, 7, 100, 3000}) {
    const TriangleMesh mesh = randomSoup(rng, n, 5, 0.5);
    checkInvariants(mesh, MeshBvh(mesh));
  }
  const TriangleMesh sphere = sphereMesh(1, 30, 60);
  checkInvariants(sphere, MeshBvh(sphere));
  // Many triangles with the same centroid: no SAH split exists, median splits take over.
  std::vector<Vec3> v;
  std::vector<Triangle> t;
  for (int k = 0; k < 200; ++k) {
    const Real a = Real(k) * Real(0.01);
    v.push_back(Vec3(std::cos(a), std::sin(a), 0));
    v.push_back(Vec3(-std::cos(a), -std::sin(a), 0));
    v.push_back(Vec3(0, 0, Real(1 + k)));
    v.push_back(Vec3(0, 0, -Real(1 + k)));
    const std::uint32_t b = std::uint32_t(4 * k);
    t.push_back({b, b + 1, b + 2});
    t.push_back({b, b + 1, b + 3});
  }
  const TriangleMesh same(v, t);
  checkInvariants(same, MeshBvh(same));
}

TEST(MeshBvh, RayCastsEqualBruteForce) {
  std::mt19937_64 rng(2);
  const TriangleMesh mesh = randomSoup(rng, 3000, 5, 0.6);
  const MeshBvh bvh(mesh);
  const auto& verts = mesh.vertices();
  int hits = 0;
  for (int k = 0; k < 5000; ++k) {
    const Vec3 o = randomVec(rng, -7, 7);
    Vec3 d = randomVec(rng, -6, 6) - o;
    if (k % 10 == 0) d = Vec3(d.x(), 0, 0);  // axis-parallel rays exercise the zero inverse
    const Real maxFraction = Real(uniform(rng, 0.2, 1.5));
    Real best = maxFraction;
    std::int64_t bestTri = -1;
    for (std::size_t t = 0; t < mesh.triangles().size(); ++t) {
      const auto& tri = mesh.triangles()[t];
      const Real s = intersectRayTriangle(o, d, best, verts[tri[0]], verts[tri[1]], verts[tri[2]]);
      if (s >= 0 && (bestTri < 0 || s < best)) {
        best = s;
        bestTri = std::int64_t(t);
      }
    }
    const auto hit = bvh.castRay(o, d, maxFraction);
    ASSERT_EQ(hit.has_value(), bestTri >= 0) << "ray " << k;
    if (!hit) continue;
    ++hits;
    // The same arithmetic on the same corners: the fraction is bit-identical.
    ASSERT_EQ(hit->fraction, best);
    // Same triangle, or another one hit at exactly the same fraction (a shared edge).
    if (hit->triangle != std::uint32_t(bestTri)) {
      const auto& tri = mesh.triangles()[hit->triangle];
      ASSERT_EQ(
          intersectRayTriangle(o, d, maxFraction, verts[tri[0]], verts[tri[1]], verts[tri[2]]),
          best);
    }
    Vec3 n = mesh.normals()[hit->triangle];
    if (n.dot(d) > 0) n = -n;
    ASSERT_EQ(hit->normal, n);
  }
  EXPECT_GT(hits, 1000);
}

TEST(MeshBvh, ClosestPointsEqualBruteForce) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 3; ++trial) {
    const TriangleMesh mesh = randomSoup(rng, 2000, 4, 0.5);
    const MeshBvh bvh(mesh);
    const auto& verts = mesh.vertices();
    for (int k = 0; k < 1000; ++k) {
      const Vec3 p = randomVec(rng, -8, 8);
      Real best = std::numeric_limits<Real>::infinity();
      for (const auto& tri : mesh.triangles()) {
        const auto c = closestPointOnTriangle(p, verts[tri[0]], verts[tri[1]], verts[tri[2]]);
        best = std::min(best, (p - c.point).squaredNorm());
      }
      const auto c = bvh.closestPoint(p);
      // Same function on the same corners: the minimum is identical.
      ASSERT_EQ(c.distanceSquared, best);
      const auto& tri = mesh.triangles()[c.triangle];
      const auto again = closestPointOnTriangle(p, verts[tri[0]], verts[tri[1]], verts[tri[2]]);
      ASSERT_EQ(again.point, c.point);
    }
  }
}

TEST(MeshBvh, BoxOverlapsEqualBruteForce) {
  std::mt19937_64 rng(4);
  const TriangleMesh mesh = randomSoup(rng, 2000, 5, 0.5);
  const MeshBvh bvh(mesh);
  for (int k = 0; k < 500; ++k) {
    const Vec3 c = randomVec(rng, -6, 6), h = randomVec(rng, 0, 1.5);
    const Aabb box{c - h, c + h};
    std::set<std::uint32_t> expected, got;
    for (std::size_t t = 0; t < mesh.triangles().size(); ++t) {
      Aabb tb;
      for (int i = 0; i < 3; ++i) tb.extend(mesh.vertices()[mesh.triangles()[t][i]]);
      if (tb.overlaps(box)) expected.insert(std::uint32_t(t));
    }
    std::size_t calls = 0;
    bvh.forEachOverlap(box, [&](std::uint32_t t) {
      got.insert(t);
      ++calls;
    });
    ASSERT_EQ(calls, got.size()) << "a triangle reported twice";
    ASSERT_EQ(got, expected);
  }
}

// A closed 12-triangle box mesh answers point queries like the Box (signed), also at
// points nearest to its edges and corners, where the pseudonormal decides the sign.
TEST(MeshQuery, ClosedBoxMeshEqualsBox) {
  std::mt19937_64 rng(5);
  const Vec3 h(Real(0.5), Real(0.8), Real(0.3));
  const Collider mesh{Shape(boxMesh(h))};
  ASSERT_TRUE(mesh.shape().get<TriangleMesh>().isClosed());
  const Collider box{Shape(Box{h})};
  const double tol = 64 * kEps * 5;
  for (int k = 0; k < 10000; ++k) {
    const Transform pose = randomPose(rng);
    const Vec3 p = pose.apply(randomVec(rng, -1.5, 1.5));
    const PointQuery a = queryPoint(mesh, pose, p), b = queryPoint(box, pose, p);
    ASSERT_NEAR(a.distance, b.distance, tol) << p.transpose();
    ASSERT_NEAR(a.normal.cast<double>().norm(), 1, 16 * kEps);
    ASSERT_LE((p - a.distance * a.normal - a.point).cast<double>().norm(), 2 * tol);
    if (b.distance > 1e-2) {
      ASSERT_LE((a.normal - b.normal).cast<double>().norm(), 1e3 * kEps / 1e-2);
    }
  }
  // Points near each corner and edge midpoint, just outside and just inside.
  for (int i = 0; i < 27; ++i) {
    const Vec3 dir(Real(i % 3 - 1), Real(i / 3 % 3 - 1), Real(i / 9 - 1));
    if (dir.isZero()) continue;
    for (const Real step : {Real(0.01), Real(-0.01)}) {
      const Vec3 p = dir.cwiseProduct(h) + step * dir.normalized();
      const PointQuery a = queryPoint(mesh, {}, p), b = queryPoint(box, {}, p);
      ASSERT_NEAR(a.distance, b.distance, tol) << p.transpose();
    }
  }
}

TEST(MeshQuery, ClosedMeshSignMatchesSphere) {
  std::mt19937_64 rng(6);
  const Collider mesh{Shape(sphereMesh(1, 24, 48))};
  const auto& m = mesh.shape().get<TriangleMesh>();
  ASSERT_TRUE(m.isClosed());
  for (std::size_t t = 0; t < m.triangles().size(); ++t)
    ASSERT_GT(m.normals()[t].dot(m.vertices()[m.triangles()[t][0]]), 0) << "inward triangle";
  // The polygon lies between radius cos(pi / 24) ~ 0.9914 and 1: points off that shell have the
  // sphere's sign.
  for (int k = 0; k < 5000; ++k) {
    const Vec3 p = randomVec(rng, -1.5, 1.5);
    const Real r = p.norm();
    if (std::abs(r - Real(0.995)) < Real(0.01)) continue;
    const PointQuery q = queryPoint(mesh, {}, p);
    ASSERT_EQ(q.distance < 0, r < 1) << p.transpose();
    ASSERT_NEAR(std::abs(q.distance), std::abs(r - 1), Real(0.012));
  }
}

TEST(MeshQuery, OpenMeshIsUnsignedAndRaysHitBothSides) {
  // A single square (two triangles) in the plane y = 0, normal +y.
  const TriangleMesh square({Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(1, 0, 1), Vec3(-1, 0, 1)},
                            {Triangle{0, 2, 1}, Triangle{0, 3, 2}});
  const Collider mesh{Shape(square)};
  ASSERT_FALSE(square.isClosed());
  const PointQuery below = queryPoint(mesh, {}, Vec3(Real(0.2), Real(-0.5), 0));
  EXPECT_NEAR(below.distance, Real(0.5), 4 * kEps);
  EXPECT_NEAR((below.normal - Vec3(0, -1, 0)).norm(), 0, 4 * kEps);
  const PointQuery on = queryPoint(mesh, {}, Vec3(Real(0.2), 0, Real(0.3)));
  EXPECT_NEAR(on.distance, 0, 4 * kEps);
  EXPECT_NEAR(on.normal.norm(), 1, 4 * kEps);
  const auto up = castRay(mesh, {}, Ray{Vec3(0, -1, 0), Vec3(0, 2, 0), 1});
  ASSERT_TRUE(up);
  EXPECT_NEAR(up->fraction, Real(0.5), 4 * kEps);
  EXPECT_EQ(up->normal, Vec3(0, -1, 0));
  const auto down = castRay(mesh, {}, Ray{Vec3(0, 1, 0), Vec3(0, -2, 0), 1});
  ASSERT_TRUE(down);
  EXPECT_EQ(down->normal, Vec3(0, 1, 0));
}

TEST(MeshQuery, PosedMeshRayMatchesPosedBox) {
  std::mt19937_64 rng(8);
  const Vec3 h(Real(0.5), Real(0.8), Real(0.3));
  const Collider mesh{Shape(boxMesh(h))};
  const Collider box{Shape(Box{h})};
  int hits = 0;
  for (int k = 0; k < 3000; ++k) {
    const Transform pose = randomPose(rng);
    const Vec3 o = pose.apply(randomVec(rng, -3, 3)), target = pose.apply(randomVec(rng, -1, 1));
    const Ray ray{o, Real(uniform(rng, 0.5, 1.5)) * (target - o), 1};
    if (queryPoint(box, pose, ray.origin).distance < Real(0.01))
      continue;  // the mesh is hit from inside
    const auto a = castRay(mesh, pose, ray), b = castRay(box, pose, ray);
    if (a.has_value() != b.has_value()) {
      const auto& one = a ? a : b;
      ASSERT_LT(std::abs(one->normal.dot(ray.direction)), 1e-3 * ray.direction.norm());
      continue;
    }
    if (!a) continue;
    ++hits;
    ASSERT_NEAR(a->fraction, b->fraction, 64 * kEps * 5 * 1e2 / ray.direction.norm());
  }
  EXPECT_GT(hits, 500);
}
