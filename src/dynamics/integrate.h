// Internal: the rotational integrators of rigid bodies.
#pragma once

#include <cmath>

#include "inertia/core/types.h"

namespace inertia::detail {

/// A body's speed cap: scales v down to the norm `limit` when it is faster (the direction
/// kept). True when it did. A vector whose squared norm overflows (components past 1e19 in
/// float) is measured without overflow: its plain norm, infinite, would scale it to zero.
inline bool capSpeed(Vec3& v, Real limit) {
  Real n = v.norm();
  if (!(n > limit)) return false;
  if (std::isinf(n)) n = v.stableNorm();
  v *= limit / n;
  return true;
}

/// Implicit gyroscopic update (Catto, GDC 2015 "Numerical Methods"): one Newton step of the
/// backward-Euler Euler equation I (w2 - w1) + h w2 x I w2 = 0 in the body frame, starting
/// from w1. Stable for thin, fast-spinning bodies (it loses energy, never gains it). `q` is the
/// body's orientation, `inertiaBody` its inertia in body axes; w is in world axes (rad/s).
Vec3 implicitGyroscopic(const Quat& q, const Mat3& inertiaBody, const Vec3& w, Real h);

/// Free rotation of a torque-free body over h by the symplectic splitting of Dullweber,
/// Leimkuhler and McLachlan (1997): the kinetic energy split by principal axes, each part an
/// exact rotation about one axis, composed 1-2-3-2-1 (Strang). The world angular momentum
/// `L` is conserved exactly and the energy error stays bounded (no drift).
/// `principal` maps the principal frame to world (the body's orientation times the
/// principal axes' rotation); `moments` are the principal moments (kg m^2, > 0). Updates
/// `principal`; returns nothing else (w = principal * (L_body / moments)).
void splitFreeRotation(Quat& principal, const Vec3& moments, const Vec3& L, Real h);

}  // namespace inertia::detail
