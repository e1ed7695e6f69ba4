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
#include <cmath>
#include <limits>

#include "contact_solver.h"
#include "inertia/core/math.h"
#include "solver_body.h"

namespace inertia::detail {

/// The most a joint row's bias asks for: m/s along a linear row, rad/s about an angular one.
/// Past every body's default speed cap (400 m/s, 200 rad/s), so that no joint meant to hold is
/// slowed; yet a joint created with its anchors 100 km apart no longer asks a light body for
/// speeds its position update never follows, which drove the velocities past float's range
/// within one substep's iterations (fuzz input world-joint-100km-error-overflow).
inline constexpr Real kMaxJointBias = 1000;

/// The bias velocity of a soft row towards C = 0, within kMaxJointBias.
inline Real jointBias(const Softness& soft, Real C) {
  return std::clamp(soft.biasRate * C, -kMaxJointBias, kMaxJointBias);
}

/// One row's Jacobian J = [-l, -jA, l, jB] on (vA, wA, vB, wB): a linear row has direction l and
/// jA = rA x l, jB = rB x l for lever arms rA, rB from the centres of mass; an angular row has
/// l = 0 and jA = jB = its axis.
struct JointRow {
  Vec3 linear = Vec3::Zero();
  Vec3 ja = Vec3::Zero();
  Vec3 jb = Vec3::Zero();

  /// The torque per unit impulse beyond the linear part's moment (the axis of an angular row).
  Vec3 angular() const { return linear.isZero() ? ja : Vec3::Zero(); }
};

inline JointRow linearRow(const Vec3& direction, const Vec3& armA, const Vec3& armB) {
  return {direction, armA.cross(direction), armB.cross(direction)};
}
inline JointRow angularRow(const Vec3& axis) { return {Vec3::Zero(), axis, axis}; }

/// Up to six coupled rows and their accumulated impulses (N s, or N m s for angular rows),
/// kept from substep to substep and step to step for warm starting. A joint's locked rows
/// form one block, solved together: solved one after another, a light body on a long lever
/// arm (a pendulum's bob) converges so slowly between its anchor rows and its angular rows that
/// Baumgarte's feedback grows the error instead of removing it.
struct RowBlock {
  static constexpr int kMax = 6;
  using Vector = Eigen::Matrix<Real, Eigen::Dynamic, 1, 0, kMax, 1>;
  using Matrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, 0, kMax, kMax>;

  // The fields every pass reads come first (a large grid's passes are bound by memory).
  int count = 0;
  /// Set by setPoint(): the block is a point constraint, three rows along the world axes with
  /// lever arms `armA` and `armB` (a ball joint's anchors), prepared and solved in closed form
  /// (Jolt's point constraint part) instead of row by row: K = (mA + mB) 1 - [rA] IA [rA] -
  /// [rB] IB [rB] by its adjugate, J v = vB + wB x rB - vA - wA x rA.
  bool point = false;
  Eigen::Matrix<Real, kMax, 1> impulse = Eigen::Matrix<Real, kMax, 1>::Zero();
  Vec3 armA = Vec3::Zero(), armB = Vec3::Zero();
  // Set by prepare() after each position update: the position errors and K^-1 (count x count,
  // column-major; a point constraint's upper triangle, packed 00, 01, 02, 11, 12, 22), which the
  // passes until the next position update share.
  Eigen::Matrix<Real, kMax, 1> error = Eigen::Matrix<Real, kMax, 1>::Zero();
  std::array<Real, kMax * kMax> inverseMass{};
  std::array<JointRow, kMax> rows{};

  void clear() {
    count = 0;
    point = false;
  }
  void add(const JointRow& row) { rows[std::size_t(count++)] = row; }
  /// The three anchor rows of a ball joint (an empty block before).
  void setPoint(const Vec3& rA, const Vec3& rB) {
    count = 3;
    point = true;
    armA = rA;
    armB = rB;
  }

