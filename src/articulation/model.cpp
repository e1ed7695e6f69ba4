// The link tree: validation of each link as it is added, its joint's frames and coordinates.
#include "inertia/articulation/model.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "inertia/core/error.h"
#include "inertia/geometry/mass.h"

namespace inertia::articulation {

int configurationSize(JointType type) {
  switch (type) {
    case JointType::Revolute:
    case JointType::Prismatic:
      return 1;
    case JointType::Spherical:
      return 4;
    case JointType::Fixed:
      return 0;
    case JointType::Floating:
      return 7;
  }
  return 0;
}

int velocitySize(JointType type) {
  switch (type) {
    case JointType::Revolute:
    case JointType::Prismatic:
      return 1;
    case JointType::Spherical:
      return 3;
    case JointType::Fixed:
      return 0;
    case JointType::Floating:
      return 6;
  }
  return 0;
}

template <class S>
LinkInertia<S> inertiaFromShapes(std::span<const LinkShape> shapes) {
  require(!shapes.empty(), "articulation: a link's inertia from shapes needs at least one shape");
  std::vector<MassProperties> parts;
  parts.reserve(shapes.size());
  for (const LinkShape& s : shapes)
    parts.push_back(transformed(massProperties(s.shape, s.density), s.pose));
  const MassProperties total = combine(parts);
  return {S(total.mass), total.centerOfMass.cast<S>(), total.inertia.cast<S>()};
}

namespace {

template <class S>
void checkInertia(const LinkInertia<S>& in, const std::string& where) {
  require(std::isfinite(in.mass) && in.mass >= 0, where + ".mass must be finite and >= 0");
  require(in.centerOfMass.allFinite(), where + ".centerOfMass must be finite");
  const Matrix3<S>& I = in.inertia;
  // A massless link (a frame for shapes or children, as URDF allows) has no inertia either.
  if (in.mass == 0) {
    require(I.isZero(0), where + ".inertia must be zero for a massless link");
    return;
  }
  require(I.allFinite() && (I - I.transpose()).cwiseAbs().maxCoeff() <= S(1e-6) * I.norm(),
          where + ".inertia must be finite and symmetric");
  const Eigen::SelfAdjointEigenSolver<Matrix3<S>> eig(I);
  const Vector3<S> p = eig.eigenvalues();
  require(p.minCoeff() > 0, where + ".inertia must be positive definite");
  // Principal moments of a real body obey the triangle inequality (with rounding slack).
  const S slack = S(1e-6) * p.sum();
  require(p(0) + p(1) + slack >= p(2) && p(1) + p(2) + slack >= p(0) && p(0) + p(2) + slack >= p(1),
          where + ".inertia breaks the triangle inequality of principal moments");
}

template <class S>
void checkDrive(const Drive<S>& d, const std::string& where) {
  require(std::isfinite(d.stiffness) && d.stiffness >= 0,
          where + ".stiffness must be finite and >= 0");
  require(std::isfinite(d.damping) && d.damping >= 0, where + ".damping must be finite and >= 0");
  require(std::isfinite(d.targetPosition), where + ".targetPosition must be finite");
  require(std::isfinite(d.targetVelocity), where + ".targetVelocity must be finite");
  require(!std::isnan(d.maxForce) && d.maxForce > 0, where + ".maxForce must be > 0");
}

template <class S>
void checkJoint(const JointSettings<S>& j, int parent, const std::string& where) {
  const bool scalar = j.type == JointType::Revolute || j.type == JointType::Prismatic;
  require(j.originPosition.allFinite(), where + ".originPosition must be finite");
  require(j.originOrientation.coeffs().allFinite() && j.originOrientation.norm() > S(0.5),
          where + ".originOrientation must be a finite, non-zero quaternion");
  require(j.type != JointType::Floating || parent == -1,
          where + ".type: a floating joint attaches a root link (parent -1) only");
  if (scalar)
    require(j.axis.allFinite() && j.axis.norm() > S(1e-6), where + ".axis must be non-zero");
  require(!std::isnan(j.lower) && !std::isnan(j.upper) && j.lower <= j.upper,
          where + ".limits must satisfy lower <= upper");
  require(scalar || (j.lower == -std::numeric_limits<S>::infinity() &&
                     j.upper == std::numeric_limits<S>::infinity()),
          where + ".limits apply to revolute and prismatic joints only");
  for (auto [value, name] :
       {std::pair{j.damping, ".damping"}, {j.friction, ".friction"}, {j.armature, ".armature"}})
    require(std::isfinite(value) && value >= 0, where + name + " must be finite and >= 0");
  require(!std::isnan(j.velocityLimit) && j.velocityLimit > 0,
          where + ".velocityLimit must be > 0 (infinite for none)");
  require(j.type != JointType::Floating || (j.damping == 0 && j.friction == 0 && j.armature == 0 &&
                                            j.velocityLimit == std::numeric_limits<S>::infinity()),
          where + ": a floating joint takes no damping, friction, armature or velocity limit");
  checkDrive(j.drive, where + ".drive");
  require(scalar || (j.drive.stiffness == 0 && j.drive.damping == 0),
          where + ".drive applies to revolute and prismatic joints only");
}

}  // namespace

template <class S>
int Model<S>::addLink(const LinkSettings<S>& s) {
  const int index = linkCount();
  const std::string where =
      "articulation: link " + std::to_string(index) + (s.name.empty() ? "" : " '" + s.name + "'");
  require(s.parent >= -1 && s.parent < index,
          where + ".parent must be -1 or an earlier link (got " + std::to_string(s.parent) + ")");
  checkJoint(s.joint, s.parent, where + ".joint");
  checkInertia(s.inertia, where + ".inertia");

  Link<S> link;
  link.name = s.name;
  link.parent = s.parent;
  link.joint = s.joint.type;
  // X_T maps parent coordinates to joint-frame coordinates: E = R^T, r = origin position.
  link.Xtree.E = s.joint.originOrientation.normalized().toRotationMatrix().transpose();
  link.Xtree.r = s.joint.originPosition;
  link.axis = s.joint.type == JointType::Revolute || s.joint.type == JointType::Prismatic
                  ? Vector3<S>(s.joint.axis.normalized())
                  : Vector3<S>::UnitZ();
  link.qIndex = nq_;
  link.vIndex = nv_;
  link.nq = configurationSize(link.joint);
  link.nv = velocitySize(link.joint);
  link.mass = s.inertia.mass;
  link.centerOfMass = s.inertia.centerOfMass;
  link.I = spatialInertia(s.inertia.mass, s.inertia.centerOfMass, s.inertia.inertia);

  const int nv = nv_ + link.nv;
  S_.conservativeResize(6, nv);
  S_.middleCols(nv_, link.nv).setZero();
  switch (link.joint) {
    case JointType::Revolute:
      S_.col(nv_).template head<3>() = link.axis;
      break;
    case JointType::Prismatic:
      S_.col(nv_).template tail<3>() = link.axis;
      break;
    case JointType::Spherical:
      S_.block(0, nv_, 3, 3).setIdentity();
      break;
    case JointType::Floating:
      S_.block(0, nv_, 6, 6).setIdentity();
      break;
    case JointType::Fixed:
      break;
  }
  auto grow = [&](VectorX<S>& v, S value) {
    v.conservativeResize(nv);
    v.segment(nv_, link.nv).setConstant(value);
  };
  grow(armature_, s.joint.armature);
  grow(damping_, s.joint.damping);
  grow(friction_, s.joint.friction);
  grow(velocityLimit_, s.joint.velocityLimit);
  grow(lower_, s.joint.lower);
  grow(upper_, s.joint.upper);
  for (int k = 0; k < link.nv; ++k) {
    drives_.push_back(s.joint.drive);
    scalarQ_.push_back(link.nq == link.nv ? link.qIndex + k : -1);
  }
  nq_ += link.nq;
  nv_ = nv;
  links_.push_back(std::move(link));
  return index;
}

template <class S>
void Model<S>::setDrive(int dof, const Drive<S>& drive) {
  const std::string where = "articulation: the drive of dof " + std::to_string(dof);
  require(dof >= 0 && dof < nv_, where + ": no such degree of freedom");
  checkDrive(drive, where);
  require(scalarQ_[dof] >= 0 || (drive.stiffness == 0 && drive.damping == 0),
          where + ": drives apply to revolute and prismatic joints only");
  drives_[dof] = drive;
}

template <class S>
int Model<S>::findLink(const std::string& name) const {
  for (int i = 0; i < linkCount(); ++i)
    if (links_[i].name == name) return i;
  return -1;
}

template <class S>
VectorX<S> Model<S>::neutralConfiguration() const {
  VectorX<S> q = VectorX<S>::Zero(nq_);
  for (const Link<S>& l : links_) {
    if (l.joint == JointType::Spherical) q(l.qIndex) = S(1);
    if (l.joint == JointType::Floating) q(l.qIndex + 3) = S(1);
  }
  return q;
}

template <class S>
int firstLinkMovingNoMass(const Model<S>& model) {
  // Subtree masses, children before parents (a parent's index is below its children's).
  std::vector<S> subtree(std::size_t(model.linkCount()), S(0));
  for (int i = model.linkCount() - 1; i >= 0; --i) {
    subtree[std::size_t(i)] += model.link(i).mass;
    if (model.link(i).parent >= 0)
      subtree[std::size_t(model.link(i).parent)] += subtree[std::size_t(i)];
  }
  for (int i = 0; i < model.linkCount(); ++i)
    if (model.link(i).nv > 0 && !(subtree[std::size_t(i)] > 0)) return i;
  return -1;
}

template int firstLinkMovingNoMass<float>(const Model<float>&);
template int firstLinkMovingNoMass<double>(const Model<double>&);
template LinkInertia<float> inertiaFromShapes<float>(std::span<const LinkShape>);
template LinkInertia<double> inertiaFromShapes<double>(std::span<const LinkShape>);
template class Model<float>;
template class Model<double>;

}  // namespace inertia::articulation
