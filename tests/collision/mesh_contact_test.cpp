// Contact manifolds against triangle meshes, height fields and compounds: resting cases against
// planes and analytic depths, the internal-edge ("ghost collision") correction on flat grids,
// real convex edges kept, a sphere in a concave bowl against queryPoint, compound sub-shapes,
// and mesh-mesh pairs of the dual BVH traversal against brute force over all triangle pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <cmath>
#include <set>
#include <utility>

#include "collision/contact_pairs.h"
#include "collision/mesh_contacts.h"
#include "collision/polyhedron.h"
#include "collision_test_util.h"
#include "inertia/collision/contact.h"
#include "inertia/collision/mesh_bvh.h"
#include "../sanitizer.h"

using namespace inertia;
using namespace inertia::test;

namespace {

// A normal "equal to the face normal within rounding": the library's merge threshold.
const double kNormalTol = 100 * kEps;

// A flat n x n grid of square cells of side `cell` in the plane y = 0, centred on the origin:
// 2 n^2 triangles, split along the same diagonal as a height field, normals +y.
TriangleMesh gridMesh(int n, double cell) {
  std::vector<Vec3> v;
  const double half = 0.5 * n * cell;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) v.emplace_back(Real(j * cell - half), 0, Real(i * cell - half));
  const auto id = [n](int i, int j) { return std::uint32_t(i * (n + 1) + j); };
  std::vector<Triangle> t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
    }
  return TriangleMesh(std::move(v), std::move(t));
}

// The same surface as a height field (rows along z, columns along x), posed at -half.
HeightField flatField(int n, double cell) {
  return HeightField(std::vector<std::vector<Real>>(std::size_t(n + 1),
                                                    std::vector<Real>(std::size_t(n + 1), 0)),
                     Real(cell));
}

double minSeparation(const std::vector<ContactManifold>& out) {
  double s = 1e300;
  for (const auto& m : out)
    for (int k = 0; k < m.pointCount; ++k) s = std::min(s, double(m.points[std::size_t(k)].separation));
  return s;
}

// Every normal within kNormalTol of `n`; every point on both surfaces (their point queries ~0),
// separation = (pB - pA) . normal.
void expectManifolds(const std::vector<ContactManifold>& out, const Vec3& n, const Collider& a,
                     const Transform& pa, const Collider& b, const Transform& pb,
                     const std::string& where) {
  for (const auto& m : out) {
    EXPECT_GE(double(m.normal.dot(n)), 1 - kNormalTol) << where << " normal " << m.normal.transpose();
    for (int k = 0; k < m.pointCount; ++k) {
      const ContactPoint& p = m.points[std::size_t(k)];
      EXPECT_NEAR(queryPoint(a, pa, p.pointA).distance, 0, kContactTol) << where;
      EXPECT_NEAR(queryPoint(b, pb, p.pointB).distance, 0, kContactTol) << where;
      EXPECT_NEAR((p.pointB - p.pointA).dot(m.normal), p.separation, kContactTol) << where;
    }
  }
}

const int kGrid = 10;
const double kCell = 0.2;  // the grid spans [-1, 1]^2

// ---- Ghost collisions on flat grids ---------------------------------------------------------

