// The URDF arm (robots/arm7.urdf) against DART, an independent implementation of the dynamics:
// DART's skeleton is built here from urdfdom's parse of the file (DART's own URDF loader is not
// packaged in Debian), our model by io::loadUrdf; then the mass matrix, forward dynamics and
// inverse dynamics compared at random states within the joint limits. Built only where CMake
// finds DART.
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

// Only the dynamics headers: DART's umbrella header pulls in IkFast, packaged apart.
#include <algorithm>
#include <cstdio>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/WeldJoint.hpp>
#include <filesystem>
#include <random>

#include "../articulation/dart_model.h"
#include "inertia/articulation/dynamics.h"
#include "inertia/io/urdf.h"

using namespace inertia;
namespace art = inertia::articulation;
namespace dd = dart::dynamics;

namespace {

std::filesystem::path armFile() {
  const char* root = std::getenv("INERTIA_SOURCE_DIR");
  return std::filesystem::path(root ? root : ".") / "robots" / "arm7.urdf";
}

Eigen::Isometry3d isometry(const urdf::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return T;
}

// DART's body for a URDF link: the inertia tensor turned from the inertial frame to the link's.
dd::BodyNode::Properties body(const urdf::Link& link) {
  dd::BodyNode::Properties b;
  b.mName = link.name;
  if (!link.inertial) {
    b.mInertia = dd::Inertia(0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero());
    return b;
  }
  const urdf::Inertial& u = *link.inertial;
  Eigen::Matrix3d I;
  I << u.ixx, u.ixy, u.ixz, u.ixy, u.iyy, u.iyz, u.ixz, u.iyz, u.izz;
  const Eigen::Isometry3d frame = isometry(u.origin);
  b.mInertia =
      dd::Inertia(u.mass, frame.translation(), frame.linear() * I * frame.linear().transpose());
  return b;
}

// The link and its subtree: revolute and continuous joints as DART's revolute joints, fixed ones
// (and the root's attachment to the world) as weld joints.
void addSubtree(const dd::SkeletonPtr& skeleton, dd::BodyNode* parent, const urdf::Link& link) {
  const urdf::Joint* j = link.parent_joint.get();
  dd::BodyNode* node = nullptr;
  if (j && (j->type == urdf::Joint::REVOLUTE || j->type == urdf::Joint::CONTINUOUS)) {
    dd::RevoluteJoint::Properties p;
    p.mName = j->name;
    p.mT_ParentBodyToJoint = isometry(j->parent_to_joint_origin_transform);
    p.mAxis = Eigen::Vector3d(j->axis.x, j->axis.y, j->axis.z).normalized();
    node = skeleton->createJointAndBodyNodePair<dd::RevoluteJoint>(parent, p, body(link)).second;
  } else {
    ASSERT_TRUE(!j || j->type == urdf::Joint::FIXED) << "the test's arm has no other joints";
    dd::WeldJoint::Properties p;
    p.mName = j ? j->name : "root";
    if (j) p.mT_ParentBodyToJoint = isometry(j->parent_to_joint_origin_transform);
    node = skeleton->createJointAndBodyNodePair<dd::WeldJoint>(parent, p, body(link)).second;
  }
  for (const urdf::LinkSharedPtr& child : link.child_links) addSubtree(skeleton, node, *child);
}

}  // namespace

