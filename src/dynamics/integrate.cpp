#include "integrate.h"

#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "inertia/core/math.h"

namespace inertia::detail {

Vec3 implicitGyroscopic(const Quat& q, const Mat3& I, const Vec3& w, Real h) {
  const Vec3 w1 = q.conjugate() * w;
  const Vec3 Iw = I * w1;
  const Vec3 f = h * w1.cross(Iw);
  const Mat3 J = I + h * (skew(w1) * I - skew(Iw));
  // The Newton step by J's closed-form inverse (cofactors over the determinant): a partial-pivot
  // LU, out of line, was a tenth of a chain of capsules' step. A J singular within its rounding
  // (a light needle, h |w| near 1: two rows came out proportional in float; fuzz input
  // world-micro-body-gyroscopic-nan) keeps w for the substep, the explicit step without the
  // gyroscopic term. The cofactor expansion's rounding: six products of three entries (2 eps
  // each), their differences and sum (3 eps more), at most 5 eps of the products' magnitudes,
  // which sum to at most 3 sqrt(3) |J_0| |J_1| |J_2| (26 eps of Hadamard's bound on |det J|).
  // A determinant below 64 eps of the bound is rounding's. J is scaled to entries of order 1
  // first: a millimetre body's inertia (1e-12 kg m^2) cubed is near float's smallest normal.
  const Real scale = J.cwiseAbs().maxCoeff();
  if (!(scale > 0) || !std::isfinite(scale)) return w;
  const Mat3 Js = J * (1 / scale);
  Mat3 inverse;
  Real det = 0;
  bool invertible = false;
  Js.computeInverseAndDetWithCheck(inverse, det, invertible, Real(0));
  const Real bound = Js.row(0).norm() * Js.row(1).norm() * Js.row(2).norm();
  if (!(std::abs(det) > 64 * std::numeric_limits<Real>::epsilon() * bound)) return w;
  const Vec3 w2 = w1 - times(inverse, f * (1 / scale));
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
