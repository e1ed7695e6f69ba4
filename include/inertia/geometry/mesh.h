// Triangle meshes: vertices, triangles, per-triangle normals and edge adjacency.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "inertia/core/types.h"
#include "inertia/geometry/bounds.h"

namespace inertia {

/// Three vertex indices, counter-clockwise seen from outside (the normal's side).
using Triangle = std::array<std::uint32_t, 3>;

/// What meets at a triangle's edge; lets the collision layer suppress contacts on internal edges.
enum class EdgeKind : std::uint8_t {
  Boundary,     ///< No neighbouring triangle: an open edge.
  Convex,       ///< The neighbour bends away from the normal side (a ridge).
  Concave,      ///< The neighbour bends towards the normal side (a valley).
  Flat,         ///< The neighbour is coplanar within kFlatSine.
  NonManifold,  ///< Three or more triangles share the edge; no single neighbour.
};

/// A triangle mesh (m), immutable once built. Edge k of a triangle runs from its vertex k to its
/// vertex (k + 1) % 3. The collision layer builds its BVH over it; nothing spatial is here.
class TriangleMesh {
 public:
  /// Marker of "no neighbouring triangle".
  static constexpr std::uint32_t kNone = 0xffffffffu;
  /// |sin| of the dihedral deviation below which two neighbours are classified Flat.
  static constexpr double kFlatSine = 1e-5;

  /// Builds the mesh and its adjacency. Throws InvalidArgument for no triangles, non-finite
  /// vertices, indices out of range, a triangle repeating a vertex or of zero area.
  TriangleMesh(std::vector<Vec3> vertices, std::vector<Triangle> triangles);

  /// Vertex positions (m), local frame.
  const std::vector<Vec3>& vertices() const { return vertices_; }
  /// Triangles (vertex indices).
  const std::vector<Triangle>& triangles() const { return triangles_; }
  /// Unit normal of each triangle, (b - a) x (c - a) normalised.
  const std::vector<Vec3>& normals() const { return normals_; }
  /// For triangle t and edge k: the triangle across that edge, or kNone.
  const std::vector<std::array<std::uint32_t, 3>>& neighbours() const { return neighbours_; }
  /// For triangle t and edge k: what kind of edge it is.
  const std::vector<std::array<EdgeKind, 3>>& edgeKinds() const { return edgeKinds_; }

  /// True when the mesh bounds a volume: every edge is shared by exactly two triangles that
  /// traverse it in opposite directions (closed, manifold and consistently oriented).
  /// Mass properties require it (and a positive volume, i.e. outward normals).
  bool isClosed() const { return closed_; }
  /// Bounds of the vertices in the local frame (m).
  const Aabb& bounds() const { return bounds_; }

 private:
  std::vector<Vec3> vertices_;
  std::vector<Triangle> triangles_;
  std::vector<Vec3> normals_;
  std::vector<std::array<std::uint32_t, 3>> neighbours_;
  std::vector<std::array<EdgeKind, 3>> edgeKinds_;
  Aabb bounds_;
  bool closed_ = false;
};

}  // namespace inertia
