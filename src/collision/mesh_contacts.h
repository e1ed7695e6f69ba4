// Internal: collide()'s pair functions for triangle meshes, height fields and compounds
// (mesh_contacts.cpp, compound_contacts.cpp). Same conventions as contact_pairs.h: A is the
// shape of the lower ShapeType, manifolds are appended in the world frame, normal from A to B.
#pragma once

#include <cstdint>
#include <vector>

#include "inertia/collision/contact.h"

namespace inertia::detail {

/// A convex shape (A: sphere, capsule, box, cylinder or hull) against a triangle mesh (B): the
/// BVH's triangles under A's bounds (mesh frame, inflated by the speculative distance), one
/// manifold per touching triangle (subShapeB = triangle index), contacts on internal edges and
/// vertices corrected to the face normal, manifolds with equal normals merged to four points.
void collideConvexMesh(const Collider& a, const Transform& poseA, const Collider& b,
                       const Transform& poseB, const ContactSettings& settings,
                       std::vector<ContactManifold>& out);

/// A convex shape (A) against a height field (B): as collideConvexMesh over the grid cells under
/// A's bounds; subShapeB = 2 * (row * (columns - 1) + column) + half (half 0 is the triangle
/// (i, j), (i + 1, j + 1), (i, j + 1) of HeightField::cellTriangles, half 1 the other).
void collideConvexHeightField(const Collider& a, const Transform& poseA, const Collider& b,
                              const Transform& poseB, const ContactSettings& settings,
                              std::vector<ContactManifold>& out);

/// Two triangle meshes: both BVHs traversed together (pairs of overlapping boxes, the larger
/// box split first), the SAT on every pair of triangles of two overlapping leaves (gated by the
/// complete 17-axis triangle-triangle separating-axis test); one manifold
/// per touching pair (subShapeA, subShapeB = the two triangle indices). No internal-edge
/// correction (each triangle pair is treated as two free triangles).
void collideMeshes(const Collider& a, const Transform& poseA, const Collider& b,
                   const Transform& poseB, const ContactSettings& settings,
                   std::vector<ContactManifold>& out);

/// Any shape (A) against a compound (B): collide() with each child whose bounds come within the
/// speculative distance of A's, subShapeB = compoundSubShape(child, count, child's subShape).
void collideWithCompound(const Collider& a, const Transform& poseA, const Collider& b,
                         const Transform& poseB, const ContactSettings& settings,
                         std::vector<ContactManifold>& out);

/// Two compounds: A's children against B (which recurses into B's children).
void collideCompounds(const Collider& a, const Transform& poseA, const Collider& b,
                      const Transform& poseB, const ContactSettings& settings,
                      std::vector<ContactManifold>& out);

/// The sub-shape key of a compound's piece: the child index in the low
/// bit_width(childCount - 1) bits and the child's own sub-shape (a mesh or height-field triangle,
/// a nested compound's key; 0 for a convex child) above them. A convex child's key is therefore
/// its child index.
std::uint32_t compoundSubShape(std::uint32_t child, std::uint32_t childCount,
                               std::uint32_t inner);

}  // namespace inertia::detail
