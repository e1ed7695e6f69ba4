// An articulation's links as driven bodies of the rigid solver (dynamics/multibody.h): the
// response of the links' points to contact impulses through the tree's mass matrix, and the
// articulation's substeps inside the rigid bodies' own.
//
// At the step's start the mass matrix H is built (CRBA) and factored (Cholesky) once; each
// contact point p on link i gets its Jacobian J (3 x nv, world axes: the point's velocity is
// J qd) and H^-1 J^T, so that an impulse P on it changes the velocities by H^-1 J^T P (every
// link moves), and the point's response is W = J H^-1 J^T. Both are kept for the step (as a
// rigid contact keeps its anchors). The articulation's joint rows (limits, drives, damping,
// friction, velocity limits) use the same factor and are swept in every solve and relax
// iteration beside the contacts (solveRows), so that a substep ends with velocities that both
// the contacts and the joints have answered: Articulation::integrateVelocity makes the rows
// from the substep's start position, Articulation::integratePosition moves q by h qd and aims
// the limit rows from there for the relax pass.
#pragma once

#include <vector>

#include "inertia/articulation/articulation.h"
#include "inertia/dynamics/multibody.h"

namespace inertia::articulation {

class LinkResponse final : public MultibodyResponse {
 public:
  /// `articulation` must outlive this; `base` places the base frame in the world. The
  /// articulation's gravity is set from `gravity` (world, m/s^2) turned into the base frame.
  LinkResponse(Articulation<Real>& articulation, const Transform& base, const Vec3& gravity);
  /// A copy of `other` (its poses and this step's points) answering for `articulation`, a copy
  /// of other's articulation: for the world's snapshots.
  LinkResponse(const LinkResponse& other, Articulation<Real>& articulation);
  LinkResponse& operator=(const LinkResponse&) = delete;

  const Transform& base() const { return base_; }
  /// The world pose of link `link`'s frame now.
  Transform linkPose(int link) const;
  /// The velocities of link `link`'s origin (m/s) and its angular velocity (rad/s), world.
  void linkVelocity(int link, Vec3& v, Vec3& w) const;
  /// Recomputes the link poses (after the articulation's state was set from outside).
  void updatePoses();

  void beginStep() override;
  int addPoint(int member, const Vec3& point) override;
  Mat3 pointResponse(int handle) const override { return points_[std::size_t(handle)].W; }
  Mat3 crossResponse(int a, int b) const override {
    return points_[std::size_t(a)].J.topRows<3>() * points_[std::size_t(b)].MinvJt.leftCols<3>();
  }
  Vec3 pointVelocity(int handle) const override;
  Vec3 pointDisplacement(int handle) const override;
  void applyImpulse(int handle, const Vec3& impulse) override;
  int addFrame(int member, const Vec3& point) override;
  FrameMatrix frameResponse(int a, int b) const override;
  FrameVector frameVelocity(int handle) const override;
  void applyFrameImpulse(int handle, const FrameVector& impulse) override;
  Quat frameRotation(int handle) const override;
  void integrateVelocities(Real h) override { articulation_->integrateVelocity(h); }
  void solveRows() override { articulation_->sweepJointRows(); }
  void integratePositions(Real h) override;

 private:
  LinkResponse(const LinkResponse&) = default;  // answering for the same articulation

  using Matrix6X = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, 0, 6, Eigen::Dynamic>;
  using MatrixX6 = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, 0, Eigen::Dynamic, 6>;
  // A point (3 rows: its velocity) or a frame (6: [v; w]).
  struct Point {
    int link = 0;
    Vec3 local = Vec3::Zero();  // in the link's frame (m)
    Vec3 start = Vec3::Zero();  // world, at the step's start (m)
    Matrix6X J;                 // [v; w] = J qd (world), v alone for a point
    MatrixX6 MinvJt;            // H^-1 J^T
    Mat3 W = Mat3::Zero();      // the point rows' J H^-1 J^T
  };
  int add(int member, const Vec3& point, int rows);

  Articulation<Real>* articulation_;  // never null
  Transform base_;
  Mat3 baseRotation_;
  Workspace<Real> ws_;
  std::vector<PluckerTransform<Real>> X0_;  // base to link, now
  std::vector<Point> points_;               // grows, kept between steps (no reallocation)
  int pointCount_ = 0;
  VectorX<Real> delta_;  // scratch of applyImpulse
};

}  // namespace inertia::articulation
