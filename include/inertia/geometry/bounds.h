// Axis-aligned bounding boxes, and the bounds of shapes in local and world coordinates.
#pragma once

#include <limits>

#include "inertia/core/types.h"

namespace inertia {

class Shape;
struct Plane;
struct Sphere;
struct Capsule;
struct Box;
struct Cylinder;
class ConvexHull;
class TriangleMesh;
class HeightField;
class Compound;

/// An axis-aligned bounding box [lower, upper] (m). The broad phase's currency.
/// `Aabb::empty()` (lower = +inf, upper = -inf) is the identity of `merge`. Bounds of unbounded
/// shapes (planes) have infinite components; every operation here handles them.
struct Aabb {
  Vec3 lower = Vec3::Constant(std::numeric_limits<Real>::infinity());   ///< Minimum corner (m).
  Vec3 upper = Vec3::Constant(-std::numeric_limits<Real>::infinity());  ///< Maximum corner (m).

  /// The empty box: contains nothing, merging with it changes nothing.
  static Aabb empty() { return {}; }
  /// The box of a centre and half extents (m).
  static Aabb fromCenterHalfExtents(const Vec3& center, const Vec3& halfExtents) {
    return {center - halfExtents, center + halfExtents};
  }

  /// True when lower <= upper on every axis (false for the empty box).
  bool isValid() const { return (lower.array() <= upper.array()).all(); }
  /// Centre (m). Meaningless for empty or unbounded boxes.
  Vec3 center() const { return Real(0.5) * (lower + upper); }
  /// Half extents (m).
  Vec3 halfExtents() const { return Real(0.5) * (upper - lower); }
  /// Surface area 2 (xy + yz + zx) (m^2): the cost of the surface-area heuristic.
  Real surfaceArea() const {
    const Vec3 e = upper - lower;
    return Real(2) * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
  }
  /// Volume (m^3).
  Real volume() const { return (upper - lower).prod(); }

  /// The smallest box containing both.
  Aabb merged(const Aabb& b) const { return {lower.cwiseMin(b.lower), upper.cwiseMax(b.upper)}; }
  /// Grows this box to contain `b`.
  void merge(const Aabb& b) { *this = merged(b); }
  /// Grows this box to contain the point `x` (m).
  void extend(const Vec3& x) {
    lower = lower.cwiseMin(x);
    upper = upper.cwiseMax(x);
  }
  /// This box grown by `margin` (m) on every side (the fat AABBs of a dynamic tree).
  Aabb inflated(Real margin) const { return {lower.array() - margin, upper.array() + margin}; }

  /// True when `b` lies inside this box (boundaries included).
  bool contains(const Aabb& b) const {
    return (lower.array() <= b.lower.array()).all() && (b.upper.array() <= upper.array()).all();
  }
  /// True when the point `x` lies inside this box (boundaries included).
  bool contains(const Vec3& x) const {
    return (lower.array() <= x.array()).all() && (x.array() <= upper.array()).all();
  }
  /// True when the boxes share at least one point (touching counts).
  bool overlaps(const Aabb& b) const {
    return (lower.array() <= b.upper.array()).all() && (b.lower.array() <= upper.array()).all();
  }
};

/// The box containing `box` after the transform `xf`: centre mapped, half extents |R| h
/// (Arvo, "Transforming axis-aligned bounding boxes", Graphics Gems 1990). Exact for the
/// transformed box's corners, so the tightest axis-aligned box of the rotated box.
Aabb transformAabb(const Aabb& box, const Transform& xf);

/// Bounds of a shape in its own local coordinates (m). Planes give infinite bounds (finite only
/// along an axis-aligned normal).
Aabb localBounds(const Shape& shape);

/// Bounds of a shape placed by `xf` (local to world), in world coordinates (m).
/// Tight (touching the shape on all six sides) for sphere, capsule, box, cylinder and convex
/// hull, computed from the rotated support function; for compounds the merge of the children's
/// bounds; for meshes and height fields the transformed local box (`transformAabb`), which is
/// conservative but not tight under rotation.
Aabb worldBounds(const Shape& shape, const Transform& xf);

/// Per-type world bounds, for callers that already know the type (same rules as above).
Aabb worldBounds(const Plane& plane, const Transform& xf);
Aabb worldBounds(const Sphere& sphere, const Transform& xf);
Aabb worldBounds(const Capsule& capsule, const Transform& xf);
Aabb worldBounds(const Box& box, const Transform& xf);
Aabb worldBounds(const Cylinder& cylinder, const Transform& xf);
Aabb worldBounds(const ConvexHull& hull, const Transform& xf);
Aabb worldBounds(const TriangleMesh& mesh, const Transform& xf);
Aabb worldBounds(const HeightField& field, const Transform& xf);
Aabb worldBounds(const Compound& compound, const Transform& xf);

}  // namespace inertia