TEST(MeshContact, BoxOnFlatGridFeelsOnlyTheFaceNormal) {
  const Collider mesh{Shape(gridMesh(kGrid, kCell))};
  const Collider field{Shape(flatField(kGrid, kCell))};
  const Collider plane{Shape(Plane{Vec3::UnitY(), 0})};
  const Transform fieldPose = at(-1, 0, -1);
  const Vec3 h(Real(0.23), Real(0.15), Real(0.17));
  const Collider box{Shape(Box{h})};
  std::mt19937_64 rng(7);
  int cases = 0;
  std::size_t maxManifolds = 0;
  for (int it = 0; it < 300; ++it) {
    // Positions on vertices, on edges, and anywhere; yaw anything; depth 1..20 mm. Every third
    // case tilted about a horizontal axis (resting on an edge).
    double x = uniform(rng, -0.6, 0.6), z = uniform(rng, -0.6, 0.6);
    if (it % 4 == 0) x = kCell * std::round(x / kCell), z = kCell * std::round(z / kCell);
    if (it % 4 == 1) x = kCell * std::round(x / kCell);
    const double depth = uniform(rng, 0.001, 0.02);
    const Quat yaw = axisAngle(it % 5 == 0 ? 0 : uniform(rng, 0, 2 * M_PI), Vec3::UnitY());
    const double tilt = it % 3 == 2 ? uniform(rng, 0.1, 0.6) : 0;
    const Quat q = yaw * axisAngle(tilt, Vec3::UnitX());
    // The lowest point of the box above its centre: max over corners of -y.
    double lowest = 0;
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner((c & 1) ? h.x() : -h.x(), (c & 2) ? h.y() : -h.y(), (c & 4) ? h.z() : -h.z());
      lowest = std::max(lowest, -double((q * corner).y()));
    }
    const Transform pose = at(x, lowest - depth, z, q);
    const auto onPlane = collideAll(box, pose, plane, {});
    ASSERT_EQ(onPlane.size(), 1u);
    for (const auto& [target, targetPose] :
         {std::pair{&mesh, Transform{}}, std::pair{&field, fieldPose}}) {
      const auto out = collideAll(box, pose, *target, targetPose);
      const std::string where = "case " + std::to_string(it);
      ASSERT_FALSE(out.empty()) << where;
      expectManifolds(out, -Vec3::UnitY(), box, pose, *target, targetPose, where);
      EXPECT_NEAR(minSeparation(out), -depth, kContactTol) << where;
      // Equal normals merge: one manifold, as on the plane, with the plane's points when the box
      // lies flat (its four bottom corners).
      EXPECT_EQ(out.size(), 1u) << where;
      maxManifolds = std::max(maxManifolds, out.size());
      if (tilt == 0) {
        ASSERT_EQ(out[0].pointCount, 4) << where;
        for (int k = 0; k < 4; ++k) {
          double best = 1e300;
          for (int j = 0; j < 4; ++j)
            best = std::min(best, double((out[0].points[std::size_t(k)].pointA -
                                          onPlane[0].points[std::size_t(j)].pointA)
                                             .norm()));
          EXPECT_LT(best, kContactTol) << where;
        }
      }
      ++cases;
    }
  }
  EXPECT_EQ(cases, 600);
  EXPECT_EQ(maxManifolds, 1u);
}

// The uncorrected per-triangle manifolds of the same configurations do lean over the seams:
// the correction above has something to correct (otherwise the test could not fail).
TEST(MeshContact, RawTriangleManifoldsHaveGhostNormalsThatTheCorrectionRemoves) {
  const TriangleMesh grid = gridMesh(kGrid, kCell);
  const Collider sphere{Shape(Sphere{Real(0.3)})};
  int ghosts = 0;
  for (int i = 0; i <= 100; ++i) {
    const Transform pose = at(-0.5 + 0.01 * i, 0.29, 0.013);
    for (const Triangle& t : grid.triangles()) {
      const Vec3 tri[3] = {grid.vertices()[t[0]], grid.vertices()[t[1]], grid.vertices()[t[2]]};
      ContactManifold m;
      if (detail::collideTriangle(tri, sphere, pose, {}, m) && m.normal.y() < 1 - kNormalTol) ++ghosts;
    }
  }
  EXPECT_GT(ghosts, 100);
}

