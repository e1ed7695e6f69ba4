// Convex hulls built from point clouds with Qhull, stored as a half-edge mesh for SAT and clipping.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "inertia/core/types.h"
#include "inertia/geometry/bounds.h"

namespace inertia {

/// One face of a convex hull: the plane {x : normal . x = offset} with outward unit `normal`,
/// and its boundary loop, `edgeCount` half-edges stored contiguously from `firstEdge`.
struct HullFace {
  Vec3 normal = Vec3::Zero();   ///< Outward unit normal.
  Real offset = 0;              ///< Plane offset (m): every hull point x has normal . x <= offset.
  std::uint32_t firstEdge = 0;  ///< Index of the face's first half-edge.
  std::uint32_t edgeCount = 0;  ///< Number of half-edges (= vertices) of the loop, >= 3.
};

/// A directed edge of one face's loop. The loop of face f is
/// halfEdges[f.firstEdge .. f.firstEdge + f.edgeCount), in counter-clockwise order seen from
/// outside the hull (right-hand rule about the outward normal); half-edge h runs from
/// `origin` to halfEdges[next].origin.
struct HullHalfEdge {
  std::uint32_t origin = 0;  ///< Vertex the half-edge starts at.
  std::uint32_t next = 0;    ///< Next half-edge of the same face's loop.
  std::uint32_t twin = 0;    ///< The opposite half-edge, on the neighbouring face.
  std::uint32_t face = 0;    ///< Face this half-edge bounds.
  std::uint32_t edge = 0;    ///< The undirected edge (index into edges()).
};

/// An undirected edge, listed once, for the edge-edge axes of the separating-axis test.
/// `halfEdge` runs from v0 to v1 on face0; its twin runs from v1 to v0 on face1.
struct HullEdge {
  std::uint32_t v0 = 0, v1 = 0;        ///< End vertices.
  std::uint32_t face0 = 0, face1 = 0;  ///< The two faces meeting at the edge.
  std::uint32_t halfEdge = 0;          ///< The half-edge v0 -> v1 (on face0).
};

/// A convex polyhedron: the convex hull of a point cloud, built by Qhull (Barber, Dobkin and
/// Huhdanpaa, "The Quickhull algorithm for convex hulls", 1996) with coplanar facets merged, so a
/// cube has 6 quadrilateral faces, not 12 triangles. Immutable once built.
///
/// Topology is a half-edge structure (as in Gregorius' SAT for convex polyhedra): each face's
/// loop, each face's neighbour across each edge (halfEdges[h].twin's face), each vertex's edges
/// (vertexEdges). Coordinates are the input's (local) frame; only hull vertices are kept.
class ConvexHull {
 public:
  /// Builds the hull of `points` (m). Throws InvalidArgument when a point is not finite, when
  /// there are fewer than 4 distinct points, or when the points are all (nearly) coplanar or
  /// collinear so that no volume is spanned: the relative thickness must exceed kMinThickness.
  explicit ConvexHull(std::span<const Vec3> points);

  /// Minimum thickness of a cloud relative to its extent (bounding-box diagonal): thinner
  /// clouds are rejected as coplanar. Measured as the height of a greedy extreme-point
  /// simplex (as Quickhull starts), so a rejected cloud is at most twice this thick.
  static constexpr double kMinThickness = 1e-6;

  /// The hull's vertices (m), in its local frame.
  const std::vector<Vec3>& vertices() const { return vertices_; }
  /// Faces (planes and loops).
  const std::vector<HullFace>& faces() const { return faces_; }
  /// All half-edges; each face's loop is a contiguous range.
  const std::vector<HullHalfEdge>& halfEdges() const { return halfEdges_; }
  /// Undirected edges, each listed once.
  const std::vector<HullEdge>& edges() const { return edges_; }

  /// The half-edges bounding face `f`, in counter-clockwise order seen from outside.
  std::span<const HullHalfEdge> faceEdges(std::size_t f) const {
    return {halfEdges_.data() + faces_[f].firstEdge, faces_[f].edgeCount};
  }
  /// The undirected edges (indices into edges()) incident to vertex `v`.
  std::span<const std::uint32_t> vertexEdges(std::size_t v) const {
    return {vertexEdgeIndices_.data() + vertexEdgeStart_[v],
            vertexEdgeStart_[v + 1] - vertexEdgeStart_[v]};
  }
  /// The face on the other side of half-edge `h`'s edge.
  std::uint32_t neighbour(std::size_t h) const { return halfEdges_[halfEdges_[h].twin].face; }

  /// The mean of the vertices (m): a point strictly inside the hull (not the centre of mass).
  const Vec3& interiorPoint() const { return interiorPoint_; }
  /// Bounds of the vertices in the local frame (m).
  const Aabb& bounds() const { return bounds_; }

 private:
  std::vector<Vec3> vertices_;
  std::vector<HullFace> faces_;
  std::vector<HullHalfEdge> halfEdges_;
  std::vector<HullEdge> edges_;
  std::vector<std::uint32_t> vertexEdgeStart_;    // CSR offsets, size vertices + 1
  std::vector<std::uint32_t> vertexEdgeIndices_;  // CSR values: edge indices
  Vec3 interiorPoint_ = Vec3::Zero();
  Aabb bounds_;
};

}  // namespace inertia
