// Internal: the constraint parts joints are built from (Jolt's constraint parts; Catto's soft
// constraints as in Box2D v3). A part is N coupled velocity rows between two solver bodies,
//   J_i = [-l_i, -(rA x l_i + g_i), l_i, rB x l_i + g_i]   (on vA, wA, vB, wB),
// a linear direction l_i with lever arms rA and rB, plus a pure angular axis g_i. A ball joint's
// anchors are three linear rows; a hinge's aligned axes two angular rows; a limit, motor or
// spring on a hinge's angle one angular row. A joint's locked rows are solved together as one
// block:
//   lambda = -massScale K^-1 (J v + bias) - impulseScale lambda_acc,   K = J M^-1 J^T,
// with Box2D v3's soft coefficients (bias rate, mass and impulse scales), which make a rigid
// row (massScale 1, impulseScale 0) or a spring of given frequency and damping ratio.
#pragma once

#include <algorithm>
#include <array>

#include "contact_solver.h"
#include "solver_body.h"

namespace inertia::detail {

/// One row's Jacobian: direction l (m/m), lever arms from the centres of mass (m), and a pure
/// angular axis g.
struct JointRow {
  Vec3 linear = Vec3::Zero();
  Vec3 armA = Vec3::Zero();
  Vec3 armB = Vec3::Zero();
  Vec3 angular = Vec3::Zero();

  Vec3 angularA() const { return armA.cross(linear) + angular; }
  Vec3 angularB() const { return armB.cross(linear) + angular; }
};

inline JointRow linearRow(const Vec3& direction, const Vec3& armA, const Vec3& armB) {
  return {direction, armA, armB, Vec3::Zero()};
}
inline JointRow angularRow(const Vec3& axis) {
  return {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), axis};
}

/// Up to six coupled rows and their accumulated impulses (N s, or N m s for angular rows),
/// kept from substep to substep and step to step for warm starting. A joint's locked rows
/// form one block, solved together: solved one after another, a light body on a long lever
/// arm (a pendulum's bob) converges so slowly between its anchor rows and its angular rows that
/// Baumgarte's feedback grows the error instead of removing it.
struct RowBlock {
  static constexpr int kMax = 6;
  using Vector = Eigen::Matrix<Real, Eigen::Dynamic, 1, 0, kMax, 1>;
  using Matrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, 0, kMax, kMax>;

  std::array<JointRow, kMax> rows{};
  int count = 0;
  Eigen::Matrix<Real, kMax, 1> impulse = Eigen::Matrix<Real, kMax, 1>::Zero();

  void clear() { count = 0; }
  void add(const JointRow& row) { rows[std::size_t(count++)] = row; }

  /// The relative velocity along the rows, J v.
  Vector velocity(const SolverBody& a, const SolverBody& b) const {
    Vector c(count);
    for (int i = 0; i < count; ++i) {
      const JointRow& r = rows[std::size_t(i)];
      c(i) = r.linear.dot(b.v - a.v) + r.angularB().dot(b.w) - r.angularA().dot(a.w);
    }
    return c;
  }
  /// K = J M^-1 J^T.
  Matrix mass(const SolverBody& a, const SolverBody& b) const {
    std::array<Vec3, kMax> ja, jb, ia, ib;
    for (std::size_t i = 0; i < std::size_t(count); ++i) {
      ja[i] = rows[i].angularA();
      jb[i] = rows[i].angularB();
      ia[i] = a.invInertia * ja[i];
      ib[i] = b.invInertia * jb[i];
    }
    Matrix k(count, count);
    for (std::size_t i = 0; i < std::size_t(count); ++i)
      for (std::size_t j = 0; j <= i; ++j)
        k(int(i), int(j)) = k(int(j), int(i)) =
            (a.invMass + b.invMass) * rows[i].linear.dot(rows[j].linear) + ja[i].dot(ia[j]) +
            jb[i].dot(ib[j]);
    return k;
  }
  /// Applies impulses `lambda` along the rows to both bodies.
  template <class V>
  void apply(SolverBody& a, SolverBody& b, const V& lambda) const {
    Vec3 p = Vec3::Zero(), la = Vec3::Zero(), lb = Vec3::Zero();
    for (std::size_t i = 0; i < std::size_t(count); ++i) {
      p += rows[i].linear * lambda(int(i));
      la += rows[i].angularA() * lambda(int(i));
      lb += rows[i].angularB() * lambda(int(i));
    }
    a.v -= a.invMass * p;
    a.w -= a.invInertia * la;
    b.v += b.invMass * p;
    b.w += b.invInertia * lb;
  }
  void warmStart(SolverBody& a, SolverBody& b) const { apply(a, b, impulse.head(count)); }