TEST(MeshContact, SphereAndCapsuleRollingAcrossSeamsFeelOnlyTheFaceNormal) {
  const Collider mesh{Shape(gridMesh(kGrid, kCell))};
  const Collider field{Shape(flatField(kGrid, kCell))};
  const Transform fieldPose = at(-1, 0, -1);
  const Real r = Real(0.3);
  const Collider sphere{Shape(Sphere{r})};
  const Collider capsule{Shape(Capsule{Real(0.1), Real(0.25)})};
  const double depth = 0.004;
  int checked = 0;
  for (int i = 0; i <= 200; ++i) {
    const double s = -0.5 + 0.005 * i;
    // Straight along x over a vertex row (z = 0), along x off the rows, and diagonally (through
    // the diagonal edges and the vertices).
    const double paths[3][2] = {{s, 0}, {s, 0.07}, {s, s * 0.9}};
    for (const auto& p : paths) {
      const Transform sp = at(p[0], r - depth, p[1]);
      // The capsule lying at a changing yaw, and standing upright.
      const Quat lying = axisAngle(3 * s, Vec3::UnitY()) * axisAngle(M_PI / 2, Vec3::UnitZ());
      const Transform cl = at(p[0], 0.1 - depth, p[1], lying);
      const Transform cu = at(p[0], 0.35 - depth, p[1]);
      for (const auto& [target, tp] : {std::pair{&mesh, Transform{}}, std::pair{&field, fieldPose}})
        for (const auto& [shape, pose] :
             {std::pair{&sphere, sp}, std::pair{&capsule, cl}, std::pair{&capsule, cu}}) {
          const auto out = collideAll(*shape, pose, *target, tp);
          const std::string where = "s " + std::to_string(s);
          ASSERT_EQ(out.size(), 1u) << where;
          expectManifolds(out, -Vec3::UnitY(), *shape, pose, *target, tp, where);
          EXPECT_NEAR(minSeparation(out), -depth, kContactTol) << where;
          ++checked;
        }
    }
  }
  EXPECT_EQ(checked, 201 * 3 * 2 * 3);
}

// ---- Real edges are kept ---------------------------------------------------------------------

TEST(MeshContact, ConvexEdgeAndCornerOfAMeshKeepTheirNormals) {
  const Collider cube{Shape(boxMesh(Vec3::Constant(Real(0.5))))};
  // A box's face pressed diagonally onto the cube's edge x = y = 0.5 (along z).
  const Vec3 h(Real(0.3), Real(0.2), Real(0.3));
  const Collider box{Shape(Box{h})};
  const Vec3 diag = Vec3(1, 1, 0).normalized();
  const double depth = 0.01;
  const Vec3 c = Vec3(Real(0.5), Real(0.5), 0) + Real(h.y() - depth) * diag;
  const Transform pose{c, axisAngle(-M_PI / 4, Vec3::UnitZ())};
  const auto out = collideAll(box, pose, cube, {});
  ASSERT_EQ(out.size(), 1u);  // the two triangles' equal edge normals merged
  expectManifolds(out, -diag, box, pose, cube, {}, "edge");
  ASSERT_EQ(out[0].pointCount, 2);
  for (int k = 0; k < 2; ++k) {
    const ContactPoint& p = out[0].points[std::size_t(k)];
    EXPECT_NEAR(p.separation, -depth, kContactTol);
    EXPECT_NEAR(std::abs(p.pointB.z()), h.z(), kContactTol);  // the box face's ends along the edge
  }
  // A sphere on the cube's corner: the vertex normal along the diagonal.
  const Collider sphere{Shape(Sphere{Real(0.2)})};
  const Vec3 d3 = Vec3::Ones().normalized();
  const Transform sp{Vec3::Constant(Real(0.5)) + Real(0.2 - depth) * d3, Quat::Identity()};
  const auto corner = collideAll(sphere, sp, cube, {});
  ASSERT_EQ(corner.size(), 1u);
  expectManifolds(corner, -d3, sphere, sp, cube, {}, "corner");
  ASSERT_EQ(corner[0].pointCount, 1);
  EXPECT_NEAR(corner[0].points[0].separation, -depth, kContactTol);
}

// ---- Hull on a mesh, sphere in a bowl ------------------------------------------------------

