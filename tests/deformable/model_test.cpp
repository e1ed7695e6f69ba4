// The generators: vertex and spring counts, rest lengths at rest, masses summing to the total,
// surfaces facing out; validation of bad models.
#include <gtest/gtest.h>

#include <set>

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
