// Spatial vector algebra in Featherstone's conventions (Rigid Body Dynamics Algorithms, 2008,
// chapter 2): six-vectors with the angular part first, motion [w; v] and force [n; f];
// Plucker transforms; spatial inertias as 6x6 matrices.
//
// Templated on the scalar so that the accuracy tests run in double in every build; the library
// instantiates the algorithms for float and double (src/articulation/).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace inertia::articulation {

template <class S>
using Vector3 = Eigen::Matrix<S, 3, 1>;
template <class S>
using Matrix3 = Eigen::Matrix<S, 3, 3>;
template <class S>
using Quaternion = Eigen::Quaternion<S>;
template <class S>
using Vector6 = Eigen::Matrix<S, 6, 1>;
template <class S>
using Matrix6 = Eigen::Matrix<S, 6, 6>;
template <class S>
using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
template <class S>
using MatrixX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <class S>
using Matrix6X = Eigen::Matrix<S, 6, Eigen::Dynamic>;

/// The cross-product matrix: skew(a) * b == a.cross(b).
template <class S>
Matrix3<S> skew(const Vector3<S>& a) {
  Matrix3<S> m;
  m << S(0), -a.z(), a.y(), a.z(), S(0), -a.x(), -a.y(), a.x(), S(0);
  return m;
}

/// The motion cross product v x m (Featherstone eq. 2.31, crm(v) m).
template <class S>
Vector6<S> crossMotion(const Vector6<S>& v, const Vector6<S>& m) {
  const Vector3<S> w = v.template head<3>(), vo = v.template tail<3>();
  Vector6<S> out;
  out << w.cross(m.template head<3>()),
      w.cross(m.template tail<3>()) + vo.cross(m.template head<3>());
  return out;
}

/// The force cross product v x* f (Featherstone eq. 2.32, crf(v) f = -crm(v)^T f).
template <class S>
Vector6<S> crossForce(const Vector6<S>& v, const Vector6<S>& f) {
  const Vector3<S> w = v.template head<3>(), vo = v.template tail<3>();
  Vector6<S> out;
  out << w.cross(f.template head<3>()) + vo.cross(f.template tail<3>()),
      w.cross(f.template tail<3>());
  return out;
}

/// A Plucker transform B_X_A from frame A to frame B (Featherstone eq. 2.24): `E` rotates A's
/// coordinates into B's, `r` is B's origin relative to A's, in A's coordinates. As a matrix,
/// [E 0; -E skew(r) E] on motion vectors.
template <class S>
struct PluckerTransform {
  Matrix3<S> E = Matrix3<S>::Identity();
  Vector3<S> r = Vector3<S>::Zero();

  /// X m: a motion vector from A's coordinates to B's.
  Vector6<S> apply(const Vector6<S>& m) const {
    const Vector3<S> w = m.template head<3>();
    Vector6<S> out;
    out << E * w, E * (m.template tail<3>() - r.cross(w));
    return out;
  }
  /// X* f: a force vector from A's coordinates to B's.
  Vector6<S> applyForce(const Vector6<S>& f) const {
    const Vector3<S> n = f.template head<3>(), fl = f.template tail<3>();
    Vector6<S> out;
    out << E * (n - r.cross(fl)), E * fl;
    return out;
  }
  /// X^-1 m: a motion vector from B's coordinates back to A's.
  Vector6<S> applyInverse(const Vector6<S>& m) const {
    const Vector3<S> w = E.transpose() * m.template head<3>();
    Vector6<S> out;
    out << w, E.transpose() * m.template tail<3>() + r.cross(w);
    return out;
  }
  /// X^T f: a force vector from B's coordinates back to A's (X^T = (X^-1)*).
  Vector6<S> applyTransposeForce(const Vector6<S>& f) const {
    const Vector3<S> fl = E.transpose() * f.template tail<3>();
    Vector6<S> out;
    out << E.transpose() * f.template head<3>() + r.cross(fl), fl;
    return out;
  }
  /// The 6x6 matrix acting on motion vectors.
  Matrix6<S> matrix() const {
    Matrix6<S> X = Matrix6<S>::Zero();
    X.template topLeftCorner<3, 3>() = E;
    X.template bottomRightCorner<3, 3>() = E;
    X.template bottomLeftCorner<3, 3>() = -E * skew(r);
    return X;
  }
  /// X^T I X: a spatial inertia (or articulated inertia) from B's coordinates to A's
  /// (Featherstone eq. 2.66).
  /// With I = [A B; B^T M] and the blocks turned into A's axes (A' = E^T A E, ...), the product
  /// of the 6x6 matrices reduces to [A' - B' R + R B'^T - R M' R, B' + R M'; B'^T - M' R, M'],
  /// R = skew(r): a third of the work of the full products.
  Matrix6<S> transformInertiaToParent(const Matrix6<S>& I) const {
    const Matrix3<S> A = E.transpose() * I.template topLeftCorner<3, 3>() * E;
    const Matrix3<S> B = E.transpose() * I.template topRightCorner<3, 3>() * E;
    const Matrix3<S> M = E.transpose() * I.template bottomRightCorner<3, 3>() * E;
    const Matrix3<S> R = skew(r);
    const Matrix3<S> RM = R * M, BR = B * R;
    Matrix6<S> out;
    out.template topLeftCorner<3, 3>() = A - BR - BR.transpose() - RM * R;
    out.template topRightCorner<3, 3>() = B + RM;
    out.template bottomLeftCorner<3, 3>() = B.transpose() + RM.transpose();
    out.template bottomRightCorner<3, 3>() = M;
    return out;
  }
  /// The inverse, A_X_B.
  PluckerTransform inverse() const { return {E.transpose(), -(E * r)}; }

  /// Composition: (B_X_A * A_X_C) m == B_X_A (A_X_C m).
  friend PluckerTransform operator*(const PluckerTransform& a, const PluckerTransform& b) {
    return {a.E * b.E, b.r + b.E.transpose() * a.r};
  }
};

/// The spatial inertia of a body of mass `m` (kg), centre of mass `c` (m) and rotational inertia
/// `Ic` about the centre of mass (kg m^2), all in one frame, about that frame's origin
/// (Featherstone eq. 2.63): [Ic + m c c^T-ish, m skew(c); m skew(c)^T, m 1].
template <class S>
Matrix6<S> spatialInertia(S m, const Vector3<S>& c, const Matrix3<S>& Ic) {
  const Matrix3<S> C = skew(c);
  Matrix6<S> I;
  I.template topLeftCorner<3, 3>() = Ic + m * C * C.transpose();
  I.template topRightCorner<3, 3>() = m * C;
  I.template bottomLeftCorner<3, 3>() = m * C.transpose();
  I.template bottomRightCorner<3, 3>() = m * Matrix3<S>::Identity();
  return I;
}

}  // namespace inertia::articulation