TEST(MeshContact, HullRestsOnAMeshAsOnAPlane) {
  const Collider mesh{Shape(gridMesh(kGrid, kCell))};
  const Collider plane{Shape(Plane{Vec3::UnitY(), 0})};
  // A hexagonal prism (vertical sides, so its cross-section at the surface is its bottom face:
  // a mesh is a surface, and a sloped side would meet the triangles inside the bottom's outline).
  std::vector<Vec3> pts;
  for (int i = 0; i < 6; ++i) {
    const double a = M_PI / 3 * i;
    for (const double y : {-0.15, 0.15})
      pts.emplace_back(Real(0.3 * std::cos(a)), Real(y), Real(0.3 * std::sin(a)));
  }
  const Collider hull{Shape(ConvexHull(pts))};
  std::mt19937_64 rng(3);
  for (int it = 0; it < 100; ++it) {
    const double depth = uniform(rng, 0.001, 0.02);
    const Transform pose = at(uniform(rng, -0.5, 0.5), 0.15 - depth, uniform(rng, -0.5, 0.5),
                              axisAngle(uniform(rng, 0, 6.3), Vec3::UnitY()));
    const auto out = collideAll(hull, pose, mesh, {});
    const auto ref = collideAll(hull, pose, plane, {});
    ASSERT_EQ(out.size(), 1u);
    ASSERT_EQ(ref.size(), 1u);
    expectManifolds(out, -Vec3::UnitY(), hull, pose, mesh, {}, "hull");
    // Four points of the bottom hexagon spanning the same area as the plane's four (the two
    // sides of the deepest-farthest diagonal: points along the hexagon edge parallel to it tie).
    ASSERT_EQ(out[0].pointCount, 4);
    ASSERT_EQ(ref[0].pointCount, 4);
    const auto area = [](const ContactManifold& m) {
      const auto p = [&m](int k) { return toD(m.points[std::size_t(k)].pointA); };
      const Vec3d base = p(1) - p(0);
      return 0.5 * (base.cross(p(2) - p(0)).norm() + base.cross(p(3) - p(0)).norm());
    };
    EXPECT_NEAR(area(out[0]), area(ref[0]), kContactTol) << it;
    EXPECT_NEAR(area(out[0]), 0.6 * 0.3 * std::sin(M_PI / 3), kContactTol) << it;
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(out[0].points[std::size_t(k)].separation, -depth, kContactTol);
  }
}

// The lower half of a UV sphere of radius R with its normals turned inward: a concave bowl.
TriangleMesh bowlMesh(double R, int stacks, int slices) {
  std::vector<Vec3> v;
  v.emplace_back(0, Real(-R), 0);
  for (int i = 1; i <= stacks; ++i) {
    const double th = 0.5 * M_PI * i / stacks;  // from the bottom pole up to the equator
    for (int j = 0; j < slices; ++j) {
      const double ph = 2 * M_PI * j / slices;
      v.emplace_back(Real(R * std::sin(th) * std::cos(ph)), Real(-R * std::cos(th)),
                     Real(R * std::sin(th) * std::sin(ph)));
    }
  }
  const auto idx = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * slices + (j % slices)); };
  std::vector<Triangle> t;
  for (int j = 0; j < slices; ++j) t.push_back({0, idx(1, j + 1), idx(1, j)});
  for (int i = 1; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      t.push_back({idx(i, j), idx(i, j + 1), idx(i + 1, j + 1)});
      t.push_back({idx(i, j), idx(i + 1, j + 1), idx(i + 1, j)});
    }
  return TriangleMesh(std::move(v), std::move(t));
}

TEST(MeshContact, SphereInABowlMatchesTheClosestPointOfTheMesh) {
  const TriangleMesh bowl = bowlMesh(1, 8, 16);
  // The bowl's normals point inward (towards the centre): its edges are concave from inside.
  ASSERT_GT(-bowl.normals()[0].y(), -1);
  EXPECT_GT(bowl.normals()[0].y(), 0);
  int concave = 0;
  for (const auto& k : bowl.edgeKinds()) concave += int(std::count(k.begin(), k.end(), EdgeKind::Concave));
  EXPECT_GT(concave, 0);
  const Collider mesh{Shape(bowl)};
  const Real r = Real(0.25);
  const Collider sphere{Shape(Sphere{r})};
  std::mt19937_64 rng(11);
  for (int it = 0; it < 200; ++it) {
    // A centre about r above the bowl's surface along a random direction of the lower cap.
    const Vec3d dir = Vec3d(uniform(rng, -0.5, 0.5), -1, uniform(rng, -0.5, 0.5)).normalized();
    const double radial = 1 - 0.25 + uniform(rng, 0.0, 0.02);
    const Vec3 centre = (radial * dir).cast<Real>();
    const PointQuery q = queryPoint(mesh, {}, centre);
    const auto out = collideAll(sphere, at(centre.x(), centre.y(), centre.z()), mesh, {});
    if (q.distance >= r) {
      EXPECT_TRUE(out.empty());
      continue;
    }
    ASSERT_FALSE(out.empty()) << it;
    // The deepest point: the sphere's depth at the mesh's closest point, normal towards it.
    const ContactManifold* deepest = nullptr;
    for (const auto& m : out)
      if (!deepest || m.points[0].separation < deepest->points[0].separation) deepest = &m;
    EXPECT_NEAR(deepest->points[0].separation, q.distance - r, kContactTol) << it;
    EXPECT_LT((deepest->points[0].pointB - q.point).norm(), 20 * kContactTol) << it;
    EXPECT_GE(double(deepest->normal.dot((q.point - centre).normalized())), 1 - 1e3 * kNormalTol) << it;
    for (const auto& m : out) EXPECT_GE(m.points[0].separation, q.distance - r - kContactTol);
  }
}

