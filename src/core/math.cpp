#include "inertia/core/math.h"

namespace inertia {

Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(),  //
      a.z(), 0, -a.x(),   //
      -a.y(), a.x(), 0;
  return m;
}

Quat quatFromRotationVector(const Vec3& v) {
  Real angle = v.norm();
  if (angle < Real(1e-8)) {
    // Taylor expansion of sin(a/2)/a keeps small rotations accurate and avoids 0/0.
    Quat r(1, Real(0.5) * v.x(), Real(0.5) * v.y(), Real(0.5) * v.z());
    r.normalize();
    return r;
  }
  Real s = std::sin(Real(0.5) * angle) / angle;
  return Quat(std::cos(Real(0.5) * angle), s * v.x(), s * v.y(), s * v.z());
}

Quat integrateRotationExact(const Quat& q, const Vec3& w, Real h) {
  Quat r = quatFromRotationVector(w * h) * q;
  r.normalize();
  return r;
}

Vec3 rotationVector(const Quat& qIn) {
  Quat q = qIn.w() < 0 ? Quat(-qIn.w(), -qIn.x(), -qIn.y(), -qIn.z()) : qIn;
  Vec3 v = q.vec();
  Real s = v.norm();
  if (s < Real(1e-8)) return Real(2) * v;
  Real angle = Real(2) * std::atan2(s, q.w());
  return v * (angle / s);
}

}  // namespace inertia
