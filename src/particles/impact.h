// Newton's impact model with Coulomb friction on a point's velocity, shared by the particle
// systems' and the deformables' obstacle collisions.
#pragma once

#include <algorithm>

#include "inertia/core/types.h"

namespace inertia::detail {

/// Newton's impact model (seed 000): the normal velocity reverses scaled by e (0 below
/// `threshold` m/s); Coulomb friction takes at most mu times the normal velocity change off the
/// tangential velocity. Nothing happens to a velocity leaving the surface (v . n >= 0).
inline void respondToImpact(Vec3& v, const Vec3& n, Real e, Real mu, Real threshold) {
  const Real vn = v.dot(n);
  if (vn >= 0) return;
  const Real ee = -vn < threshold ? Real(0) : e;
  const Real dvn = -(1 + ee) * vn;
  Vec3 vt = v - vn * n;
  const Real vtNorm = vt.norm();
  if (vtNorm > 0) vt *= std::max(Real(0), 1 - mu * dvn / vtNorm);
  v = vt - ee * vn * n;
}

}  // namespace inertia::detail