// ---- Compounds -------------------------------------------------------------------------------

TEST(CompoundContact, TwoBoxesOnAPlaneAndOnABoxGiveOneManifoldPerChild) {
  const Box child{Vec3::Constant(Real(0.25))};
  const Collider twoBoxes{Shape(Compound({{Shape(child), at(-0.6, 0, 0)},
                                          {Shape(child), at(0.6, 0, 0, axisAngle(0.3, Vec3::UnitY()))}}))};
  const Collider plane{Shape(Plane{Vec3::UnitY(), 0})};
  const Collider ground{Shape(Box{Vec3(2, Real(0.5), 2)})};
  const double depth = 0.01;
  const Transform pose = at(0.1, 0.25 - depth, -0.2);
  for (const auto& [other, otherPose] : {std::pair{&plane, Transform{}}, std::pair{&ground, at(0, -0.5, 0)}}) {
    const auto out = collideAll(*other, otherPose, twoBoxes, pose);
    ASSERT_EQ(out.size(), 2u);
    std::set<std::uint32_t> subs;
    for (const auto& m : out) {
      subs.insert(m.subShapeB);
      EXPECT_EQ(m.subShapeA, 0u);
      EXPECT_EQ(m.pointCount, 4);
      EXPECT_GE(double(m.normal.y()), 1 - kNormalTol);
      for (int k = 0; k < 4; ++k)
        EXPECT_NEAR(m.points[std::size_t(k)].separation, -depth, kContactTol);
      // The points belong to the named child: within its box horizontally.
      const double cx = m.subShapeB == 0 ? -0.5 : 0.7;
      for (int k = 0; k < 4; ++k) EXPECT_LT(std::abs(m.points[std::size_t(k)].pointB.x() - cx), 0.37);
    }
    EXPECT_EQ(subs, (std::set<std::uint32_t>{0, 1}));
    // The other order is the flipped manifolds.
    const auto swapped = collideAll(twoBoxes, pose, *other, otherPose);
    ASSERT_EQ(swapped.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(swapped[i].subShapeA, out[i].subShapeB);
      EXPECT_EQ(swapped[i].normal, -out[i].normal);
    }
  }
  // Lifting one child off the plane (tilting the compound about z) leaves the other.
  const Transform tilted{Vec3(0, Real(0.25 - depth), 0), axisAngle(0.2, Vec3::UnitZ())};
  const auto one = collideAll(plane, {}, twoBoxes, tilted);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].subShapeB, 0u);  // +0.2 rad about z lowers the -x child
}

