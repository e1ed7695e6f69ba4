// Support functions of the convex shapes, the primitive GJK, EPA and MPR are built on.
#pragma once

#include "inertia/core/types.h"
#include "inertia/geometry/shapes.h"

namespace inertia {

/// Support mapping s(d) = argmax over x in the shape of d . x, in the shape's local frame (m),
/// for a direction `d` in the same frame (need not be unit; for d = 0 any point of the shape).
/// When several points tie (a face of a box, the cap of a cylinder) any of them is returned.
Vec3 support(const Sphere& sphere, const Vec3& d);
Vec3 support(const Capsule& capsule, const Vec3& d);
Vec3 support(const Box& box, const Vec3& d);
Vec3 support(const Cylinder& cylinder, const Vec3& d);
/// Brute force over the vertices, O(V); the collision layer may hill-climb with vertexEdges().
Vec3 support(const ConvexHull& hull, const Vec3& d);

/// Dispatches on the type; throws InvalidArgument for a shape that is not convex
/// (plane, mesh, height field, compound).
Vec3 support(const Shape& shape, const Vec3& d);

}  // namespace inertia