  /// K^-1 (K = J M^-1 J^T) and C for the rows as they are now.
  void prepare(const SolverBody& a, const SolverBody& b, const Vector& C) {
    error.head(count) = C;
    if (point && invertPoint(a, b)) return;
    invertRows(a, b);
  }
  /// The relative velocity along the rows, J v.
  Vector velocity(const SolverBody& a, const SolverBody& b) const {
    Vector c(count);
    for (std::size_t i = 0; i < std::size_t(count); ++i)
      c(int(i)) = rows[i].linear.dot(b.v - a.v) + rows[i].jb.dot(b.w) - rows[i].ja.dot(a.w);
    return c;
  }
  /// Applies impulses `lambda` along the rows to both bodies.
  template <class V>
  void apply(SolverBody& a, SolverBody& b, const V& lambda) const {
    Vec3 p = Vec3::Zero(), la = Vec3::Zero(), lb = Vec3::Zero();
    for (std::size_t i = 0; i < std::size_t(count); ++i) {
      p += rows[i].linear * lambda(int(i));
      la += rows[i].ja * lambda(int(i));
      lb += rows[i].jb * lambda(int(i));
    }
    a.v -= a.invMass * p;
    a.w -= times(a.invInertia, la);
    b.v += b.invMass * p;
    b.w += times(b.invInertia, lb);
  }
  void warmStart(SolverBody& a, SolverBody& b) const {
    if (point)
      applyPoint(a, b, impulse.head<3>());
    else
      apply(a, b, impulse.head(count));
  }

  /// One equality solve towards C = 0 with `soft`'s coefficients.
  void solve(SolverBody& a, SolverBody& b, const Softness& soft) {
    if (point) return solvePoint(a, b, soft);
    switch (count) {
      case 1:
        return solveFixed<1>(a, b, soft);
      case 2:
        return solveFixed<2>(a, b, soft);
      case 3:
        return solveFixed<3>(a, b, soft);
      case 4:
        return solveFixed<4>(a, b, soft);
      case 5:
        return solveFixed<5>(a, b, soft);
      case 6:
        return solveFixed<6>(a, b, soft);
      default:
        return;
    }
  }

  /// A velocity block driven to zero with its accumulated impulse inside a ball of radius
  /// `maxImpulse` (a ball joint's friction torque).
  void solveFriction(SolverBody& a, SolverBody& b, Real maxImpulse) {
    const Vector old = impulse.head(count);
    Vector next = old - inverse() * velocity(a, b);
    const Real norm = next.norm();
    if (norm > maxImpulse) next *= maxImpulse / norm;
    impulse.head(count) = next;
    apply(a, b, next - old);
  }

  /// The force (or impulse) these rows put on B: the linear part and the torque beyond the
  /// linear part's moment about B's anchor.
  void reaction(Vec3& linear, Vec3& angular) const {
    if (point) {
      linear += impulse.head<3>();
      return;
    }
    for (std::size_t i = 0; i < std::size_t(count); ++i) {
      linear += rows[i].linear * impulse(int(i));
      angular += rows[i].angular() * impulse(int(i));
    }
  }