TEST(CompoundContact, CompoundOnAMeshAndOnACompoundCombineTheSubShapes) {
  const Box child{Vec3::Constant(Real(0.25))};
  const Collider twoBoxes{Shape(Compound({{Shape(child), at(-0.4, 0, 0)}, {Shape(child), at(0.4, 0, 0)}}))};
  const TriangleMesh grid = gridMesh(kGrid, kCell);
  const Collider mesh{Shape(grid)};
  const double depth = 0.01;
  const Transform pose = at(0.03, 0.25 - depth, 0.05);
  const auto out = collideAll(twoBoxes, pose, mesh, {});
  ASSERT_EQ(out.size(), 2u);
  std::set<std::uint32_t> children;
  for (const auto& m : out) {
    // The compound's key is the child index; the mesh's is the (merged manifold's) triangle.
    const std::uint32_t childIndex = m.subShapeA, tri = m.subShapeB;
    children.insert(childIndex);
    ASSERT_LT(tri, grid.triangles().size());
    // The merged manifold is named after the lowest triangle under that child (a triangle whose
    // centroid is within a cell of the child's footprint).
    const double cx = childIndex == 0 ? -0.37 : 0.43;
    double lowest = 1e300;
    for (std::uint32_t t = 0; t < grid.triangles().size(); ++t) {
      const Vec3 c = (grid.vertices()[grid.triangles()[t][0]] + grid.vertices()[grid.triangles()[t][1]] +
                      grid.vertices()[grid.triangles()[t][2]]) / 3;
      if (std::abs(c.x() - cx) < 0.25 + kCell && std::abs(c.z() - 0.05) < 0.25 + kCell) lowest = std::min(lowest, double(t));
    }
    EXPECT_EQ(double(tri), lowest);
    EXPECT_LE(double(m.normal.y()), -(1 - kNormalTol));
    EXPECT_NEAR(minSeparation({m}), -depth, kContactTol);
  }
  EXPECT_EQ(children, (std::set<std::uint32_t>{0, 1}));
  // Compound on compound: two boxes stacked on two boxes, child k on child k.
  const auto stacked = collideAll(twoBoxes, at(0, 0.5 - depth, 0), twoBoxes, {});
  ASSERT_EQ(stacked.size(), 2u);
  for (const auto& m : stacked) {
    EXPECT_EQ(m.subShapeA, m.subShapeB);
    EXPECT_NEAR(minSeparation({m}), -depth, kContactTol);
  }
  EXPECT_EQ(detail::compoundSubShape(2, 3, 5), 2u | (5u << 2));
  EXPECT_EQ(detail::compoundSubShape(0, 1, 7), 7u);
}

// ---- Mesh against mesh -------------------------------------------------------------------

// Brute force over all triangle pairs by the double gap: intersecting pairs (gap <= 0) must be
// reported, pairs apart by more than `spec` must not; in between the gap is only a lower bound
// of the distance, so a pair may or may not be within `spec` (the test checks the reported
// separation instead). Pairs within rounding of a threshold are accepted either way.
struct BrutePairs {
  std::set<std::pair<std::uint32_t, std::uint32_t>> sure, possible;
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> gap;
};
BrutePairs bruteForceTrianglePairs(const TriangleMesh& a, const Transform& pa,
                                   const TriangleMesh& b, const Transform& pb, double spec) {
  BrutePairs out;
  const auto world = [](const TriangleMesh& m, std::uint32_t t, const Transform& p) {
    std::array<Vec3d, 3> w;
    for (std::size_t k = 0; k < 3; ++k)
      w[k] = p.q.cast<double>() * toD(m.vertices()[m.triangles()[t][k]]) + toD(p.p);
    return w;
  };
  for (std::uint32_t i = 0; i < a.triangles().size(); ++i)
    for (std::uint32_t j = 0; j < b.triangles().size(); ++j) {
      const double gap = triangleGap(world(a, i, pa), world(b, j, pb));
      out.gap[{i, j}] = gap;
      if (gap < -kContactTol)
        out.sure.insert({i, j});
      else if (gap < spec + kContactTol)
        out.possible.insert({i, j});
    }
  return out;
}

