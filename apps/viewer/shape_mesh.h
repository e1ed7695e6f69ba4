// Triangle meshes for drawing shapes: every Shape tessellated in its local frame (no GL here,
// so the tessellation is testable and shared by the headless renderer and the viewer).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "inertia/core/types.h"
#include "inertia/deformable/deformable.h"
#include "inertia/geometry/shapes.h"

namespace inertia::viewer {

/// Indexed triangles (counter-clockwise seen from outside) with a normal per vertex, in float
/// as the GPU takes them.
struct MeshData {
  std::vector<Eigen::Vector3f> positions{};  ///< m, shape-local
  std::vector<Eigen::Vector3f> normals{};    ///< unit
  std::vector<std::uint32_t> indices{};      ///< 3 per triangle

  std::size_t triangleCount() const { return indices.size() / 3; }
  /// Appends `other` moved by `pose` (compound children).
  void append(const MeshData& other, const Transform& pose);
};

struct TessellationSettings {
  int segments = 32;         ///< Around the axis of spheres, capsules and cylinders (>= 3).
  Real planeHalfSize = 100;  ///< Half the side of the square drawn for an infinite plane (m).
};

/// The triangles of `shape` in its local frame. Boxes, hulls, meshes and height fields get flat
/// normals (a vertex per face corner); spheres, capsules and cylinder sides smooth ones. A plane
/// becomes a square of side 2 planeHalfSize centred at its point nearest the local origin;
/// a compound is the union of its children.
MeshData tessellate(const Shape& shape, const TessellationSettings& settings = {});

/// A deformable as drawn, in world coordinates: a model with triangles (cloth, soft bodies) is
/// its surface with smooth normals (each vertex's area-weighted face normals; the renderer
/// shades both sides); one without (ropes, hair) is a tube of `sides` faces and radius
/// `tubeRadius` (m) along each unbroken stretch spring.
MeshData deformableMesh(const Deformable& deformable, int sides, Real tubeRadius);

/// Two unit vectors spanning the plane orthogonal to unit `n` (for plane quads and grids).
void planeBasis(const Vec3& n, Vec3& u, Vec3& v);

}  // namespace inertia::viewer
