// Tessellation of every shape: closed surfaces enclose the shape's volume, vertices lie on the
// surface, and triangles wind counter-clockwise seen from outside (their normals agree).
#include "shape_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "inertia/deformable/generators.h"

namespace inertia::viewer {
namespace {

constexpr double kPi = std::numbers::pi;

// Divergence theorem: the signed volume of a closed, outward-wound triangle surface.
double enclosedVolume(const MeshData& m) {
  double v = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Eigen::Vector3d a = m.positions[m.indices[t]].cast<double>();
    const Eigen::Vector3d b = m.positions[m.indices[t + 1]].cast<double>();
    const Eigen::Vector3d c = m.positions[m.indices[t + 2]].cast<double>();
    v += a.dot(b.cross(c)) / 6;
  }
  return v;
}

// Every non-degenerate triangle's winding normal points the way of its vertex normals.
void expectConsistentWinding(const MeshData& m) {
  ASSERT_EQ(m.positions.size(), m.normals.size());
  ASSERT_EQ(m.indices.size() % 3, 0u);
  ASSERT_GT(m.indices.size(), 0u);
  int checked = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    for (int k = 0; k < 3; ++k) ASSERT_LT(m.indices[t + k], m.positions.size());
    const Eigen::Vector3f& a = m.positions[m.indices[t]];
    const Eigen::Vector3f n =
        (m.positions[m.indices[t + 1]] - a).cross(m.positions[m.indices[t + 2]] - a);
    if (n.norm() < 1e-7f) continue;  // the poles of a UV sphere
    const Eigen::Vector3f vn =
        m.normals[m.indices[t]] + m.normals[m.indices[t + 1]] + m.normals[m.indices[t + 2]];
    EXPECT_GT(n.normalized().dot(vn.normalized()), 0.5f) << "triangle " << t / 3;
    ++checked;
  }
  EXPECT_GT(checked, 0);
  for (const Eigen::Vector3f& n : m.normals) EXPECT_NEAR(n.norm(), 1.0f, 1e-4f);
}

TEST(ShapeMesh, SphereEnclosesItsVolumeAndLiesOnItsSurface) {
  const MeshData m = tessellate(Sphere{Real(0.5)}, {.segments = 48});
  expectConsistentWinding(m);
  for (const Eigen::Vector3f& p : m.positions) EXPECT_NEAR(p.norm(), 0.5f, 1e-5f);
  // An inscribed polyhedron: a little under 4/3 pi r^3 (1.6% at 48 segments).
  const double exact = 4.0 / 3.0 * kPi * 0.125;
  EXPECT_LT(enclosedVolume(m), exact);
  EXPECT_NEAR(enclosedVolume(m), exact, 0.03 * exact);
}

TEST(ShapeMesh, CapsuleIsACylinderWithHemispheres) {
  const MeshData m = tessellate(Capsule{Real(0.3), Real(0.7)}, {.segments = 48});
  expectConsistentWinding(m);
  for (const Eigen::Vector3f& p : m.positions) {
    const Eigen::Vector3f nearest(0, std::clamp(p.y(), -0.7f, 0.7f), 0);
    EXPECT_NEAR((p - nearest).norm(), 0.3f, 1e-5f);
  }
  const double exact = kPi * 0.09 * 1.4 + 4.0 / 3.0 * kPi * 0.027;
  EXPECT_NEAR(enclosedVolume(m), exact, 0.03 * exact);
}

TEST(ShapeMesh, BoxIsExact) {
  const MeshData m = tessellate(Box{Vec3(1, 2, 3)});
  expectConsistentWinding(m);
  EXPECT_EQ(m.triangleCount(), 12u);
  EXPECT_NEAR(enclosedVolume(m), 48.0, 1e-4);
  for (const Eigen::Vector3f& p : m.positions) {
    EXPECT_FLOAT_EQ(std::abs(p.x()), 1.0f);
    EXPECT_FLOAT_EQ(std::abs(p.y()), 2.0f);
    EXPECT_FLOAT_EQ(std::abs(p.z()), 3.0f);
  }
}

TEST(ShapeMesh, CylinderEnclosesItsVolume) {
  const MeshData m = tessellate(Cylinder{Real(0.5), Real(1)}, {.segments = 64});
  expectConsistentWinding(m);
  const double exact = kPi * 0.25 * 2;
  EXPECT_LT(enclosedVolume(m), exact);
  EXPECT_NEAR(enclosedVolume(m), exact, 0.01 * exact);
}

