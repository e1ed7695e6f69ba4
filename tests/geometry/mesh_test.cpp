// Triangle meshes: adjacency and edge classification, closedness, and mass properties.
#include "inertia/geometry/mesh.h"

#include <gtest/gtest.h>

#include "geometry_test_util.h"
#include "inertia/core/error.h"

using namespace inertia;
using namespace inertia::test;

namespace {

// A closed, star-shaped, non-convex mesh: a latitude-longitude sphere whose vertices are pushed
// to random radii along their directions (a radial graph, so it stays a simple surface), then
// scaled and moved. Triangles wind counter-clockwise seen from outside.
TriangleMesh blob(std::mt19937_64& rng, int lat, int lon, const Transform& xf = {}) {
  std::uniform_real_distribution<double> radius(0.6, 1.4);
  const Vec3d scale(1, 0.8, 1.2), offset(0.3, -0.2, 0.5);
  std::vector<Vec3> v;
  auto add = [&](const Vec3d& dir) {
    v.push_back(xf.apply((radius(rng) * dir.cwiseProduct(scale) + offset).cast<Real>()));
    return std::uint32_t(v.size() - 1);
  };
  const std::uint32_t top = add(Vec3d::UnitY()), bottom = add(-Vec3d::UnitY());
  auto ring = [&](int i, int j) { return std::uint32_t(2 + (i - 1) * lon + j % lon); };
  for (int i = 1; i < lat; ++i)
    for (int j = 0; j < lon; ++j) {
      const double theta = kPi * i / lat, phi = 2 * kPi * j / lon;
      add(Vec3d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
    }
  std::vector<Triangle> t;
  for (int j = 0; j < lon; ++j) {
    t.push_back({top, ring(1, j + 1), ring(1, j)});
    t.push_back({ring(lat - 1, j), ring(lat - 1, j + 1), bottom});
    for (int i = 1; i + 1 < lat; ++i) {
      const auto a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j + 1), d = ring(i + 1, j);
      t.push_back({a, b, c});
      t.push_back({a, c, d});
    }
  }
  return TriangleMesh(std::move(v), std::move(t));
}

// Generalised winding number (sum of signed solid angles / 4 pi, Van Oosterom and Strackee
// 1983): 1 inside a closed outward mesh, 0 outside. Plain doubles over a flat copy of the
// triangles: it runs ~10^7 times, and unoptimised Eigen (sanitizer builds) is slow.
class WindingNumber {
 public:
  explicit WindingNumber(const TriangleMesh& mesh) {
    for (const Triangle& t : mesh.triangles())
      for (std::uint32_t v : t)
        for (int k = 0; k < 3; ++k) corners_.push_back(mesh.vertices()[v][k]);
  }
  bool inside(const Vec3d& x) const {
    double total = 0;
    for (std::size_t i = 0; i < corners_.size(); i += 9) {
      const double* c = &corners_[i];
      const double ax = c[0] - x[0], ay = c[1] - x[1], az = c[2] - x[2];
      const double bx = c[3] - x[0], by = c[4] - x[1], bz = c[5] - x[2];
      const double cx = c[6] - x[0], cy = c[7] - x[1], cz = c[8] - x[2];
      const double la = std::sqrt(ax * ax + ay * ay + az * az);
      const double lb = std::sqrt(bx * bx + by * by + bz * bz);
      const double lc = std::sqrt(cx * cx + cy * cy + cz * cz);
      const double det =
          ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
      const double ab = ax * bx + ay * by + az * bz, ac = ax * cx + ay * cy + az * cz;
      const double bc = bx * cx + by * cy + bz * cz;
      total += 2 * std::atan2(det, la * lb * lc + ab * lc + ac * lb + bc * la);
    }
    return total > 2 * kPi;
  }