TEST(MeshMeshContact, OverlappingCubesTouchDisjointOnesDoNot) {
  const TriangleMesh cube = boxMesh(Vec3::Constant(Real(0.5)));
  const Collider a{Shape(cube)}, b{Shape(cube)};
  const double depth = 0.02;
  const Transform pb = at(1 - depth, 0.2, 0.1);
  const auto out = collideAll(a, {}, b, pb);
  ASSERT_FALSE(out.empty());
  // The facing sides (A's +x, B's -x triangles) overlap by `depth` along +x. Other pairs
  // (A's top triangles crossed by B's side) are triangle-soup contacts, not checked for depth.
  double faceDepth = 1e300;
  for (const auto& m : out)
    if (m.normal.x() > 1 - kNormalTol) faceDepth = std::min(faceDepth, minSeparation({m}));
  EXPECT_NEAR(faceDepth, -depth, kContactTol);
  for (const auto& m : out)
    EXPECT_GE(minSeparation({m}), -0.2 - kContactTol);  // B's top is 0.2 above
  EXPECT_TRUE(collideAll(a, {}, b, at(1.05, 0.2, 0.1)).empty());
  EXPECT_TRUE(collideAll(a, {}, b, at(3, 2, 1)).empty());
  // Speculative: apart by 5 cm, reported with a 10 cm margin, nothing closer than 5 cm.
  const auto spec = collideAll(a, {}, b, at(1.05, 0.2, 0.1), Real(0.1));
  ASSERT_FALSE(spec.empty());
  EXPECT_GE(minSeparation(spec), 0.05 - kContactTol);
  double specFace = 1e300;
  for (const auto& m : spec)
    if (m.normal.x() > 1 - kNormalTol) specFace = std::min(specFace, minSeparation({m}));
  EXPECT_NEAR(specFace, 0.05, kContactTol);
}

TEST(MeshMeshContact, DualTraversalFindsTheSameTrianglePairsAsBruteForce) {
  const TriangleMesh ma = sphereMesh(1, 10, 20, 0.05, 1), mb = sphereMesh(0.7, 8, 16, 0.1, 2);
  const Collider a{Shape(ma)}, b{Shape(mb)};
  ASSERT_GT(a.meshBvh()->depth(), 3);
  std::mt19937_64 rng(5);
  int nonEmpty = 0;
  std::size_t sureTotal = 0, possibleTotal = 0;
  const int poses = test::samplesFor(25, 10);
  for (int it = 0; it < poses; ++it) {
    const Transform pa = randomPose(rng, 0.3), pb = randomPose(rng, 1.2);
    const Real spec = it % 2 ? Real(0.05) : Real(0);
    const auto out = collideAll(a, pa, b, pb, spec);
    std::set<std::pair<std::uint32_t, std::uint32_t>> found;
    for (const auto& m : out) {
      EXPECT_TRUE(found.insert({m.subShapeA, m.subShapeB}).second) << "pair reported twice";
      EXPECT_NEAR(m.normal.norm(), 1, 10 * kEps);
    }
    const BrutePairs brute = bruteForceTrianglePairs(ma, pa, mb, pb, spec);
    for (const auto& p : brute.sure) EXPECT_TRUE(found.count(p)) << it << " missed " << p.first << "," << p.second;
    for (const auto& p : found) EXPECT_TRUE(brute.sure.count(p) || brute.possible.count(p)) << it << " extra " << p.first << "," << p.second;
    // A reported pair apart by a positive gap is at least that far apart (distance >= gap).
    for (const auto& m : out) {
      const double g = brute.gap.at({m.subShapeA, m.subShapeB});
      if (g > kContactTol) {
        EXPECT_GE(minSeparation({m}), g - kContactTol) << it;
      }
    }
    sureTotal += brute.sure.size();
    possibleTotal += brute.possible.size();
    nonEmpty += !found.empty();
  }
  EXPECT_GT(nonEmpty, poses * 2 / 5);
  EXPECT_GT(sureTotal, std::size_t(poses * 4));
  std::printf("intersecting pairs %zu, within the speculative band %zu\n", sureTotal, possibleTotal);
}

// ---- Static pairs --------------------------------------------------------------------------

TEST(MeshContact, StaticPairsReportNothing) {
  const Collider mesh{Shape(gridMesh(2, 1))};
  const Collider field{Shape(flatField(2, 1))};
  const Collider plane{Shape(Plane{Vec3::UnitY(), 0})};
  EXPECT_TRUE(collideAll(mesh, {}, plane, {}).empty());
  EXPECT_TRUE(collideAll(mesh, {}, field, {}).empty());
  EXPECT_TRUE(collideAll(field, {}, mesh, {}).empty());
}

}  // namespace
