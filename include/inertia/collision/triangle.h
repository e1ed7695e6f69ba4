// Single-triangle primitives shared by meshes, height fields and hull tests: the closest point
// on a triangle (with the Voronoi feature it lies on) and the two-sided ray-triangle test.
#pragma once

#include <cstdint>

#include "inertia/core/types.h"

namespace inertia {

/// The feature of a triangle (a, b, c) a closest point lies on. Edge k runs from vertex k to
/// vertex (k + 1) % 3, as in TriangleMesh: Edge0 = ab, Edge1 = bc, Edge2 = ca.
enum class TriangleFeature : std::uint8_t { Vertex0, Vertex1, Vertex2, Edge0, Edge1, Edge2, Face };

/// The closest point on a triangle and its feature.
struct TriangleClosest {
  Vec3 point = Vec3::Zero();  ///< Closest point of the triangle (m).
  TriangleFeature feature = TriangleFeature::Face;
};

/// The point of the triangle (a, b, c) closest to `p`, by the Voronoi regions of its vertices,
/// edges and face (Ericson, Real-Time Collision Detection, 5.1.5). Never NaN for finite input,
/// also for slivers (a degenerate triangle falls back to its closest edge).
TriangleClosest closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Moller-Trumbore ray-triangle intersection, two-sided: the s in [0, maxFraction] at which
/// origin + s * direction meets the triangle (boundary included), or a negative value for no
/// hit (also for rays parallel to the triangle's plane). Division-free until the final
/// fraction, so never NaN for finite input. `direction` need not be unit.
Real intersectRayTriangle(const Vec3& origin, const Vec3& direction, Real maxFraction,
                          const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace inertia
