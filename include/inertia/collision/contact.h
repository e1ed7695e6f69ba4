// Contact manifolds: where two shapes touch, for the contact solver.
//
// collide() dispatches through a [ShapeType][ShapeType] table of free functions (STYLE.md,
// Box2D v3's manifold table): analytic routines for the primitive pairs, the separating axis
// test with face clipping for polyhedra, GJK/EPA with clipping of the supporting features for
// the general convex case, and BVH traversal for meshes, height fields and compounds.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "inertia/collision/collider.h"
#include "inertia/core/types.h"

namespace inertia {

/// One point of contact between shape A and shape B.
struct ContactPoint {
  Vec3 pointA = Vec3::Zero();  ///< On A's surface (m, world).
  Vec3 pointB = Vec3::Zero();  ///< On B's surface (m, world).
  /// (pointB - pointA) . normal (m): negative when the shapes overlap (penetration depth),
  /// positive for a speculative point that is not touching yet.
  Real separation = 0;
  /// Key of the pair of features that made the point (which vertex, edge or face of each
  /// shape). Stable from step to step while the same features touch, so the solver can warm
  /// start by matching (subShapeA, subShapeB, id). Distinct within one manifold.
  std::uint32_t id = 0;
};

/// Up to four points sharing one normal: the contact between two convex pieces.
struct ContactManifold {
  /// Unit normal (world), pointing from A towards B: moving B along it separates the pair.
  Vec3 normal = Vec3::UnitY();
  std::array<ContactPoint, 4> points{};
  int pointCount = 0;
  /// Which piece of each shape: the compound child index, the mesh triangle index or the
  /// height-field triangle index (2 * (row * (columns - 1) + column) + half); 0 for a
  /// convex shape. Compound children holding meshes combine both (see collide()).
  std::uint32_t subShapeA = 0;
  std::uint32_t subShapeB = 0;
};

/// How collide() works.
struct ContactSettings {
  /// Points are reported while their separation is below this (m): 0 reports touching and
  /// overlapping pairs only; a positive value adds speculative contacts for continuous
  /// collision (the solver lets the gap close but not go negative).
  Real speculativeDistance = 0;
};

/// Appends to `out` the manifolds between `a` posed at `poseA` and `b` posed at `poseB`: none
/// when they are apart by more than settings.speculativeDistance, one for a pair of convex
/// shapes, several for meshes, height fields and compounds (one per touching piece, after
/// reduction). Pairs of two shapes that cannot move (plane, height field: both static only)
/// produce nothing. `out` is not cleared, so a caller can gather a whole step's manifolds into
/// one reused vector without allocating once it has grown. Inputs must be finite with unit
/// quaternions; results are deterministic (no dependence on memory addresses).
///
/// Swapping two shapes of different types gives exactly the flipped manifold (normal negated,
/// pointA and pointB exchanged, the 16-bit halves of each id exchanged). Two shapes of the same
/// type are computed in the order given, with A's faces preferred when two axes are within the
/// SAT's hysteresis band: pass a pair in a stable order (e.g. by body index) from step to step.
///
/// Meshes and height fields against a convex shape give one manifold per touching triangle;
/// contacts on internal (flat or concave) edges and vertices take the face normal, so nothing
/// bumps over the seams between triangles; manifolds with equal normals are merged (subShape
/// the lowest triangle). Two meshes: one manifold per touching pair of triangles. A compound's
/// subShape holds the child index in its low bit_width(childCount - 1) bits and the child's own
/// subShape (a triangle index, a nested compound's key; 0 for a convex child) above them, so a
/// convex child's subShape is its index. Plane-mesh and mesh-height-field pairs (both static)
/// produce nothing.
void collide(const Collider& a, const Transform& poseA, const Collider& b,
             const Transform& poseB, const ContactSettings& settings,
             std::vector<ContactManifold>& out);

/// collide() for two convex shapes (any but Mesh, HeightField and Compound), which make one
/// manifold at most: writes it to `out` and returns true, or returns false when the shapes are
/// apart by more than settings.speculativeDistance (or cannot both move). The same manifold
/// as collide() gives, without the vector.
bool collideConvex(const Collider& a, const Transform& poseA, const Collider& b,
                   const Transform& poseB, const ContactSettings& settings, ContactManifold& out);

}  // namespace inertia
