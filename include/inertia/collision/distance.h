// Distance, closest points and penetration depth of two convex shapes: GJK and EPA on bare
// colliders and transforms, without a world.
//
// Convex shapes only: sphere, capsule, box, cylinder, hull (any other type throws
// InvalidArgument). Inputs must be finite with unit quaternions. Results are in the world frame,
// never NaN, and allocate nothing.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>

#include "inertia/collision/collider.h"
#include "inertia/core/types.h"

namespace inertia {

/// The closest points of two convex shapes.
struct ClosestPoints {
  /// Distance between the shapes (m), >= 0; 0 when they touch or overlap.
  Real distance = 0;
  /// Closest point on A's surface (m, world). When overlapping: A's deepest point in B
  /// (as Penetration::pointA).
  Vec3 pointA = Vec3::Zero();
  /// Closest point on B's surface (m, world). When overlapping: as Penetration::pointB.
  Vec3 pointB = Vec3::Zero();
  /// Unit direction from A to B: (pointB - pointA) / distance when apart; when overlapping, the
  /// penetration normal (moving B along it separates the shapes fastest).
  Vec3 normal = Vec3::UnitY();
  /// True when the shapes overlap (penetration depth > 0) or touch within rounding.
  bool overlapping = false;
};

/// The closest points of convex `a` at `poseA` and `b` at `poseB`, by GJK with the
/// signed-volume sub-algorithm (Montanari et al. 2017) on the shapes' cores (a sphere's centre,
/// a capsule's segment, the box, cylinder or hull), then the radii; EPA supplies the normal
/// and points when the cores overlap. Accuracy: polytope pairs are exact up to rounding (a few
/// ulps of the coordinates); pairs with a cylinder to a relative 1e-6 in float (1e-12 in double),
/// plus the same rounding. That is the accuracy of the distance and the points, except that in
/// double a point on a cylinder's curved side may lie up to 1e-10 of the pair's size off it; the
/// normal of nearly touching shapes is only as good as pointB - pointA, which carries their
/// rounding.
ClosestPoints closestPoints(const Collider& a, const Transform& poseA, const Collider& b,
                            const Transform& poseB);

/// How deep two convex shapes overlap.
struct Penetration {
  /// Penetration depth (m), > 0: the length of the shortest translation that separates them.
  Real depth = 0;
  /// Unit direction from A to B: translating B by depth * normal separates the shapes.
  Vec3 normal = Vec3::UnitY();
  Vec3 pointA = Vec3::Zero();  ///< A's deepest point inside B, on A's surface (m, world).
  /// B's deepest point inside A, on B's surface (m, world): pointA - pointB == depth * normal.
  Vec3 pointB = Vec3::Zero();
};

/// The penetration of convex `a` and `b`, or nothing when they are apart or only touch. GJK on
/// the cores, then EPA (expanding polytope, van den Bergen 2001) when the cores themselves
/// overlap; rounded shapes whose cores are apart need no EPA (depth = radii - core distance).
/// EPA is exact for polytopes (up to rounding) and within a relative 1e-5 of the depth in float
/// (1e-7 in double) for cylinders, plus rounding: a few dozen ulps of the pair's size (its
/// centres' distance plus the shapes' reach); moving B by depth * normal separates the pair to
/// the same accuracy. tests/collision/penetration_oracle_test.cpp checks this on random pairs of
/// every kind against an exact reference.
std::optional<Penetration> penetration(const Collider& a, const Transform& poseA, const Collider& b,
                                       const Transform& poseB);

/// True when convex `a` and `b` overlap or touch (GJK only; no EPA).
bool overlap(const Collider& a, const Transform& poseA, const Collider& b, const Transform& poseB);

/// The closest points of two triangles.
struct TriangleDistance {
  /// Distance between the triangles (m), >= 0; 0 when they intersect or touch.
  Real distance = 0;
  /// Closest point on the first triangle (m); when they intersect, a common point.
  Vec3 pointA = Vec3::Zero();
  /// Closest point on the second triangle (m); equal to pointA when they intersect.
  Vec3 pointB = Vec3::Zero();
};

/// The exact distance between triangles (a0, a1, a2) and (b0, b1, b2), both in one frame: 0 when
/// an edge of one crosses the other (Moller-Trumbore on the six edges, the ones that straddle the
/// other's plane), else the nearest of the nine edge-edge segment pairs and the six vertex-face
/// projections (Ericson, Real-Time Collision Detection, 5.1.9 and 5.1.5), which contain the
/// closest pair of two disjoint triangles. Never NaN for finite input, also for zero-area
/// triangles (a sliver is treated as its edges).
TriangleDistance triangleDistance(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                                  const Vec3& b1, const Vec3& b2);

/// The closest points of two triangle meshes.
struct MeshDistance {
  /// Distance between the meshes' surfaces (m), >= 0; 0 when two triangles intersect or touch.
  /// Surfaces only: a mesh lying wholly inside a closed mesh is at a positive distance.
  Real distance = 0;
  Vec3 pointA = Vec3::Zero();   ///< Closest point on A's triangle (m, world).
  Vec3 pointB = Vec3::Zero();   ///< Closest point on B's triangle (m, world).
  std::uint32_t triangleA = 0;  ///< A's mesh triangle holding pointA.
  std::uint32_t triangleB = 0;  ///< B's mesh triangle holding pointB.
};

/// The distance between triangle meshes `a` at `poseA` and `b` at `poseB` (both colliders of
/// ShapeType::Mesh, else InvalidArgument), or nothing when it exceeds `maxDistance` (m). Both
/// BVHs traversed together by branch and bound: pairs of nodes visited nearest box pair first
/// (lower bound: the larger of the box gaps in A's frame and in B's, each tree's boxes carried
/// into the other's frame), pairs no nearer than the best so far pruned, triangleDistance on
/// the pairs of two leaves (skipped when their boxes or planes are farther than the best). A
/// first pass with a zero bound finds an intersecting pair, if any, and stops there. Computed in
/// A's frame: exact up to the rounding of B's corners carried into it (a few ulps of the
/// coordinates). Allocates nothing.
std::optional<MeshDistance> meshDistance(const Collider& a, const Transform& poseA,
                                         const Collider& b, const Transform& poseB,
                                         Real maxDistance = std::numeric_limits<Real>::infinity());

/// True when two triangle meshes intersect or touch (some pair of triangles shares a point):
/// meshDistance with maxDistance 0, which stops at the first intersecting pair.
bool meshesOverlap(const Collider& a, const Transform& poseA, const Collider& b,
                   const Transform& poseB);

}  // namespace inertia
