// Our articulation models as DART skeletons, for the DART test and benchmark: the same links,
// joints and inertias, with DART's dof order and position coordinates mapped to ours.
#pragma once

// DART's umbrella header pulls in IkFast, whose header Debian ships in another package: include
// only the dynamics used.
#include <dart/dynamics/BallJoint.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/PrismaticJoint.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/WeldJoint.hpp>
#include <vector>

#include "inertia/articulation/model.h"

namespace inertia::articulation::dart_peer {

namespace dd = dart::dynamics;

inline Eigen::Isometry3d isometry(const PluckerTransform<double>& X) {
  // X maps parent to joint-frame coordinates: the joint frame is at r, turned by E^T.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = X.E.transpose();
  T.translation() = X.r;
  return T;
}

template <class J>
typename J::Properties jointProperties(const Link<double>& link) {
  typename J::Properties p;
  p.mName = link.name + "_joint";
  p.mT_ParentBodyToJoint = isometry(link.Xtree);
  return p;
}

// The skeleton, and for each of our velocity coordinates the index of DART's dof.
struct DartTree {
  dd::SkeletonPtr skeleton;
  std::vector<int> dof;
};

inline DartTree toDart(const Model<double>& model) {
  DartTree d{dd::Skeleton::create("tree"), std::vector<int>(model.nv())};
  std::vector<dd::BodyNode*> bodies;
  for (const Link<double>& l : model.links()) {
    dd::BodyNode* parent = l.parent < 0 ? nullptr : bodies[l.parent];
    dd::BodyNode::Properties body;
    body.mName = l.name;
    // Our spatial inertia about the link origin, back to mass, centre and inertia about it.
    const Matrix3<double> C = skew(l.centerOfMass);
    const Matrix3<double> Ic = l.I.topLeftCorner<3, 3>() - l.mass * C * C.transpose();
    body.mInertia = dd::Inertia(l.mass, l.centerOfMass, Ic);
    std::pair<dd::Joint*, dd::BodyNode*> pair;
    switch (l.joint) {
      case JointType::Revolute: {
        auto p = jointProperties<dd::RevoluteJoint>(l);
        p.mAxis = l.axis;
        pair = d.skeleton->createJointAndBodyNodePair<dd::RevoluteJoint>(parent, p, body);
        break;
      }
      case JointType::Prismatic: {
        auto p = jointProperties<dd::PrismaticJoint>(l);
        p.mAxis = l.axis;
        pair = d.skeleton->createJointAndBodyNodePair<dd::PrismaticJoint>(parent, p, body);
        break;
      }
      case JointType::Spherical:
        pair = d.skeleton->createJointAndBodyNodePair<dd::BallJoint>(
            parent, jointProperties<dd::BallJoint>(l), body);
        break;
      case JointType::Fixed:
        pair = d.skeleton->createJointAndBodyNodePair<dd::WeldJoint>(
            parent, jointProperties<dd::WeldJoint>(l), body);
        break;
      case JointType::Floating:
        pair = d.skeleton->createJointAndBodyNodePair<dd::FreeJoint>(
            parent, jointProperties<dd::FreeJoint>(l), body);
        break;
    }
    bodies.push_back(pair.second);
    for (int k = 0; k < l.nv; ++k)
      d.dof[l.vIndex + k] = static_cast<int>(pair.first->getDof(k)->getIndexInSkeleton());
  }
  d.skeleton->setGravity(model.gravity);
  return d;
}

// DART's positions for our q (its own conversions for ball and free joints).
inline Eigen::VectorXd dartPositions(const Model<double>& model, const DartTree& d,
                                     const VectorX<double>& q) {
  Eigen::VectorXd out(model.nv());
  for (const Link<double>& l : model.links()) {
    const int i = l.qIndex, k = l.vIndex;
    auto rotation = [&](int at) {
      return Quaternion<double>(q(at), q(at + 1), q(at + 2), q(at + 3)).toRotationMatrix();
    };
    switch (l.joint) {
      case JointType::Revolute:
      case JointType::Prismatic:
        out(d.dof[k]) = q(i);
        break;
      case JointType::Spherical:
        out.segment<3>(d.dof[k]) = dd::BallJoint::convertToPositions(rotation(i));
        break;
      case JointType::Floating: {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = rotation(i + 3);
        T.translation() = q.segment<3>(i);
        out.segment<6>(d.dof[k]) = dd::FreeJoint::convertToPositions(T);
        break;
      }
      case JointType::Fixed:
        break;
    }
  }
  return out;
}

inline Eigen::VectorXd toDartOrder(const DartTree& d, const VectorX<double>& x) {
  Eigen::VectorXd out(x.size());
  for (int k = 0; k < x.size(); ++k) out(d.dof[k]) = x(k);
  return out;
}

/// A vector DART computes, read one entry at a time: a vector that DART returns by value is
/// allocated by its Eigen, which under AddressSanitizer does not match ours (Eigen stops
/// trusting malloc's alignment there), and freeing it here is a heap-buffer-overflow.
template <class F>
Eigen::VectorXd readDartVector(int n, F entry) {
  Eigen::VectorXd out(n);
  for (int i = 0; i < n; ++i) out(i) = entry(i);
  return out;
}

}  // namespace inertia::articulation::dart_peer
