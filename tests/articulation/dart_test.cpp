// Against DART (Debian's libdart-dev), an independent implementation of Featherstone's
// algorithms: the same random trees built as DART skeletons (revolute, prismatic, ball, weld and
// free joints), then the mass matrix, forward dynamics (ABA) and inverse dynamics compared.
// Built only where CMake finds DART.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

// DART's umbrella header pulls in IkFast, whose header Debian ships in another package: include
// only the dynamics used.
#include <dart/dynamics/BallJoint.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/PrismaticJoint.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/WeldJoint.hpp>

#include "inertia/articulation/builders.h"
#include "inertia/articulation/dynamics.h"

using namespace inertia::articulation;
namespace dd = dart::dynamics;

namespace {

Eigen::Isometry3d isometry(const PluckerTransform<double>& X) {
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

DartTree toDart(const Model<double>& model) {
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
Eigen::VectorXd dartPositions(const Model<double>& model, const DartTree& d,
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

Eigen::VectorXd toDartOrder(const DartTree& d, const VectorX<double>& x) {
  Eigen::VectorXd out(x.size());
  for (int k = 0; k < x.size(); ++k) out(d.dof[k]) = x(k);
  return out;
}

}  // namespace

// Both sides are double-precision recursions over the same data, so they agree to rounding,
// kappa(H) n eps ~ 1e-13 for these trees (measured: 1e-15 to 5e-14); the 1e-9 relative
// is asserted.
TEST(Dart, MassMatrixForwardAndInverseDynamicsAgree) {
  double worst[3] = {0, 0, 0};
  for (bool floating : {false, true}) {
    for (std::uint32_t seed = 1; seed <= 8; ++seed) {
      const Model<double> model = randomTree<double>(
          {.links = 10, .floatingBase = floating, .armature = false, .seed = seed});
      VectorX<double> q, qd;
      randomState(model, seed + 50, q, qd);
      const VectorX<double> tau = VectorX<double>::Random(model.nv());
      DartTree d = toDart(model);
      ASSERT_EQ(static_cast<int>(d.skeleton->getNumDofs()), model.nv());
      d.skeleton->setPositions(dartPositions(model, d, q));
      d.skeleton->setVelocities(toDartOrder(d, qd));

      const MatrixX<double> H = crba(model, q);
      MatrixX<double> Hd(model.nv(), model.nv());
      for (int a = 0; a < model.nv(); ++a)
        for (int b = 0; b < model.nv(); ++b)
          Hd(a, b) = d.skeleton->getMassMatrix()(d.dof[a], d.dof[b]);
      worst[0] = std::max(worst[0], (H - Hd).norm() / H.norm());
      EXPECT_LT((H - Hd).norm(), 1e-9 * H.norm()) << "seed " << seed << " floating " << floating;

      d.skeleton->setForces(toDartOrder(d, tau));
      d.skeleton->computeForwardDynamics();
      const VectorX<double> qdd = aba(model, q, qd, tau);
      const Eigen::VectorXd qddDart = d.skeleton->getAccelerations();
      worst[1] = std::max(worst[1], (toDartOrder(d, qdd) - qddDart).norm() / qdd.norm());
      EXPECT_LT((toDartOrder(d, qdd) - qddDart).norm(), 1e-9 * qdd.norm()) << "seed " << seed;

      d.skeleton->setAccelerations(toDartOrder(d, qdd));
      d.skeleton->computeInverseDynamics();
      const VectorX<double> tauOurs = rnea(model, q, qd, qdd);
      worst[2] = std::max(worst[2],
                          (toDartOrder(d, tauOurs) - d.skeleton->getForces()).norm() / tau.norm());
      EXPECT_LT((toDartOrder(d, tauOurs) - d.skeleton->getForces()).norm(), 1e-9 * tau.norm())
          << "seed " << seed;
    }
  }
  std::printf("against DART, worst relative difference: H %.3g, ABA %.3g, RNEA %.3g\n", worst[0],
              worst[1], worst[2]);
}