 private:
  // Adds [r]^T I^-1 [r] for a symmetric I^-1 (the inverse mass a point at arm r gets from a
  // body's rotation) to the packed upper triangle k (00, 01, 02, 11, 12, 22). With s_i = r x e_i
  // the columns of [r] and t_i = I^-1 s_i, entry (i, j) is s_i . t_j. In scalars: Eigen's
  // expressions over 3-vectors cost four times the arithmetic here, and K is made for every
  // joint after every position update.
  static void addArmMass(std::array<Real, 6>& k, const Mat3& inv, const Vec3& r) {
    const Real x = r.x(), y = r.y(), z = r.z();
    const Real i00 = inv(0, 0), i01 = inv(0, 1), i02 = inv(0, 2);
    const Real i11 = inv(1, 1), i12 = inv(1, 2), i22 = inv(2, 2);
    const Real t0y = z * i11 - y * i12, t0z = z * i12 - y * i22;
    const Real t1x = x * i02 - z * i00, t1y = x * i12 - z * i01, t1z = x * i22 - z * i02;
    const Real t2x = y * i00 - x * i01, t2y = y * i01 - x * i11, t2z = y * i02 - x * i12;
    k[0] += z * t0y - y * t0z;
    k[1] += z * t1y - y * t1z;
    k[2] += z * t2y - y * t2z;
    k[3] += x * t1z - z * t1x;
    k[4] += x * t2z - z * t2x;
    k[5] += y * t2x - x * t2y;
  }
  // v += s M u for a symmetric 3x3 M (an inverse inertia), in scalars.
  static void addSymmetricProduct(Vec3& v, Real s, const Mat3& m, const Vec3& u) {
    const Real x = u.x(), y = u.y(), z = u.z();
    v.x() += s * (m(0, 0) * x + m(0, 1) * y + m(0, 2) * z);
    v.y() += s * (m(0, 1) * x + m(1, 1) * y + m(1, 2) * z);
    v.z() += s * (m(0, 2) * x + m(1, 2) * y + m(2, 2) * z);
  }
  static Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(),
            a.x() * b.y() - a.y() * b.x()};
  }
  // The point constraint's passes in scalars, every input read before the first write: the
  // same operations in the same order as the vector form (the same bits), which the compiler
  // kept in loops through the stack, reloading each body after each write (it cannot know
  // that a and b are two bodies). A large joint grid spends most of its step here.
  void applyPoint(SolverBody& a, SolverBody& b, const Vec3& lambda) const {
    const Real lx = lambda.x(), ly = lambda.y(), lz = lambda.z();
    const Vec3 ta = cross(armA, lambda), tb = cross(armB, lambda);
    const Real ma = a.invMass, mb = b.invMass;
    Vec3 va = a.v, vb = b.v, wa = a.w, wb = b.w;
    va.x() -= ma * lx;
    va.y() -= ma * ly;
    va.z() -= ma * lz;
    vb.x() += mb * lx;
    vb.y() += mb * ly;
    vb.z() += mb * lz;
    addSymmetricProduct(wa, -1, a.invInertia, ta);
    addSymmetricProduct(wb, 1, b.invInertia, tb);
    a.v = va;
    a.w = wa;
    b.v = vb;
    b.w = wb;
  }
  void solvePoint(SolverBody& a, SolverBody& b, const Softness& soft) {
    const Vec3 wbr = cross(b.w, armB), war = cross(a.w, armA);
    const Real rx = (b.v.x() + wbr.x()) - (a.v.x() + war.x()) + jointBias(soft, error(0));
    const Real ry = (b.v.y() + wbr.y()) - (a.v.y() + war.y()) + jointBias(soft, error(1));
    const Real rz = (b.v.z() + wbr.z()) - (a.v.z() + war.z()) + jointBias(soft, error(2));
    // K^-1 is symmetric: its upper triangle, packed as addArmMass's.
    const Real* m = inverseMass.data();
    const Real s = soft.massScale, t = soft.impulseScale;
    const Vec3 delta(-s * (m[0] * rx + m[1] * ry + m[2] * rz) - t * impulse(0),
                     -s * (m[1] * rx + m[3] * ry + m[4] * rz) - t * impulse(1),
                     -s * (m[2] * rx + m[4] * ry + m[5] * rz) - t * impulse(2));
    impulse(0) += delta.x();
    impulse(1) += delta.y();
    impulse(2) += delta.z();
    applyPoint(a, b, delta);
  }

 public:
  // K^-1 of a point constraint by the adjugate of the symmetric K. False where K is near
  // singular (no moving body on either side has mass, which a joint never has, or a
  // determinant lost to rounding): the caller falls back to the rows' LDLT.
  bool invertPoint(const SolverBody& a, const SolverBody& b) {
    const Real m = a.invMass + b.invMass;
    std::array<Real, 6> k = {m, 0, 0, m, 0, m};
    addArmMass(k, a.invInertia, armA);
    addArmMass(k, b.invInertia, armB);
    const Real c00 = k[3] * k[5] - k[4] * k[4];
    const Real c01 = k[2] * k[4] - k[1] * k[5];
    const Real c02 = k[1] * k[4] - k[2] * k[3];
    const Real det = k[0] * c00 + k[1] * c01 + k[2] * c02;
    const Real scale = k[0] + k[3] + k[5];
    if (!(det > std::numeric_limits<Real>::epsilon() * scale * scale * scale)) {
      point = false;
      for (int i = 0; i < 3; ++i)
        rows[std::size_t(i)] = {Vec3::Unit(i), armA.cross(Vec3::Unit(i)),
                                armB.cross(Vec3::Unit(i))};
      return false;
    }
    const Real inv = 1 / det;
    inverseMass[0] = inv * c00;
    inverseMass[1] = inv * c01;
    inverseMass[2] = inv * c02;
    inverseMass[3] = inv * (k[0] * k[5] - k[2] * k[2]);
    inverseMass[4] = inv * (k[1] * k[2] - k[0] * k[4]);
    inverseMass[5] = inv * (k[0] * k[3] - k[1] * k[1]);
    return true;
  }

 private:
  // solve() for N rows, in fixed-size (unrolled) arithmetic.
  template <int N>
  void solveFixed(SolverBody& a, SolverBody& b, const Softness& soft) {
    Eigen::Matrix<Real, N, 1> rhs;
    const Vec3 dv = b.v - a.v;
    for (int i = 0; i < N; ++i) {
      const JointRow& r = rows[std::size_t(i)];
      rhs(i) = r.linear.dot(dv) + r.jb.dot(b.w) - r.ja.dot(a.w) + jointBias(soft, error(i));
    }
    const Eigen::Map<const Eigen::Matrix<Real, N, N>> kinv(inverseMass.data());
    const Eigen::Matrix<Real, N, 1> delta =
        -soft.massScale * (kinv * rhs) - soft.impulseScale * impulse.template head<N>();
    impulse.template head<N>() += delta;
    Vec3 p = Vec3::Zero(), la = Vec3::Zero(), lb = Vec3::Zero();
    for (int i = 0; i < N; ++i) {
      const JointRow& r = rows[std::size_t(i)];
      p += r.linear * delta(i);
      la += r.ja * delta(i);
      lb += r.jb * delta(i);
    }
    a.v -= a.invMass * p;
    a.w -= times(a.invInertia, la);
    b.v += b.invMass * p;
    b.w += times(b.invInertia, lb);
  }

  Eigen::Map<const Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, 0, kMax, kMax>> inverse()
      const {
    return {inverseMass.data(), count, count};
  }
  // K^-1 of the rows by a fixed-size LDLT, in joint_parts.cpp: its Eigen solvers, for six
  // sizes in two precisions, took 35 s of the compiler's front end in every file that included
  // this header.
  void invertRows(const SolverBody& a, const SolverBody& b);
  template <int N, class S>
  Eigen::Matrix<S, N, N> massMatrix(const SolverBody& a, const SolverBody& b) const;
  template <int N>
  void invert(const SolverBody& a, const SolverBody& b);
};

