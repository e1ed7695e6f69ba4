// Volume integrals of closed polyhedra by tetrahedron decomposition (internal to geometry).
#pragma once

#include <Eigen/Core>

namespace inertia::detail {

/// Accumulates the integrals of 1, x and x x^T over a closed polyhedron given as outward
/// triangles. Each triangle (a, b, c) forms a signed tetrahedron with a reference point r; by
/// the divergence theorem the signed sum is the polyhedron (Mirtich 1996). Per tetrahedron,
/// with A = [a-r, b-r, c-r] and D = det A (Tonon 2004; Blow and Binstock 2004):
///   integral 1 = D / 6,  integral (x-r) = D / 24 (a+b+c-3r),
///   integral (x-r)(x-r)^T = D A C A^T,  C = [[2,1,1],[1,2,1],[1,1,2]] / 120.
/// Sums in double with r inside or near the body, so the cancellation is small.
class PolyhedronIntegrals {
 public:
  explicit PolyhedronIntegrals(const Eigen::Vector3d& reference) : r_(reference) {}

  void addTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    Eigen::Matrix3d A;
    A << a - r_, b - r_, c - r_;
    const double det = A.determinant();
    static const Eigen::Matrix3d kCanonical =
        (Eigen::Matrix3d() << 2, 1, 1, 1, 2, 1, 1, 1, 2).finished() / 120.0;
    volume_ += det / 6.0;
    first_ += det / 24.0 * (A.col(0) + A.col(1) + A.col(2));
    second_ += det * A * kCanonical * A.transpose();
  }

  /// Volume (m^3), signed: positive for outward-facing triangles.
  double volume() const { return volume_; }
  /// Centre of the volume (m).
  Eigen::Vector3d centroid() const { return r_ + first_ / volume_; }
  /// Inertia tensor about the centroid per unit density (m^5): trace(S) E - S with S the second
  /// moment about the centroid, shifted from r by S_c = S_r - V d d^T.
  Eigen::Matrix3d unitInertia() const {
    const Eigen::Vector3d d = first_ / volume_;
    const Eigen::Matrix3d s = second_ - volume_ * d * d.transpose();
    return s.trace() * Eigen::Matrix3d::Identity() - s;
  }

 private:
  Eigen::Vector3d r_;
  double volume_ = 0;
  Eigen::Vector3d first_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second_ = Eigen::Matrix3d::Zero();
};

}  // namespace inertia::detail
