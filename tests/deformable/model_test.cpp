// The generators: vertex and spring counts, rest lengths at rest, masses summing to the total,
// surfaces facing out; validation of bad models.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "inertia/core/error.h"
#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"

namespace inertia {
namespace {

// Every spring starts at its rest length, and the masses sum to the total (float rounding of
// a sum of n equal terms: n eps relative).
void expectAtRest(const MassSpringModel& m, Real totalMass) {
  ASSERT_NO_THROW(validate(m));
  for (const Spring& s : m.springs)
    EXPECT_NEAR((m.positions[s.a] - m.positions[s.b]).norm(), s.restLength, 1e-6f * s.restLength);
  double sum = 0;
  for (Real mass : m.masses) sum += mass;
  EXPECT_NEAR(sum, totalMass, 1e-6 * double(m.masses.size()) * totalMass);
}

std::size_t count(const MassSpringModel& m, SpringKind kind) {
  std::size_t c = 0;
  for (const Spring& s : m.springs) c += s.kind == kind;
  return c;
}

TEST(DeformableGenerators, RopeHasNeighbourAndSkipOneSprings) {
  const MassSpringModel m = rope({.from = {0, 0, 0}, .to = {2, 0, 0}, .segments = 8, .mass = 3});
  EXPECT_EQ(m.vertexCount(), 9u);
  EXPECT_EQ(count(m, SpringKind::Stretch), 8u);
  EXPECT_EQ(count(m, SpringKind::Bend), 7u);
  EXPECT_FLOAT_EQ(m.positions[8].x(), 2);
  expectAtRest(m, 3);
}

// Hair: strands of rope()'s springs, roots pinned on the sphere within the cap, tips at the
// length along the normal. The Fibonacci roots are spread evenly: every nearest neighbour is
// farther than half the mean spacing sqrt(cap area / strands) (a spiral's nearest neighbours
// are about 0.9 of it; roots bunched at the pole or on one meridian would fail).
TEST(DeformableGenerators, HairStrandsRootedEvenlyOnTheCap) {
  const Real radius = Real(0.1), length = Real(0.3), cap = Real(1.2);
  const int strands = 200, segments = 6;
  const Vec3 centre(1, 2, 3);
  const MassSpringModel m = hair({.pose = {centre, Quat::Identity()},
                                  .radius = radius,
                                  .capAngle = cap,
                                  .strands = strands,
                                  .segments = segments,
                                  .length = length,
                                  .mass = Real(0.05)});
  EXPECT_EQ(m.vertexCount(), std::size_t(strands * (segments + 1)));
  EXPECT_EQ(count(m, SpringKind::Stretch), std::size_t(strands * segments));
  EXPECT_EQ(count(m, SpringKind::Bend), std::size_t(strands * (segments - 1)));
  ASSERT_EQ(m.pinned.size(), std::size_t(strands));
  expectAtRest(m, Real(0.05));
  std::vector<Vec3> roots;
  for (int k = 0; k < strands; ++k) {
    const std::uint32_t root = std::uint32_t(k * (segments + 1));
    EXPECT_EQ(m.pinned[std::size_t(k)], root);
    const Vec3 normal = (m.positions[root] - centre) / radius;
    EXPECT_NEAR(normal.norm(), 1, 1e-5);
    EXPECT_GE(normal.y(), std::cos(cap) - Real(1e-5));
    const Vec3 tip = m.positions[root + std::uint32_t(segments)];
    EXPECT_NEAR((tip - centre).norm(), radius + length, 1e-5);
    roots.push_back(m.positions[root]);
  }
  const double pi = std::acos(-1.0);
  const double spacing = std::sqrt(2 * pi * double(radius * radius) * (1 - std::cos(double(cap))) /
                                   strands);
  for (std::size_t a = 0; a < roots.size(); ++a) {
    double nearest = 1e9;
    for (std::size_t b = 0; b < roots.size(); ++b)
      if (a != b) nearest = std::min(nearest, double((roots[a] - roots[b]).norm()));
    EXPECT_GT(nearest, 0.5 * spacing) << "root " << a;
  }
  EXPECT_THROW(hair({.capAngle = 4}), InvalidArgument);
  EXPECT_THROW(hair({.strands = 0}), InvalidArgument);
  EXPECT_THROW(hair({.length = 0}), InvalidArgument);
}

// A cube [0, side]^3 as 12 triangles, counter-clockwise seen from outside.
TriangleMesh cubeMesh(Real side) {
  std::vector<Vec3> v;
  for (int k = 0; k < 8; ++k)
    v.push_back(side * Vec3(Real((k & 1) ^ ((k >> 1) & 1)), Real((k >> 1) & 1), Real(k >> 2)));
  return TriangleMesh(v, {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                          {3, 7, 6}, {3, 6, 2}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}});
}

// A cube's soft body: the 8 corners, then the 4 x 4 x 4 cell centres (all inside), softBox's
// lattice springs among them, the surface's 18 edges and their bend springs, and 4 ties per
// corner to the nearest centres (the corner cell's, then three of its neighbours').
TEST(DeformableGenerators, SoftMeshFillsACubeWithItsLattice) {
  const TriangleMesh mesh = cubeMesh(1);
  const MassSpringModel m = softMesh({.mesh = &mesh, .resolution = 4, .ties = 4, .mass = 2});
  ASSERT_EQ(m.vertexCount(), 8u + 64u);
  EXPECT_EQ(m.triangles.size(), 12u);
  expectAtRest(m, 2);
  // The lattice alone: 3 * 4 * 4 * 3 axis, 3 * 2 * 4 * 3 * 3 face diagonals, 4 * 27 body
  // diagonals, 3 * 4 * 4 * 2 bend; the surface: 18 edges, 18 bend; 8 * 4 ties.
  EXPECT_EQ(count(m, SpringKind::Stretch), std::size_t(144 + 18 + 32));
  EXPECT_EQ(count(m, SpringKind::Shear), std::size_t(216 + 108));
  EXPECT_EQ(count(m, SpringKind::Bend), std::size_t(96 + 18));
  for (std::size_t i = 8; i < m.vertexCount(); ++i)
    for (int a = 0; a < 3; ++a) {
      const Real c = m.positions[i][a] * 4 - Real(0.5);  // 0..3 at the cell centres
      EXPECT_NEAR(c, std::round(c), 1e-5) << "vertex " << i;
    }
  const Spring& tie = m.springs[m.springs.size() - 32];  // corner 0's nearest: centre (1/8)^3
  EXPECT_EQ(tie.a, 0u);
  EXPECT_TRUE(m.positions[tie.b].isApprox(Vec3::Constant(Real(0.125))));
}

// Inside a sphere's mesh (the soft sphere's icosphere surface, radius 0.5): every lattice
// vertex lies inside the sphere, and every cell centre well inside it (0.45, within the
// icosphere's inscribed radius: its faces span about 9 degrees from their centres, so about
// 0.5 cos 9 = 0.49) is a lattice vertex.
TEST(DeformableGenerators, SoftMeshLatticeIsWhatLiesInside) {
  const MassSpringModel ball = softSphere({.radius = Real(0.5), .subdivisions = 2});
  std::vector<Vec3> surface(ball.positions.begin(), ball.positions.end() - 1);
  const TriangleMesh mesh(surface, ball.triangles);
  const int resolution = 10;
  const MassSpringModel m = softMesh({.mesh = &mesh, .resolution = resolution});
  // The bounds are within rounding of a cube, so the grid has `resolution` cells per axis.
  const Vec3 cell = (mesh.bounds().upper - mesh.bounds().lower) / Real(resolution);
  std::set<std::array<long, 3>> lattice;
  for (std::size_t i = surface.size(); i < m.vertexCount(); ++i) {
    EXPECT_LT(m.positions[i].norm(), Real(0.5)) << "vertex " << i;
    const Vec3 c =
        (m.positions[i] - mesh.bounds().lower).cwiseQuotient(cell) - Vec3::Constant(Real(0.5));
    lattice.insert({std::lround(c.x()), std::lround(c.y()), std::lround(c.z())});
  }
  for (long l = 0; l < resolution; ++l)
    for (long j = 0; j < resolution; ++j)
      for (long i = 0; i < resolution; ++i) {
        const Vec3 centre = mesh.bounds().lower + cell.cwiseProduct(Vec3(Real(i), Real(j), Real(l)) +
                                                                    Vec3::Constant(Real(0.5)));
        if (centre.norm() < Real(0.45)) {
          EXPECT_TRUE(lattice.count({i, j, l})) << i << " " << j << " " << l;
        }
      }
}

TEST(DeformableGenerators, SoftMeshRefusesOpenInwardAndTooCoarseMeshes) {
  const TriangleMesh cube = cubeMesh(1);
  std::vector<Triangle> open = cube.triangles(), inward = cube.triangles();
  open.pop_back();
  for (Triangle& t : inward) std::swap(t[1], t[2]);
  const TriangleMesh openMesh(cube.vertices(), open), inwardMesh(cube.vertices(), inward);
  const auto message = [](const SoftMeshSettings& s) {
    try {
      softMesh(s);
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_NE(message({.mesh = &openMesh}).find("closed"), std::string::npos);
  EXPECT_NE(message({.mesh = &inwardMesh}).find("inwards"), std::string::npos);
  EXPECT_NE(message({}).find("mesh must be given"), std::string::npos);
  EXPECT_NE(message({.mesh = &cube, .resolution = 0}).find("resolution"), std::string::npos);
}

TEST(DeformableGenerators, ClothGridCountsAndLayout) {
  const int nx = 4, nz = 3;
  const MassSpringModel m = cloth({.pose = {Vec3(0, 2, 0), Quat::Identity()},
                                   .size = {2, 1},
                                   .resolution = {nx, nz},
                                   .mass = 0.5f});
  EXPECT_EQ(m.vertexCount(), std::size_t((nx + 1) * (nz + 1)));
  EXPECT_EQ(count(m, SpringKind::Stretch), std::size_t(nx * (nz + 1) + nz * (nx + 1)));
  EXPECT_EQ(count(m, SpringKind::Shear), std::size_t(2 * nx * nz));
  EXPECT_EQ(count(m, SpringKind::Bend), std::size_t((nx - 1) * (nz + 1) + (nz - 1) * (nx + 1)));
  EXPECT_EQ(m.triangles.size(), std::size_t(2 * nx * nz));
  // DESIGN.md section 4: vertex i + j (nx + 1) at column i along x, row j along z.
  EXPECT_TRUE(m.positions[1].isApprox(Vec3(-0.5f, 2, -0.5f)));
  EXPECT_TRUE(m.positions[std::size_t(nx + 1)].isApprox(Vec3(-1, 2, Real(-0.5) + Real(1) / nz)));
  for (const auto& t : m.triangles) {
    const Vec3 n =
        (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
    EXPECT_GT(n.y(), 0) << "triangles face +y";
  }
  expectAtRest(m, 0.5f);
}

// A closed surface facing out: the divergence theorem gives its volume from the triangles,
// positive only if they are counter-clockwise seen from outside.
double signedVolume(const MassSpringModel& m) {
  double v = 0;
  for (const auto& t : m.triangles)
    v += m.positions[t[0]].cast<double>().dot(
             m.positions[t[1]].cast<double>().cross(m.positions[t[2]].cast<double>())) /
         6;
  return v;
}

TEST(DeformableGenerators, SoftBoxLatticeAndOutwardFaces) {
  const MassSpringModel m =
      softBox({.halfExtents = {1, 0.5f, 0.25f}, .resolution = {2, 2, 2}, .mass = 2});
  EXPECT_EQ(m.vertexCount(), 27u);
  // Axis springs: 3 directions x 2 x 3 x 3; bend: 3 x 1 x 3 x 3; shear: face diagonals
  // 3 planes x 2 diagonals x (2 x 2 cells) x 3 layers, body diagonals 4 x 8 cells.
  EXPECT_EQ(count(m, SpringKind::Stretch), 54u);
  EXPECT_EQ(count(m, SpringKind::Bend), 27u);
  EXPECT_EQ(count(m, SpringKind::Shear), 3u * 2 * 4 * 3 + 4 * 8);
  EXPECT_EQ(m.triangles.size(), 6u * 4 * 2);
  EXPECT_NEAR(signedVolume(m), 2.0 * 1.0 * 0.5, 1e-5);
  expectAtRest(m, 2);
}

TEST(DeformableGenerators, SoftSphereIcosphereFacesOutAndHasSpokes) {
  const int s = 2;
  const MassSpringModel m = softSphere({.radius = 1, .subdivisions = s, .mass = 1});
  const std::size_t surface = 10 * 16 + 2;  // 10 * 4^s + 2
  EXPECT_EQ(m.vertexCount(), surface + 1);
  EXPECT_EQ(m.triangles.size(), 20u * 16);
  // Edges E = 3F / 2, one stretch spring each, one bend across each, one spoke per vertex.
  EXPECT_EQ(count(m, SpringKind::Stretch), 480u + surface);
  EXPECT_EQ(count(m, SpringKind::Bend), 480u);
  // The inscribed polyhedron's volume lies below the sphere's 4/3 pi (about 4% at s = 2).
  const double v = signedVolume(m);
  EXPECT_GT(v, 0.9 * 4.18879);
  EXPECT_LT(v, 4.18879);
  expectAtRest(m, 1);
}

TEST(DeformableGenerators, BadSettingsAndModelsAreRefusedByName) {
  EXPECT_THROW(rope({.segments = 0}), InvalidArgument);
  EXPECT_THROW(cloth({.size = {0, 1}}), InvalidArgument);
  EXPECT_THROW(softBox({.mass = -1}), InvalidArgument);
  MassSpringModel m = rope({});
  m.springs[0].b = 99;
  try {
    validate(m);
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("springs[0]"), std::string::npos) << e.what();
  }
  m = rope({});
  m.masses[3] = 0;
  EXPECT_THROW(Deformable({}, m), InvalidArgument);
  EXPECT_THROW(Deformable({.thickness = 0}, rope({})), InvalidArgument);
}

}  // namespace
}  // namespace inertia
