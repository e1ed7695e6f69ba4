// Support mappings s(d) = argmax_x d . x of the convex shapes (van den Bergen 2003, ch. 4).
#include "inertia/geometry/support.h"

#include <cmath>
#include <string>
#include <type_traits>

#include "inertia/core/error.h"

namespace inertia {

Vec3 support(const Sphere& sphere, const Vec3& d) {
  const Real len = d.norm();
  return len > 0 ? Vec3(d / len * sphere.radius) : Vec3(sphere.radius, 0, 0);
}

// Minkowski sum of the core segment and a ball: the sum of the two supports.
Vec3 support(const Capsule& capsule, const Vec3& d) {
  const Vec3 tip(0, d.y() >= 0 ? capsule.halfHeight : -capsule.halfHeight, 0);
  return tip + support(Sphere{capsule.radius}, d);
}

Vec3 support(const Box& box, const Vec3& d) {
  const Vec3& h = box.halfExtents;
  return {d.x() >= 0 ? h.x() : -h.x(), d.y() >= 0 ? h.y() : -h.y(), d.z() >= 0 ? h.z() : -h.z()};
}

// The cap on d's side, then the rim point of that cap in d's radial direction.
Vec3 support(const Cylinder& cylinder, const Vec3& d) {
  const Real radial = std::hypot(d.x(), d.z());
  const Real y = d.y() >= 0 ? cylinder.halfHeight : -cylinder.halfHeight;
  if (!(radial > 0)) return {0, y, 0};
  // Divide first: r / radial may overflow for a tiny d.
  return {d.x() / radial * cylinder.radius, y, d.z() / radial * cylinder.radius};
}

Vec3 support(const ConvexHull& hull, const Vec3& d) {
  const auto& v = hull.vertices();
  std::size_t best = 0;
  Real bestDot = v[0].dot(d);
  for (std::size_t i = 1; i < v.size(); ++i) {
    const Real dot = v[i].dot(d);
    if (dot > bestDot) bestDot = dot, best = i;
  }
  return v[best];
}

Vec3 support(const Shape& shape, const Vec3& d) {
  return shape.visit([&](const auto& s) -> Vec3 {
    // Listed explicitly: Plane, Compound, ... convert implicitly to Shape, and would recurse.
    using S = std::decay_t<decltype(s)>;
    if constexpr (std::is_same_v<S, Sphere> || std::is_same_v<S, Capsule> ||
                  std::is_same_v<S, Box> || std::is_same_v<S, Cylinder> ||
                  std::is_same_v<S, ConvexHull>) {
      return support(s, d);
    } else {
      throw InvalidArgument(std::string("support: a ") + shapeTypeName(shape.type()) +
                            " is not convex and has no support function");
    }
  });
}

}  // namespace inertia
