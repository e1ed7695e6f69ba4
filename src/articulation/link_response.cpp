#include "inertia/articulation/link_response.h"

namespace inertia::articulation {

LinkResponse::LinkResponse(Articulation<Real>& articulation, const Transform& base,
                           const Vec3& gravity)
    : articulation_(&articulation),
      base_(base),
      baseRotation_(base.q.toRotationMatrix()),
      ws_(articulation.model()) {
  articulation_->setGravity(baseRotation_.transpose() * gravity);
  delta_.resize(articulation.model().nv());
  updatePoses();
}

LinkResponse::LinkResponse(const LinkResponse& other, Articulation<Real>& articulation)
    : LinkResponse(other) {
  articulation_ = &articulation;
}

void LinkResponse::updatePoses() {
  parentTransforms<Real>(articulation_->model(), articulation_->q(), ws_.Xup);
  baseTransforms(articulation_->model(), ws_.Xup, X0_);
}

Transform LinkResponse::linkPose(int link) const {
  // X0 maps base coordinates into the link's: the link's rotation in the base frame is E^T.
  const PluckerTransform<Real>& X = X0_[std::size_t(link)];
  return base_ * Transform{X.r, Quat(Mat3(X.E.transpose())).normalized()};
}

void LinkResponse::linkVelocity(int link, Vec3& v, Vec3& w) const {
  const Model<Real>& m = articulation_->model();
  const VectorX<Real>& qd = articulation_->qd();
  const Vec3 p = X0_[std::size_t(link)].r;
  Vec3 wb = Vec3::Zero(), vb = Vec3::Zero();
  for (int j = link; j >= 0; j = m.link(j).parent) {
    for (int k = m.link(j).vIndex; k < m.link(j).vIndex + m.link(j).nv; ++k) {
      const Vector6<Real> s = X0_[std::size_t(j)].applyInverse(m.motionSubspace().col(k));
      wb += s.head<3>() * qd(k);
      vb += (s.tail<3>() + s.head<3>().cross(p)) * qd(k);
    }
  }
  v = baseRotation_ * vb;
  w = baseRotation_ * wb;
}

// H at the step's start, factored once: the contacts' responses and the joint rows share it, so
// that both are solved against one mass matrix.
void LinkResponse::beginStep() {
  pointCount_ = 0;
  articulation_->factorMassMatrix(articulation_->q());
}

int LinkResponse::addPoint(int member, const Vec3& point) { return add(member, point, 3); }

int LinkResponse::addFrame(int member, const Vec3& point) { return add(member, point, 6); }

// The point's Jacobian (its velocity's rows, then the link's angular velocity's for a frame),
// as pointJacobian (kinematics.h), from this step's link transforms.
int LinkResponse::add(int member, const Vec3& point, int rows) {
  const Model<Real>& m = articulation_->model();
  if (std::size_t(pointCount_) == points_.size()) points_.emplace_back();
  Point& pt = points_[std::size_t(pointCount_)];
  pt.link = member;
  pt.start = point;
  pt.local = linkPose(member).applyInverse(point);
  const Vec3 p = base_.applyInverse(point);
  pt.J.setZero(rows, m.nv());
  for (int j = member; j >= 0; j = m.link(j).parent) {
    for (int k = m.link(j).vIndex; k < m.link(j).vIndex + m.link(j).nv; ++k) {
      const Vector6<Real> s = X0_[std::size_t(j)].applyInverse(m.motionSubspace().col(k));
      pt.J.block<3, 1>(0, k) = baseRotation_ * (s.tail<3>() + s.head<3>().cross(p));
      if (rows == 6) pt.J.block<3, 1>(3, k) = baseRotation_ * s.head<3>();
    }
  }
  pt.MinvJt = articulation_->massMatrixFactor().solve(pt.J.transpose());
  pt.W = pt.J.topRows<3>() * pt.MinvJt.leftCols<3>();
  return pointCount_++;
}

Vec3 LinkResponse::pointVelocity(int handle) const {
  return points_[std::size_t(handle)].J.topRows<3>() * articulation_->qd();
}

MultibodyResponse::FrameMatrix LinkResponse::frameResponse(int a, int b) const {
  return points_[std::size_t(a)].J * points_[std::size_t(b)].MinvJt;
}

MultibodyResponse::FrameVector LinkResponse::frameVelocity(int handle) const {
  return points_[std::size_t(handle)].J * articulation_->qd();
}

void LinkResponse::applyFrameImpulse(int handle, const FrameVector& impulse) {
  delta_.noalias() = points_[std::size_t(handle)].MinvJt * impulse;
  articulation_->addVelocity(delta_);
}

Quat LinkResponse::frameRotation(int handle) const {
  return linkPose(points_[std::size_t(handle)].link).q;
}

Vec3 LinkResponse::pointDisplacement(int handle) const {
  const Point& pt = points_[std::size_t(handle)];
  return linkPose(pt.link).apply(pt.local) - pt.start;
}

void LinkResponse::applyImpulse(int handle, const Vec3& impulse) {
  delta_.noalias() = points_[std::size_t(handle)].MinvJt.leftCols<3>() * impulse;
  articulation_->addVelocity(delta_);
}

void LinkResponse::integratePositions(Real h) {
  articulation_->integratePosition(h);
  updatePoses();
}

}  // namespace inertia::articulation
