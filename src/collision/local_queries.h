// Internal: the point and ray queries in a shape's local frame, shared by queryPoint/castRay
// and by compounds (which recurse into their children without composing transforms).
#pragma once

#include <cmath>
#include <limits>
#include <optional>

#include "inertia/collision/queries.h"

namespace inertia::detail {

/// v / |v|, or `fallback` when |v|^2 underflows (or overflows): never NaN for finite v.
inline Vec3 normalizedOr(const Vec3& v, const Vec3& fallback) {
  const Real n2 = v.squaredNorm();
  if (n2 > std::numeric_limits<Real>::min() && n2 < std::numeric_limits<Real>::infinity())
    return v / std::sqrt(n2);
  return fallback;
}

/// v / |v| for finite non-zero v, also where |v|^2 falls below float's normal range and so
/// keeps too few bits to normalise by (a cross product of edges of 1e-11 m, 1e-22 m^2, whose
/// square is denormal, came out 0.999 long): there v is first scaled by its largest component.
inline Vec3 unitOf(const Vec3& v) {
  const Real n2 = v.squaredNorm();
  if (n2 > std::numeric_limits<Real>::min()) return v / std::sqrt(n2);
  const Vec3 u = v / v.cwiseAbs().maxCoeff();
  return u / u.norm();
}

/// queryPoint with the point and the answer in the collider's local frame.
PointQuery queryPointLocal(const Collider& collider, const Vec3& p);

/// A ray hit in the local frame: fraction and unit normal facing the origin's side.
struct LocalHit {
  Real fraction = 0;
  Vec3 normal = Vec3::UnitY();
};
/// castRay in the collider's local frame (direction non-zero, maxFraction >= 0).
std::optional<LocalHit> castRayLocal(const Collider& collider, const Vec3& origin,
                                     const Vec3& direction, Real maxFraction);

}  // namespace inertia::detail