 private:
  std::vector<double> corners_;
};

TriangleMesh tetrahedron(bool flipOne = false) {
  std::vector<Vec3> v{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  std::vector<Triangle> t{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  if (flipOne) std::swap(t[3][0], t[3][1]);
  return TriangleMesh(v, t);
}

}  // namespace

TEST(MeshStructure, NormalsAndAdjacencyOfATetrahedron) {
  const TriangleMesh mesh = tetrahedron();
  EXPECT_TRUE(mesh.isClosed());
  for (std::size_t t = 0; t < 4; ++t) {
    // The outward normal points away from the centroid (1/4, 1/4, 1/4).
    const Vec3 a = mesh.vertices()[mesh.triangles()[t][0]];
    EXPECT_GT(mesh.normals()[t].dot(a - Vec3::Constant(Real(0.25))), 0);
    EXPECT_NEAR(mesh.normals()[t].norm(), 1, 4 * kEps);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(mesh.edgeKinds()[t][k], EdgeKind::Convex);
      const std::uint32_t u = mesh.neighbours()[t][k];
      ASSERT_NE(u, TriangleMesh::kNone);
      EXPECT_NE(u, t);
      // The neighbour lists this triangle back across the same edge.
      int back = 0;
      for (int m = 0; m < 3; ++m) back += mesh.neighbours()[u][m] == t;
      EXPECT_EQ(back, 1);
    }
  }
  // Same solid as the hull of its corners: volume 1/6 (both are Real roundings of a double sum).
  const auto p = massProperties(mesh, 1);
  EXPECT_NEAR(p.volume, 1.0 / 6, 4 * kEps);
}

TEST(MeshStructure, FoldedPairIsConvexConcaveOrFlat) {
  // A lies in the plane y = 0 (normal +y); B shares A's edge (0,0,0)-(1,0,0) and rises to an
  // apex at height h: above A's plane (h > 0) is a valley, below a ridge, h = 0 flat.
  for (const auto& [h, kind] :
       {std::pair{Real(0.5), EdgeKind::Concave}, std::pair{Real(-0.5), EdgeKind::Convex},
        std::pair{Real(0), EdgeKind::Flat}}) {
    const TriangleMesh mesh(
        {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(Real(0.5), 0, -1), Vec3(Real(0.5), h, 1)},
        {{0, 1, 2}, {1, 0, 3}});
    EXPECT_NEAR(mesh.normals()[0].y(), 1, 4 * kEps);
    EXPECT_EQ(mesh.edgeKinds()[0][0], kind);
    EXPECT_EQ(mesh.edgeKinds()[1][0], kind);  // symmetric from the other side
    EXPECT_EQ(mesh.neighbours()[0][0], 1u);
    EXPECT_EQ(mesh.neighbours()[1][0], 0u);
    EXPECT_EQ(mesh.edgeKinds()[0][1], EdgeKind::Boundary);
    EXPECT_EQ(mesh.neighbours()[0][1], TriangleMesh::kNone);
    EXPECT_FALSE(mesh.isClosed());
  }
}

TEST(MeshStructure, ThreeTrianglesOnOneEdgeAreNonManifold) {
  const TriangleMesh mesh(
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)},
      {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  for (int t = 0; t < 3; ++t) {
    EXPECT_EQ(mesh.edgeKinds()[t][0], EdgeKind::NonManifold);
    EXPECT_EQ(mesh.neighbours()[t][0], TriangleMesh::kNone);
  }
  EXPECT_FALSE(mesh.isClosed());
}

TEST(MeshMass, OpenInconsistentOrInsideOutMeshesAreRejected) {
  auto expectThrowMentioning = [](const TriangleMesh& mesh, const std::string& word) {
    try {
      massProperties(Shape(mesh), 1000);
      ADD_FAILURE() << "no exception; expected one mentioning " << word;
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  // Open: a tetrahedron missing a face.
  const TriangleMesh open({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)},
                          {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}});
  EXPECT_FALSE(open.isClosed());
  expectThrowMentioning(open, "closed");
  // One face flipped: every edge is shared twice but not in opposite directions.
  EXPECT_FALSE(tetrahedron(true).isClosed());
  expectThrowMentioning(tetrahedron(true), "consistently oriented");
  // Every face flipped: closed and consistent, but facing inwards.
  const TriangleMesh inverted({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)},
                              {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}});
  EXPECT_TRUE(inverted.isClosed());
  expectThrowMentioning(inverted, "inside out");
}

