// Queries on a single shape in a pose: point queries (signed distance, closest point, normal)
// and ray / segment casts. Usable on bare shapes and transforms, without a world.
//
// Inputs must be finite (points, rays, poses with unit quaternions): these functions run per
// particle per step, so they do not validate; for finite input they never return NaN or
// infinity. They allocate nothing and make no virtual calls (a switch on the shape type).
#pragma once

#include <optional>

#include "inertia/collision/collider.h"
#include "inertia/core/types.h"

namespace inertia {

/// The answer of a point query.
struct PointQuery {
  /// Signed distance from the point to the shape's surface (m): positive outside, negative
  /// inside (for solids: planes' half-spaces, primitives, hulls, closed meshes, height fields
  /// (below the surface is inside)). For an open mesh, the unsigned distance.
  Real distance = 0;
  Vec3 point = Vec3::Zero();  ///< Closest point on the surface (m, world).
  /// Unit direction (world) in which the point leaves the shape fastest: the outward surface
  /// normal at `point` for points outside or inside. Always finite and unit, also on edges,
  /// corners and at the exact centre of a sphere (a fixed, documented choice there).
  Vec3 normal = Vec3::UnitY();
};

/// The point query of `point` (m, world) against `collider` posed at `pose`.
///
/// Wherever the direction p - point is defined, normal = (p - point) / distance, so
/// `point == p - distance * normal` (inside as well as outside). Fixed choices where it is not
/// (all in the shape's local frame, then rotated by the pose):
///  - sphere centre: +y;  capsule axis (segment, end points included): +x;
///  - box: the face of least depth, ties to the lower axis (x, y, z) and the + side (the centre
///    of a cube gets +x);  cylinder inside: the side (radial, +x on the axis) when nearer than
///    the caps, else the cap (ties go to the cap);
///  - hull inside: the face plane of least depth (exact for convex polytopes);
///  - a point on a surface (distance 0): the face normal, or for closed meshes the
///    angle-weighted pseudonormal of the closest feature.
/// Meshes: closed meshes (TriangleMesh::isClosed) are signed by the angle-weighted pseudonormal
/// of the closest feature (Baerentzen and Aanaes 2005); open meshes give unsigned distances.
/// Height fields: below the surface, within the grid's footprint, is inside; the search covers
/// the cells within the vertical distance to the surface, so it costs O((d / spacing)^2) for a
/// point at distance d. Compounds: the child with the least signed distance (exact outside; in
/// overlapping children, the depth in the child reporting the least value).
PointQuery queryPoint(const Collider& collider, const Transform& pose, const Vec3& point);

/// A segment origin + s * direction, s in [0, maxFraction] (m, world). direction need not be
/// unit; with maxFraction = 1 the segment runs from origin to origin + direction.
struct Ray {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3::UnitX();
  Real maxFraction = 1;
};

/// Where a ray first enters a shape.
struct RayHit {
  Real fraction = 0;            ///< s of the hit point along the ray.
  Vec3 point = Vec3::Zero();    ///< Hit point (m, world).
  Vec3 normal = Vec3::UnitY();  ///< Unit surface normal at the hit, facing the ray's origin side.
};

/// The first point where the ray enters the shape's surface, or nothing. A ray starting inside
/// a solid reports no hit (the point query is the tool there); triangles of meshes and height
/// fields are hit from either side. Degenerate rays (zero direction) report nothing, and so
/// does a negative maxFraction. A ray starting on a solid's surface and moving into it hits at
/// fraction 0; one moving out or along the surface does not. A ray grazing an edge or a
/// tangent point may go either way (decided by rounding), always with a finite unit normal.
/// Compounds report the nearest child hit, and nothing when the origin is strictly inside a
/// solid child (primitive, hull, plane; mesh and height-field children are surfaces for rays).
std::optional<RayHit> castRay(const Collider& collider, const Transform& pose, const Ray& ray);

}  // namespace inertia
