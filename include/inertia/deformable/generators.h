// Generators of mass-spring models, shared by the tests, benchmarks, samples and scene files:
// rope or hair strand, hair on a head, cloth rectangle, soft box, soft sphere, soft body from a
// closed triangle mesh.
//
// Masses are totals, spread evenly over the vertices; stiffness values are per spring (N/m) and
// damping per spring (N s/m). Rest lengths are the distances at creation, so every model starts
// at rest and unstressed. Nothing is pinned (set MassSpringModel::pinned) except hair's roots.
#pragma once

#include <array>

#include "inertia/core/types.h"
#include "inertia/deformable/model.h"
#include "inertia/geometry/mesh.h"

namespace inertia {

/// Stiffness per spring kind (N/m).
struct SpringStiffness {
  Real stretch = 5000;
  Real shear = 500;
  Real bend = 5;
};

/// A rope or hair strand: vertex 0 at `from`, vertex `segments` at `to`, stretch springs
/// between neighbours and bend springs from i to i + 2.
struct RopeSettings {
  Vec3 from = Vec3::Zero();     ///< m
  Vec3 to = Vec3(1, 0, 0);      ///< m
  int segments = 10;            ///< >= 1
  Real mass = 1;                ///< kg, total
  SpringStiffness stiffness{};  ///< stretch and bend used
  Real damping = 0;             ///< N s/m per spring
};
MassSpringModel rope(const RopeSettings& settings);

/// Hair: `strands` straight strands rooted on a sphere (a head) of `radius` about pose.p, over
/// the cap within `capAngle` of the pose's +y axis, each growing `length` along the sphere's
/// outward normal at its root. The roots follow a Fibonacci spiral, which spreads them evenly
/// over the cap's area (each at the centre of an equal-area band, turned by the golden angle).
/// Strand s is vertices s (segments + 1) .. s (segments + 1) + segments, its root first and
/// pinned; each strand has rope()'s springs (stretch between neighbours, bend from i to i + 2).
struct HairSettings {
  Transform pose{};
  Real radius = Real(0.1);     ///< m, > 0: the sphere the roots lie on
  Real capAngle = Real(1.2);   ///< rad, in (0, pi]: how far from +y the roots reach
  int strands = 100;           ///< 1..1000000
  int segments = 16;           ///< per strand, 1..10000
  Real length = Real(0.2);     ///< m per strand, > 0
  Real mass = Real(0.05);      ///< kg, total
  SpringStiffness stiffness{};  ///< stretch and bend used
  Real damping = 0;            ///< N s/m per spring
};
MassSpringModel hair(const HairSettings& settings);

/// A cloth rectangle centred on pose.p in its local x-z plane (normal +y): vertex
/// i + j (nx + 1) at column i along x and row j along z, structural springs along the grid,
/// shear springs on both diagonals of every cell, bend springs skipping one vertex along x and
/// z; two triangles per cell, counter-clockwise seen from +y.
struct ClothSettings {
  Transform pose{};
  std::array<Real, 2> size = {1, 1};         ///< m along local x and z, > 0
  std::array<int, 2> resolution = {10, 10};  ///< cells along x and z, >= 1
  Real mass = 1;                             ///< kg, total
  SpringStiffness stiffness{};
  Real damping = 0;
};
MassSpringModel cloth(const ClothSettings& settings);

/// A soft box: a lattice of (nx + 1)(ny + 1)(nz + 1) vertices filling the box, stretch springs
/// along the lattice's axes, shear springs on every cell's face and body diagonals, bend springs
/// skipping one vertex along each axis; the box's faces as triangles.
struct SoftBoxSettings {
  Transform pose{};
  Vec3 halfExtents = Vec3(Real(0.5), Real(0.5), Real(0.5));  ///< m, > 0
  std::array<int, 3> resolution = {4, 4, 4};                 ///< cells per axis, >= 1
  Real mass = 1;                                             ///< kg, total
  SpringStiffness stiffness{};
  Real damping = 0;
};
MassSpringModel softBox(const SoftBoxSettings& settings);

/// A soft sphere: an icosphere surface (the icosahedron subdivided `subdivisions` times,
/// 10 * 4^s + 2 vertices) and a centre vertex (the last one). Stretch springs on the surface
/// edges and from the centre to every surface vertex, bend springs across every surface edge
/// (between the two vertices opposite it); the icosphere's triangles.
struct SoftSphereSettings {
  Transform pose{};
  Real radius = Real(0.5);  ///< m, > 0
  int subdivisions = 2;     ///< 0..5
  Real mass = 1;            ///< kg, total
  SpringStiffness stiffness{};
  Real damping = 0;
};
MassSpringModel softSphere(const SoftSphereSettings& settings);

/// A soft body from a closed triangle mesh (an OBJ file's, say): the mesh's vertices and faces
/// as its surface, with stretch springs on the edges and bend springs across them (between the
/// two vertices opposite each edge), filled by an interior lattice that holds its volume. The
/// lattice's vertices are the centres of the cells of a grid over the mesh's bounds, `resolution`
/// cells along the longest side, that lie inside the mesh (ray parity along x per row of cells);
/// neighbours are joined as in softBox (stretch along the axes, shear on the face and body
/// diagonals, bend skipping one), and each surface vertex is tied by stretch springs to its
/// `ties` nearest lattice vertices. Surface vertices come first, in the mesh's order; the faces
/// are the model's triangles. Throws InvalidArgument for no mesh, a mesh that is not closed or
/// whose faces turn inwards, or a resolution too coarse to put a lattice vertex inside.
struct SoftMeshSettings {
  Transform pose{};
  const TriangleMesh* mesh = nullptr;  ///< read during the call only
  int resolution = 6;                  ///< lattice cells along the longest side, 1..64
  int ties = 4;                        ///< lattice vertices per surface vertex, 1..8
  Real mass = 1;                       ///< kg, total
  SpringStiffness stiffness{};
  Real damping = 0;
};
MassSpringModel softMesh(const SoftMeshSettings& settings);

}  // namespace inertia