TEST(MeshErrors, InvalidMeshesAreRejected) {
  auto expectThrowMentioning = [](std::vector<Vec3> v, std::vector<Triangle> t,
                                  const std::string& word) {
    try {
      TriangleMesh mesh(std::move(v), std::move(t));
      ADD_FAILURE() << "no exception; expected one mentioning " << word;
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  const std::vector<Vec3> v{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  expectThrowMentioning(v, {{0, 1, 3}}, "out of range");
  expectThrowMentioning(v, {{0, 1, 0xffffffffu}}, "out of range");
  expectThrowMentioning(v, {}, "no triangles");
  expectThrowMentioning(v, {{0, 1, 1}}, "repeats");
  expectThrowMentioning({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)}, {{0, 1, 2}}, "zero area");
  expectThrowMentioning({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, std::nanf(""), 0)}, {{0, 1, 2}},
                        "not finite");
}

// Monte Carlo with the winding-number inside test; 5 sigma of the sample's standard error (see
// hull_test.cpp) plus Real rounding.
TEST(MeshMass, NonConvexClosedMeshMatchesMonteCarloAndTransformsRigidly) {
  std::mt19937_64 rng(23);
  const TriangleMesh mesh = blob(rng, 8, 12);
  ASSERT_TRUE(mesh.isClosed());
  int convex = 0, concave = 0;
  for (const auto& kinds : mesh.edgeKinds())
    for (EdgeKind k : kinds) convex += k == EdgeKind::Convex, concave += k == EdgeKind::Concave;
  EXPECT_GT(concave, 0);  // the random radii make it non-convex
  EXPECT_GT(convex, 0);

  const auto p = massProperties(mesh, 1);
  const Aabb b = mesh.bounds();
  const WindingNumber winding(mesh);
  const MonteCarlo mc = monteCarlo([&](const Vec3d& x) { return winding.inside(x); },
                                   b.lower.cast<double>(), b.upper.cast<double>(), 60000, 2);
  const double round = 16 * kEps;
  EXPECT_NEAR(p.volume, mc.volume, 5 * mc.volumeSigma + round * mc.volume);
  const Vec3d first = double(p.mass) * p.centerOfMass.cast<double>();
  const Mat3d io = inertiaAboutOrigin(p);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(first[i], mc.first[i], 5 * mc.firstSigma[i] + round * mc.volume);
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(io(i, j), mc.inertia(i, j), 5 * mc.inertiaSigma(i, j) + round * io.norm());
  }
  std::printf("  volume %.5f vs Monte Carlo %.5f +- %.5f\n", double(p.volume), mc.volume,
              mc.volumeSigma);

  // The same blob (same random radii) built directly in a moved frame; rounding of the moved
  // vertices as in hull_test.cpp.
  std::mt19937_64 rng2(23);
  const Transform xf{Vec3(-3, 4, 2), randomRotation(rng)};
  const auto q = massProperties(blob(rng2, 8, 12, xf), 1);
  const Mat3d r = xf.q.toRotationMatrix().cast<double>();
  EXPECT_NEAR(q.volume, p.volume, 256 * kEps * p.volume);
  EXPECT_LE((q.centerOfMass - xf.apply(p.centerOfMass)).norm(), 256 * kEps * 7);
  EXPECT_LE(relativeError(q.inertia.cast<double>(), r * p.inertia.cast<double>() * r.transpose()),
            256 * kEps);
}

TEST(MeshMass, ClosedMeshOfAHullEqualsTheHull) {
  // Triangulating a random hull's faces gives a closed mesh of the same solid.
  std::mt19937_64 rng(29);
  std::vector<Vec3> pts;
  for (int i = 0; i < 30; ++i) pts.push_back(randomVec(rng, -1, 1));
  const ConvexHull hull(pts);
  std::vector<Triangle> tris;
  for (std::size_t f = 0; f < hull.faces().size(); ++f) {
    const auto loop = hull.faceEdges(f);
    for (std::size_t k = 1; k + 1 < loop.size(); ++k)
      tris.push_back({loop[0].origin, loop[k].origin, loop[k + 1].origin});
  }
  const TriangleMesh mesh(hull.vertices(), tris);
  ASSERT_TRUE(mesh.isClosed());
  for (const auto& kinds : mesh.edgeKinds())
    for (EdgeKind k : kinds) EXPECT_TRUE(k == EdgeKind::Convex || k == EdgeKind::Flat);
  const auto a = massProperties(mesh, 3), b = massProperties(hull, 3);
  // Same triangles, different reference point: double sums, one rounding to Real each.
  EXPECT_NEAR(a.mass, b.mass, 8 * kEps * b.mass);
  EXPECT_LE((a.centerOfMass - b.centerOfMass).norm(), 8 * kEps);
  EXPECT_LE(relativeError(a.inertia.cast<double>(), b.inertia.cast<double>()), 8 * kEps);
}