TEST(ShapeMesh, HullOfACubeIsTheCube) {
  std::vector<Vec3> points;
  for (int i = 0; i < 8; ++i) points.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  points.emplace_back(0, 0, 0);  // inside: not a hull vertex
  const MeshData m = tessellate(ConvexHull(points));
  expectConsistentWinding(m);
  EXPECT_NEAR(enclosedVolume(m), 8.0, 1e-4);
}

TEST(ShapeMesh, TriangleMeshKeepsItsTriangles) {
  // A closed tetrahedron, outward wound.
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<Triangle> t = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const MeshData m = tessellate(TriangleMesh(v, t));
  expectConsistentWinding(m);
  EXPECT_EQ(m.triangleCount(), 4u);
  EXPECT_NEAR(enclosedVolume(m), 1.0 / 6.0, 1e-6);
}

TEST(ShapeMesh, HeightFieldFacesUp) {
  const MeshData m = tessellate(HeightField({{0, 0.5f, 0}, {0.2f, 1, 0.1f}, {0, 0, 0}}, Real(2)));
  expectConsistentWinding(m);
  EXPECT_EQ(m.triangleCount(), 8u);
  for (const Eigen::Vector3f& n : m.normals) EXPECT_GT(n.y(), 0.0f);
}

TEST(ShapeMesh, PlaneIsASquareFacingItsNormal) {
  const Vec3 normal = Vec3(1, 1, 0).normalized();
  const MeshData m = tessellate(Plane{normal, Real(2)}, {.planeHalfSize = 10});
  expectConsistentWinding(m);
  EXPECT_EQ(m.triangleCount(), 2u);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_NEAR(m.positions[i].cast<double>().dot(normal.cast<double>()), 2.0, 1e-5);
    EXPECT_GT(m.normals[i].dot(normal.cast<float>()), 0.999f);
  }
  Vec3 u, v;
  planeBasis(normal, u, v);
  EXPECT_NEAR(u.cross(v).dot(normal), 1.0, 1e-6);
}

TEST(ShapeMesh, CompoundPlacesItsChildren) {
  Transform right;
  right.p = Vec3(3, 0, 0);
  const Compound c({{Box{Vec3(1, 1, 1)}, Transform{}}, {Sphere{Real(0.5)}, right}});
  const MeshData m = tessellate(c, {.segments = 16});
  const MeshData sphere = tessellate(Sphere{Real(0.5)}, {.segments = 16});
  expectConsistentWinding(m);
  EXPECT_EQ(m.triangleCount(), 12 + sphere.triangleCount());
  EXPECT_NEAR(enclosedVolume(m), 8.0 + enclosedVolume(sphere), 1e-3);
  EXPECT_NEAR(m.positions.back().x(), 3.0f + sphere.positions.back().x(), 1e-5f);
}

// A deformable with triangles is drawn as its surface: its own vertices, smooth normals (+y for
// a flat cloth, whose triangles wind counter-clockwise seen from +y). One without (a rope) is a
// tube of `sides` faces around each stretch spring, every vertex at the radius from the axis.
TEST(ShapeMesh, DeformablesAreSurfacesOrTubes) {
  const Deformable sheet(
      {}, cloth({.pose = {Vec3(0, 1, 0), Quat::Identity()}, .size = {1, 1}, .resolution = {3, 3}}));
  const MeshData surface = deformableMesh(sheet, 6, Real(0.01));
  ASSERT_EQ(surface.positions.size(), 16u);
  EXPECT_EQ(surface.triangleCount(), 18u);
  for (std::size_t i = 0; i < surface.positions.size(); ++i) {
    EXPECT_TRUE(surface.positions[i].isApprox(sheet.position(i).cast<float>()));
    EXPECT_NEAR(surface.normals[i].y(), 1.0f, 1e-6f);
  }
  expectConsistentWinding(surface);

  const Deformable line({}, rope({.from = {0, 0, 0}, .to = {2, 0, 0}, .segments = 4}));
  const MeshData tube = deformableMesh(line, 6, Real(0.05));
  EXPECT_EQ(tube.positions.size(), 4u * 2u * 6u);  // 4 stretch springs (bend springs skipped)
  EXPECT_EQ(tube.triangleCount(), 4u * 2u * 6u);
  for (const Eigen::Vector3f& p : tube.positions) {
    EXPECT_NEAR(std::hypot(p.y(), p.z()), 0.05f, 1e-6f);
    EXPECT_GE(p.x(), -1e-6f);
    EXPECT_LE(p.x(), 2.0f + 1e-6f);
  }
  expectConsistentWinding(tube);  // the tube's faces wind outwards
}

}  // namespace
}  // namespace inertia::viewer