/// A joint's free coordinate (an angle or a position along an axis): one row shared by the
/// spring, the motor, the friction and the two limits, each with its own accumulated impulse.
struct AxisRows {
  JointRow row;
  /// Accumulated impulses; `lock` holds a coordinate fixed (a distance joint's rigid rod).
  Real spring = 0, motor = 0, friction = 0, lower = 0, upper = 0, lock = 0;
  // Set by prepare() after each position update: the effective mass.
  Real effectiveMass = 0;

  /// The effective mass of the row as it is now (the bodies' positions and the row do not
  /// change between position updates, so the passes share it).
  void prepare(const SolverBody& a, const SolverBody& b) {
    const Real k = (a.invMass + b.invMass) * row.linear.squaredNorm() +
                   row.ja.dot(times(a.invInertia, row.ja)) +
                   row.jb.dot(times(b.invInertia, row.jb));
    effectiveMass = k > 0 ? 1 / k : 0;
  }
  Real total() const { return spring + motor + friction + lower - upper + lock; }
  Real velocity(const SolverBody& a, const SolverBody& b) const {
    return row.linear.dot(b.v - a.v) + row.jb.dot(b.w) - row.ja.dot(a.w);
  }
  void apply(SolverBody& a, SolverBody& b, Real lambda) const {
    a.v -= a.invMass * lambda * row.linear;
    a.w -= times(a.invInertia, lambda * row.ja);
    b.v += b.invMass * lambda * row.linear;
    b.w += times(b.invInertia, lambda * row.jb);
  }
  void warmStart(SolverBody& a, SolverBody& b) const { apply(a, b, total()); }
  void reaction(Vec3& linear, Vec3& angular) const {
    linear += row.linear * total();
    angular += row.angular() * total();
  }

  /// A bounded velocity row: drives J v to `speed` with |impulse| <= maxImpulse.
  void solveMotor(SolverBody& a, SolverBody& b, Real& accumulated, Real speed, Real maxImpulse) {
    const Real old = accumulated;
    accumulated =
        std::clamp(old - effectiveMass * (velocity(a, b) - speed), -maxImpulse, maxImpulse);
    if (accumulated != old) apply(a, b, accumulated - old);  // a stalled motor: nothing
  }
  /// A soft row towards C = 0 (a spring or a servo), |impulse| <= maxImpulse.
  void solveSoft(SolverBody& a, SolverBody& b, Real& accumulated, Real C, const Softness& soft,
                 Real maxImpulse) {
    const Real old = accumulated;
    const Real lambda = -soft.massScale * effectiveMass * (velocity(a, b) + jointBias(soft, C)) -
                        soft.impulseScale * old;
    accumulated = std::clamp(old + lambda, -maxImpulse, maxImpulse);
    if (accumulated != old) apply(a, b, accumulated - old);
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
      bias = jointBias(soft, C);
      massScale = soft.massScale;
      impulseScale = soft.impulseScale;
    }
    const Real old = accumulated;
    const Real lambda =
        -massScale * effectiveMass * (sign * velocity(a, b) + bias) - impulseScale * old;
    accumulated = std::max(old + lambda, Real(0));
    // An inactive limit (the usual case: speculative, its gap not closing) changes nothing.
    if (accumulated != old) apply(a, b, sign * (accumulated - old));
  }
};

}  // namespace inertia::detail
