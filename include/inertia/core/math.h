// Small helpers over the core types: skew matrices, quaternion integration, finiteness checks.
#pragma once

#include <cmath>

#include "inertia/core/types.h"

namespace inertia {

/// The cross-product matrix: skew(a) * b == a.cross(b).
Mat3 skew(const Vec3& a);

/// Advances an orientation by angular velocity `w` (rad/s, world frame) over `h` seconds with
/// the first-order update q' = q + h/2 (0, w) q, then renormalises (Baraff's SIGGRAPH notes,
/// eq. for dq/dt = 1/2 w q). Cheap and what the rigid-body solvers use every substep, for every
/// body: inline, so that the substep loop is not a loop of calls.
inline Quat integrateRotation(const Quat& q, const Vec3& w, Real h) {
  const Quat dq = Quat(0, w.x(), w.y(), w.z()) * q;  // dq/dt = 1/2 (0, w) q
  Quat r(q.w() + Real(0.5) * h * dq.w(), q.x() + Real(0.5) * h * dq.x(),
         q.y() + Real(0.5) * h * dq.y(), q.z() + Real(0.5) * h * dq.z());
  r.normalize();
  return r;
}

/// m v for a 3x3 matrix, in scalars and in the order Eigen sums a float product's rows,
/// m(i,0) v0 + (m(i,1) v1 + m(i,2) v2): the same bits as `m * v` in the float build (in double,
/// Eigen sums two of the rows left to right, in SSE pairs). GCC at -O2 left Eigen's product an
/// out-of-line call in the joint passes (a tenth of a joint grid's step).
inline Vec3 times(const Mat3& m, const Vec3& v) {
  const Real x = v.x(), y = v.y(), z = v.z();
  return {m(0, 0) * x + (m(0, 1) * y + m(0, 2) * z), m(1, 0) * x + (m(1, 1) * y + m(1, 2) * z),
          m(2, 0) * x + (m(2, 1) * y + m(2, 2) * z)};
}

/// Advances an orientation by the exact rotation of constant `w` over `h`: q' = exp(h w / 2) q.
/// Exact for constant angular velocity; used where accuracy matters more than cost.
Quat integrateRotationExact(const Quat& q, const Vec3& w, Real h);

/// The rotation vector (axis * angle, rad) of a unit quaternion; inverse of quatFromRotationVector.
Vec3 rotationVector(const Quat& q);
/// The unit quaternion of a rotation by |v| radians about v.
Quat quatFromRotationVector(const Vec3& v);

/// True when every component is finite (no NaN, no infinity).
template <class Derived>
bool allFinite(const Eigen::MatrixBase<Derived>& m) {
  return m.allFinite();
}
inline bool allFinite(const Quat& q) { return q.coeffs().allFinite(); }
inline bool isFinite(Real x) { return std::isfinite(x); }

}  // namespace inertia
