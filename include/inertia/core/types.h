// Scalar type and the Eigen aliases every layer uses.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>

namespace inertia {

#ifdef INERTIA_DOUBLE
using Real = double;
#else
using Real = float;
#endif

/// Real's infinity: unbounded distances and times, the bounds of an empty box.
inline constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Vec4 = Eigen::Matrix<Real, 4, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;
using Quat = Eigen::Quaternion<Real>;
using VecX = Eigen::Matrix<Real, Eigen::Dynamic, 1>;
using MatX = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>;

/// A rigid transform: rotation followed by translation, x_world = q * x_local + p.
/// A position and a unit quaternion rather than Eigen's 4x4 Isometry: half the storage,
/// and the form in which bodies keep their pose (as in Jolt, Box2D and Bullet).
struct Transform {
  Vec3 p = Vec3::Zero();       ///< Translation (m).
  Quat q = Quat::Identity();   ///< Rotation, a unit quaternion.

  static Transform identity() { return {}; }

  /// Maps a point from local to world coordinates.
  Vec3 apply(const Vec3& x) const { return q * x + p; }
  /// Maps a direction from local to world coordinates (no translation).
  Vec3 rotate(const Vec3& v) const { return q * v; }
  /// Maps a point from world to local coordinates.
  Vec3 applyInverse(const Vec3& x) const { return q.conjugate() * (x - p); }
  Transform inverse() const {
    Quat qi = q.conjugate();
    return {qi * -p, qi};
  }
  /// Composition: (a * b).apply(x) == a.apply(b.apply(x)).
  friend Transform operator*(const Transform& a, const Transform& b) {
    return {a.q * b.p + a.p, a.q * b.q};
  }
};

}  // namespace inertia
