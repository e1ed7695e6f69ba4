// Damped spring forces and their analytic Jacobians (seed 002, "Jacobian Matrix K";
// Baraff and Witkin 1998, section 4).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include "inertia/deformable/model.h"

namespace inertia::detail {

template <class S>
using Vec3Of = Eigen::Matrix<S, 3, 1>;

/// The force of spring `s` on vertex a (on b it is the opposite):
/// F_a = -(k (l - L) + c (v_a - v_b) . u) u. Zero for a collapsed spring (l = 0: no direction).
template <class S>
Vec3Of<S> springForce(const Spring& s, const Vec3Of<S>& xa, const Vec3Of<S>& xb,
                      const Vec3Of<S>& va, const Vec3Of<S>& vb) {
  const Vec3Of<S> d = xa - xb;
  const S l = d.norm();
  if (!(l > S(0))) return Vec3Of<S>::Zero();
  const Vec3Of<S> u = d / l;
  const S magnitude = S(s.stiffness) * (l - S(s.restLength)) + S(s.damping) * (va - vb).dot(u);
  return -magnitude * u;
}

/// Adds every unbroken spring's forces (N) to f (3 per vertex); x and v are 3 per vertex.
/// Springs are summed in order, so the result does not depend on threads.
template <class S>
void addSpringForces(std::span<const Spring> springs, std::span<const std::uint8_t> broken,
                     const S* x, const S* v, S* f) {
  for (std::size_t k = 0; k < springs.size(); ++k) {
    if (broken[k]) continue;
    const Spring& s = springs[k];
    using Map = Eigen::Map<const Vec3Of<S>>;
    const Vec3Of<S> fa =
        springForce<S>(s, Map(x + 3 * s.a), Map(x + 3 * s.b), Map(v + 3 * s.a), Map(v + 3 * s.b));
    Eigen::Map<Vec3Of<S>>(f + 3 * s.a) += fa;
    Eigen::Map<Vec3Of<S>>(f + 3 * s.b) -= fa;
  }
}

/// The spring's Jacobian blocks for vertex a: dx = dF_a/dx_a, dv = dF_a/dv_a. The other blocks
/// follow: dF_a/dx_b = -dx, dF_b/dx_b = dx (likewise dv).
///   dF_a/dx_a = -k (u u^T + max(0, 1 - L / l) (I - u u^T)),   dF_a/dv_a = -c u u^T.
/// The transverse term is clamped at zero for a compressed spring (l < L; Choi and Ko 2002):
/// it would make the block indefinite and the implicit system lose the positive definiteness
/// conjugate gradients need. As Baraff and Witkin do, the damping force's dependence on
/// position is left out (it is not symmetric).
struct SpringJacobian {
  Eigen::Matrix3d dx = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d dv = Eigen::Matrix3d::Zero();
};

inline SpringJacobian springJacobian(const Spring& s, const Eigen::Vector3d& xa,
                                     const Eigen::Vector3d& xb) {
  SpringJacobian j;
  const Eigen::Vector3d d = xa - xb;
  const double l = d.norm();
  if (!(l > 0)) return j;
  const Eigen::Vector3d u = d / l;
  const Eigen::Matrix3d uu = u * u.transpose();
  const double transverse = std::max(0.0, 1.0 - double(s.restLength) / l);
  j.dx = -double(s.stiffness) * (uu + transverse * (Eigen::Matrix3d::Identity() - uu));
  j.dv = -double(s.damping) * uu;
  return j;
}

/// The convex majorant of a spring's energy that the implicit step minimises (implicit_euler.h):
///     U~(d) = k/2 (max(l - L, 0)^2 + max(L - u0 . d, 0)^2),   l = |d|,
/// with u0 the spring's unit direction at the step's start (zero for a collapsed spring, which
/// makes the second term k L^2 / 2). U~ >= U = k (l - L)^2 / 2 everywhere and U~ = U at the
/// start: a stretched spring is itself, a compressed one pushes along u0. Both terms are convex.
struct SurrogateSpring {
  double k, rest;
  Eigen::Vector3d u0;

  double tension(const Eigen::Vector3d& d) const { return std::max(0.0, d.norm() - rest); }
  double compression(const Eigen::Vector3d& d) const { return std::max(0.0, rest - u0.dot(d)); }
  double energy(const Eigen::Vector3d& d) const {
    const double t = tension(d), c = compression(d);
    return 0.5 * k * (t * t + c * c);
  }
  /// -dU~/dd: the force on vertex a (on b it is the opposite).
  Eigen::Vector3d force(const Eigen::Vector3d& d) const {
    const double l = d.norm(), t = tension(d);
    Eigen::Vector3d f = k * compression(d) * u0;
    if (t > 0) f -= k * t * (d / l);
    return f;
  }
  /// d^2 U~/dd^2, positive semi-definite: k (u u^T + (1 - L/l)(I - u u^T)) while stretched,
  /// plus k u0 u0^T while compressed along u0.
  Eigen::Matrix3d stiffness(const Eigen::Vector3d& d) const {
    Eigen::Matrix3d kk = Eigen::Matrix3d::Zero();
    const double l = d.norm();
    if (l > rest) {
      const Eigen::Vector3d u = d / l;
      const Eigen::Matrix3d uu = u * u.transpose();
      kk += k * (uu + (1 - rest / l) * (Eigen::Matrix3d::Identity() - uu));
    }
    if (compression(d) > 0) kk += k * u0 * u0.transpose();
    return kk;
  }
  /// U~(d + delta) - U~(d), formed from differences so that a line search's small changes are
  /// not lost to cancellation: l' - l = delta . (d' + d) / (l' + l).
  double energyChange(const Eigen::Vector3d& d, const Eigen::Vector3d& delta) const {
    const Eigen::Vector3d e = d + delta;
    const double lo = d.norm(), ln = e.norm();
    const double to = std::max(0.0, lo - rest), tn = std::max(0.0, ln - rest);
    const double dt = (to > 0 && tn > 0 && ln + lo > 0) ? delta.dot(e + d) / (ln + lo) : tn - to;
    const double co = compression(d), cn = compression(e);
    const double dc = (co > 0 && cn > 0) ? -u0.dot(delta) : cn - co;
    return 0.5 * k * (dt * (tn + to) + dc * (cn + co));
  }
};

}  // namespace inertia::detail