  /// One equality solve towards C = 0 (C the rows' position errors, m or rad) with `soft`'s
  /// coefficients.
  void solve(SolverBody& a, SolverBody& b, const Vector& C, const Softness& soft) {
    if (count == 0) return;
    Vector delta = -soft.massScale * mass(a, b).ldlt().solve(velocity(a, b) + soft.biasRate * C);
    delta -= soft.impulseScale * impulse.head(count);
    impulse.head(count) += delta;
    apply(a, b, delta);
  }

  /// A velocity block driven to zero with its accumulated impulse inside a ball of radius
  /// `maxImpulse` (a ball joint's friction torque).
  void solveFriction(SolverBody& a, SolverBody& b, Real maxImpulse) {
    const Vector old = impulse.head(count);
    Vector next = old - mass(a, b).ldlt().solve(velocity(a, b));
    const Real norm = next.norm();
    if (norm > maxImpulse) next *= maxImpulse / norm;
    impulse.head(count) = next;
    apply(a, b, next - old);
  }

  /// The force (or impulse) these rows put on B: the linear part and the torque beyond the
  /// linear part's moment about B's anchor.
  void reaction(Vec3& linear, Vec3& angular) const {
    for (std::size_t i = 0; i < std::size_t(count); ++i) {
      linear += rows[i].linear * impulse(int(i));
      angular += rows[i].angular * impulse(int(i));
    }
  }
};

/// A joint's free coordinate (an angle or a position along an axis): one row shared by the
/// spring, the motor, the friction and the two limits, each with its own accumulated impulse.
struct AxisRows {
  JointRow row;
  /// Accumulated impulses; `lock` holds a coordinate fixed (a distance joint's rigid rod).
  Real spring = 0, motor = 0, friction = 0, lower = 0, upper = 0, lock = 0;

  Real total() const { return spring + motor + friction + lower - upper + lock; }
  Real velocity(const SolverBody& a, const SolverBody& b) const {
    return row.linear.dot(b.v - a.v) + row.angularB().dot(b.w) - row.angularA().dot(a.w);
  }
  Real mass(const SolverBody& a, const SolverBody& b) const {
    const Vec3 ja = row.angularA(), jb = row.angularB();
    const Real k = (a.invMass + b.invMass) * row.linear.squaredNorm() + ja.dot(a.invInertia * ja) +
                   jb.dot(b.invInertia * jb);
    return k > 0 ? 1 / k : 0;
  }
  void apply(SolverBody& a, SolverBody& b, Real lambda) const {
    a.v -= a.invMass * lambda * row.linear;
    a.w -= a.invInertia * (lambda * row.angularA());
    b.v += b.invMass * lambda * row.linear;
    b.w += b.invInertia * (lambda * row.angularB());
  }
  void warmStart(SolverBody& a, SolverBody& b) const { apply(a, b, total()); }
  void reaction(Vec3& linear, Vec3& angular) const {
    linear += row.linear * total();
    angular += row.angular * total();
  }

  /// A bounded velocity row: drives J v to `speed` with |impulse| <= maxImpulse.
  void solveMotor(SolverBody& a, SolverBody& b, Real& accumulated, Real speed, Real maxImpulse) {
    const Real m = mass(a, b);
    const Real old = accumulated;
    accumulated = std::clamp(old - m * (velocity(a, b) - speed), -maxImpulse, maxImpulse);
    apply(a, b, accumulated - old);
  }
  /// A soft row towards C = 0 (a spring or a servo), |impulse| <= maxImpulse.
  void solveSoft(SolverBody& a, SolverBody& b, Real& accumulated, Real C, const Softness& soft,
                 Real maxImpulse) {
    const Real m = mass(a, b);
    const Real old = accumulated;
    const Real lambda =
        -soft.massScale * m * (velocity(a, b) + soft.biasRate * C) - soft.impulseScale * old;
    accumulated = std::clamp(old + lambda, -maxImpulse, maxImpulse);
    apply(a, b, accumulated - old);
  }
  /// A one-sided row keeping C >= 0 (C = coordinate - lower, or upper - coordinate with
  /// sign -1): speculative while C > 0 (it lets the gap close in this substep, Box2D v3),
  /// `soft` while violated.
  void solveLimit(SolverBody& a, SolverBody& b, Real& accumulated, Real C, Real sign,
                  const Softness& soft, Real invH) {
    Real bias = 0, massScale = 1, impulseScale = 0;
    if (C > 0) {
      bias = C * invH;
    } else {
      bias = soft.biasRate * C;
      massScale = soft.massScale;
      impulseScale = soft.impulseScale;
    }
    const Real m = mass(a, b);
    const Real old = accumulated;
    const Real lambda = -massScale * m * (sign * velocity(a, b) + bias) - impulseScale * old;
    accumulated = std::max(old + lambda, Real(0));
    apply(a, b, sign * (accumulated - old));
  }
};

}  // namespace inertia::detail
