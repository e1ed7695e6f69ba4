// The static bounding-volume hierarchy over a triangle mesh (seeds 001 and 003: BVH / AABB
// trees): ray casts, closest points and box overlaps in O(log n) typical time.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "inertia/collision/triangle.h"
#include "inertia/core/types.h"
#include "inertia/geometry/bounds.h"
#include "inertia/geometry/mesh.h"

namespace inertia {

/// An AABB tree over a mesh's triangles, in the mesh's local frame. Built top-down with a
/// binned surface-area heuristic (Wald, "On fast construction of SAH-based bounding volume
/// hierarchies", 2007: 16 bins per axis, all three axes tried), immutable afterwards. Nodes sit
/// in one flat array in depth-first order: an inner node's first child is the next node, its
/// second child is `index`; a leaf's triangles are the slots [index, index + count) of the
/// tree's own copy of the triangle corners (stored in leaf order, so a leaf reads contiguous
/// memory). The tree copies what it needs and does not reference the mesh afterwards.
///
/// Queries allocate nothing: they traverse with a fixed stack (the builder bounds the depth
/// by switching from SAH to median splits deep in the tree).
class MeshBvh {
 public:
  /// One node. 32 bytes with float Reals.
  struct Node {
    Vec3 lower = Vec3::Zero();  ///< Box minimum corner (m).
    std::uint32_t index = 0;    ///< Inner: second child's node index. Leaf: first slot.
    Vec3 upper = Vec3::Zero();  ///< Box maximum corner (m).
    std::uint32_t count = 0;    ///< Number of triangles of a leaf; 0 for an inner node.
    bool isLeaf() const { return count != 0; }
  };

  /// The deepest a tree may be (root = depth 0): the size of the traversal stacks.
  static constexpr int kMaxDepth = 100;
  /// At most this many triangles in a leaf.
  static constexpr std::uint32_t kMaxLeafSize = 8;

  explicit MeshBvh(const TriangleMesh& mesh);

  /// Nodes, root first.
  const std::vector<Node>& nodes() const { return nodes_; }
  /// The mesh triangle index stored in each leaf slot.
  const std::vector<std::uint32_t>& slotTriangles() const { return slotTriangle_; }
  /// Number of triangles.
  std::size_t triangleCount() const { return slotTriangle_.size(); }
  /// Depth of the deepest leaf (a single leaf is depth 0).
  int depth() const { return depth_; }
  /// Whether the mesh was closed (TriangleMesh::isClosed): point queries are then signed.
  bool closed() const { return closed_; }

  /// A ray's first hit on the mesh.
  struct RayHit {
    Real fraction = 0;            ///< s of origin + s * direction.
    std::uint32_t triangle = 0;   ///< Mesh triangle index.
    Vec3 normal = Vec3::UnitY();  ///< Unit triangle normal turned to face the ray's origin.
  };
  /// Closest triangle hit (two-sided) with s in [0, maxFraction], local frame; front-to-back
  /// traversal that skips boxes entered beyond the best hit so far.
  std::optional<RayHit> castRay(const Vec3& origin, const Vec3& direction, Real maxFraction) const;

  /// The closest point of the mesh to a point.
  struct Closest {
    Vec3 point = Vec3::Zero();                        ///< Closest point on the mesh (m, local).
    Real distanceSquared = 0;                         ///< |p - point|^2 (m^2).
    std::uint32_t triangle = 0;                       ///< Mesh triangle index.
    TriangleFeature feature = TriangleFeature::Face;  ///< Where on that triangle.
  };
  /// The closest point of the mesh to `p` (local frame), by branch and bound: children visited
  /// nearest box first, boxes farther than the best so far skipped. Always finds one.
  Closest closestPoint(const Vec3& p) const;

  /// The angle-weighted pseudonormal (Baerentzen and Aanaes 2005) of a triangle's feature:
  /// face normal, normalised sum of the two faces at an edge, or the incidence-angle-weighted
  /// sum at a vertex. For closed meshes, sign((p - q) . pseudonormal) is the sign of the
  /// distance; for open meshes (no pseudonormals stored) the face normal.
  Vec3 pseudonormal(std::uint32_t triangle, TriangleFeature feature) const;

  /// The unit normal of mesh triangle `t` (as TriangleMesh::normals()).
  const Vec3& triangleNormal(std::uint32_t t) const { return normals_[t]; }

  /// Calls f(triangle) for every mesh triangle whose bounding box overlaps `box` (local frame),
  /// each once, in no particular order.
  template <class F>
  void forEachOverlap(const Aabb& box, F&& f) const {
    std::uint32_t stack[kMaxDepth + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!overlapsBox(n, box)) continue;
      if (n.isLeaf()) {
        for (std::uint32_t s = n.index; s < n.index + n.count; ++s) {
          const auto& t = corners_[s];
          const Vec3 lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
          const Vec3 hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
          if ((lo.array() <= box.upper.array()).all() && (box.lower.array() <= hi.array()).all())
            f(slotTriangle_[s]);
        }
      } else {
        const std::uint32_t self = std::uint32_t(&n - nodes_.data());
        stack[top++] = n.index;
        stack[top++] = self + 1;
      }
    }
  }

  /// The corners of the triangle in leaf slot `s` (m, local).
  const std::array<Vec3, 3>& slotCorners(std::size_t s) const { return corners_[s]; }

 private:
  static bool overlapsBox(const Node& n, const Aabb& b) {
    return (n.lower.array() <= b.upper.array()).all() && (b.lower.array() <= n.upper.array()).all();
  }

  std::vector<Node> nodes_;
  std::vector<std::array<Vec3, 3>> corners_;  // per slot
  std::vector<std::uint32_t> slotTriangle_;   // per slot: mesh triangle index
  std::vector<Vec3> normals_;                 // per mesh triangle
  // Pseudonormals, closed meshes only: per mesh triangle edge, and per triangle corner (the
  // vertex's normal, copied so a query needs no vertex indices).
  std::vector<std::array<Vec3, 3>> edgeNormals_;
  std::vector<std::array<Vec3, 3>> vertexNormals_;
  int depth_ = 0;
  bool closed_ = false;
};

}  // namespace inertia