// In double both sides are recursions over the same numbers and agree to rounding,
// kappa(H) n eps ~ 1e-13; the 1e-9 relative is asserted. In float our model holds the
// file's numbers rounded to float (6e-8 relative) and computes in float: the mass matrix and
// forward dynamics to 1e-5 (measured 8e-7 and 2e-7), inverse dynamics to 1e-4 relative to the
// torques, which are differences of gravity and inertial terms several times larger (measured
// 2e-5).
TEST(UrdfDart, ArmMassMatrixForwardAndInverseDynamicsAgree) {
  const bool dbl = std::is_same_v<Real, double>;
  const double tolH = dbl ? 1e-9 : 1e-5, tolAba = dbl ? 1e-9 : 1e-5, tolRnea = dbl ? 1e-9 : 1e-4;
  const io::UrdfRobot robot = io::loadUrdf(armFile());
  const urdf::ModelInterfaceSharedPtr parsed = urdf::parseURDFFile(armFile().string());
  ASSERT_TRUE(parsed);
  const dd::SkeletonPtr skeleton = dd::Skeleton::create("arm");
  addSubtree(skeleton, nullptr, *parsed->getRoot());
  const art::Model<Real>& model = robot.model;
  const int n = model.nv();
  ASSERT_EQ(int(skeleton->getNumDofs()), n);
  skeleton->setGravity(model.gravity.cast<double>());
  // Our dof k is the joint of the link with vIndex k: DART's dof of the joint of that name.
  std::vector<int> dof(std::size_t(n), -1);
  for (const io::UrdfJoint& j : robot.joints) {
    const art::Link<Real>& l = model.link(j.link);
    if (l.nv == 1)
      dof[std::size_t(l.vIndex)] = int(skeleton->getJoint(j.name)->getDof(0)->getIndexInSkeleton());
  }
  auto toDart = [&](const Eigen::VectorXd& x) {
    Eigen::VectorXd out(n);
    for (int k = 0; k < n; ++k) out(dof[std::size_t(k)]) = x(k);
    return out;
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  double worst[3] = {0, 0, 0};
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::VectorXd q(n), qd(n), tau(n);
    for (int k = 0; k < n; ++k) {
      q(k) = model.lower()(k) + unit(rng) * (model.upper()(k) - model.lower()(k));
      qd(k) = 2 * unit(rng) - 1;
      tau(k) = 20 * unit(rng) - 10;
    }
    skeleton->setPositions(toDart(q));
    skeleton->setVelocities(toDart(qd));
    const art::VectorX<Real> qr = q.cast<Real>(), qdr = qd.cast<Real>(), taur = tau.cast<Real>();

    const Eigen::MatrixXd H = art::crba(model, qr).cast<double>();
    Eigen::MatrixXd Hd(n, n);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        Hd(a, b) = skeleton->getMassMatrix()(dof[std::size_t(a)], dof[std::size_t(b)]);
    worst[0] = std::max(worst[0], (H - Hd).norm() / Hd.norm());
    EXPECT_LT((H - Hd).norm(), tolH * Hd.norm()) << "trial " << trial;

    skeleton->setForces(toDart(tau));
    skeleton->computeForwardDynamics();
    const Eigen::VectorXd qdd = art::aba(model, qr, qdr, taur).cast<double>();
    const Eigen::VectorXd qddDart =
        art::dart_peer::readDartVector(n, [&](int i) { return skeleton->getAcceleration(i); });
    worst[1] = std::max(worst[1], (toDart(qdd) - qddDart).norm() / qddDart.norm());
    EXPECT_LT((toDart(qdd) - qddDart).norm(), tolAba * qddDart.norm()) << "trial " << trial;

    skeleton->setAccelerations(qddDart);
    skeleton->computeInverseDynamics();
    const Eigen::VectorXd tauOurs =
        art::rnea(model, qr, qdr,
                  art::VectorX<Real>(art::dart_peer::readDartVector(
                                         n, [&](int k) { return qddDart(dof[std::size_t(k)]); })
                                         .cast<Real>()))
            .cast<double>();
    const Eigen::VectorXd tauDart =
        art::dart_peer::readDartVector(n, [&](int i) { return skeleton->getForce(i); });
    worst[2] = std::max(worst[2], (toDart(tauOurs) - tauDart).norm() / tauDart.norm());
    EXPECT_LT((toDart(tauOurs) - tauDart).norm(), tolRnea * tauDart.norm()) << "trial " << trial;
  }
  std::printf("URDF arm against DART, worst relative difference: H %.3g, ABA %.3g, RNEA %.3g\n",
              worst[0], worst[1], worst[2]);
}
