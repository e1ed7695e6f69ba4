#include "integrate.h"

#include <Eigen/LU>

#include "inertia/core/math.h"

namespace inertia::detail {

Vec3 implicitGyroscopic(const Quat& q, const Mat3& I, const Vec3& w, Real h) {
  const Vec3 w1 = q.conjugate() * w;
  const Vec3 Iw = I * w1;
  const Vec3 f = h * w1.cross(Iw);
  const Mat3 J = I + h * (skew(w1) * I - skew(Iw));
  const Vec3 w2 = w1 - J.partialPivLu().solve(f);
  // A Newton matrix singular in float (a light needle, h |w| near 1: two of J's rows came out
  // proportional, and the LU's last pivot 0 gave 0/0; fuzz input
  // world-micro-body-gyroscopic-nan): the substep keeps w, the explicit step without the
  // gyroscopic term.
  return w2.allFinite() ? Vec3(q * w2) : w;
}

void splitFreeRotation(Quat& principal, const Vec3& moments, const Vec3& L, Real h) {
  // Body-frame momentum; in flow i, L_body rotates about e_i by -theta while the body turns
  // by +theta, theta = tau * L_i / I_i (L_i constant along flow i).
  Vec3 Lb = principal.conjugate() * L;
  auto flow = [&](int axis, Real tau) {
    const Real theta = tau * Lb[axis] / moments[axis];
    const Quat turn(Eigen::AngleAxis<Real>(theta, Vec3::Unit(axis)));
    principal = principal * turn;
    Lb = turn.conjugate() * Lb;
  };
  const Real half = Real(0.5) * h;
  flow(0, half);
  flow(1, half);
  flow(2, h);
  flow(1, half);
  flow(0, half);
  principal.normalize();
}

}  // namespace inertia::detail
