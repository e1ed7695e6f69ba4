// Featherstone's algorithms against each other and against closed forms: ABA equals CRBA with a
// Cholesky solve, RNEA inverts ABA, H is symmetric positive definite with 1/2 qd.H qd the kinetic
// energy, simple and double pendulums against their equations of motion, gravity forces as the
// gradient of the potential energy, Jacobians and momentum against finite differences.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "../epsilon.h"
#include "inertia/articulation/builders.h"
#include "inertia/articulation/dynamics.h"

using namespace inertia::articulation;
using inertia::test::kDoubleEps;

namespace {

// The 2-norm condition number of a symmetric positive definite matrix.
double condition(const MatrixX<double>& H) {
  const Eigen::SelfAdjointEigenSolver<MatrixX<double>> eig(H);
  return eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
}

// Both forward dynamics compute H^-1 (tau - C) by backward-stable recursions of 6x6 products, n
// levels deep; perturbation theory bounds their relative difference by kappa(H) times their
// relative backward errors, O(n eps) each. 16 covers the handful of roundings per level.
double solveTolerance(const MatrixX<double>& H) {
  return 16 * double(H.rows()) * condition(H) * kDoubleEps;
}

struct Case {
  Model<double> model;
  VectorX<double> q, qd, tau;
};

Case randomCase(std::uint32_t seed, bool floating, int links = 12) {
  Case c{randomTree<double>({.links = links, .floatingBase = floating, .seed = seed}), {}, {}, {}};
  randomState(c.model, seed + 1000, c.q, c.qd);
  c.tau = VectorX<double>::Random(c.model.nv());
  return c;
}

}  // namespace

TEST(Algorithms, RandomTreesHaveEveryJointType) {
  const Model<double> m = randomTree<double>({.links = 9, .floatingBase = true});
  int counts[5] = {};
  for (const Link<double>& l : m.links()) ++counts[static_cast<int>(l.joint)];
  for (int t = 0; t < 5; ++t) EXPECT_GE(counts[t], 1) << "joint type " << t;
}

TEST(Algorithms, AbaEqualsCrbaWithCholesky) {
  double worst = 0;
  for (bool floating : {false, true}) {
    for (std::uint32_t seed = 1; seed <= 20; ++seed) {
      const Case c = randomCase(seed, floating);
      const VectorX<double> a = aba(c.model, c.q, c.qd, c.tau);
      const VectorX<double> b = forwardDynamicsCrba(c.model, c.q, c.qd, c.tau);
      const double rel = (a - b).norm() / b.norm();
      const double tol = solveTolerance(crba(c.model, c.q));
      EXPECT_LT(rel, tol) << "seed " << seed << " floating " << floating;
      worst = std::max(worst, rel);
    }
  }
  EXPECT_LT(worst, 1e-10);  // the bound, met by these well-conditioned trees
  std::printf("ABA against CRBA + Cholesky: worst relative difference %.3g\n", worst);
}

TEST(Algorithms, RneaInvertsAba) {
  for (bool floating : {false, true}) {
    for (std::uint32_t seed = 1; seed <= 20; ++seed) {
      const Case c = randomCase(seed, floating);
      const VectorX<double> qdd = aba(c.model, c.q, c.qd, c.tau);
      const VectorX<double> tau = rnea(c.model, c.q, c.qd, qdd);
      // tau = H qdd + C: rounding relative to the largest of the terms summed.
      const VectorX<double> C = rnea(c.model, c.q, c.qd, VectorX<double>::Zero(c.model.nv()));
      const MatrixX<double> H = crba(c.model, c.q);
      const double scale = c.tau.norm() + C.norm() + H.norm() * qdd.norm();
      EXPECT_LT((tau - c.tau).norm(), solveTolerance(H) * scale) << "seed " << seed;
    }
  }
}

TEST(Algorithms, MassMatrixIsSymmetricPositiveDefiniteWithKineticEnergy) {
  for (bool floating : {false, true}) {
    for (std::uint32_t seed = 1; seed <= 10; ++seed) {
      const Case c = randomCase(seed, floating);
      const MatrixX<double> H = crba(c.model, c.q);
      EXPECT_EQ(H, H.transpose());  // crba copies H_ji from H_ij and symmetrises H_ii
      EXPECT_EQ(Eigen::LLT<MatrixX<double>>(H).info(), Eigen::Success);
      const double T = kineticEnergy(c.model, c.q, c.qd);
      // Two sums of the same n positive terms, ordered differently: a few n eps relative.
      EXPECT_NEAR(c.qd.dot(H * c.qd), 2 * T,
                  8 * double(H.rows()) * kDoubleEps * H.norm() * c.qd.squaredNorm());
    }
  }
}

// Column k of H is the joint force that accelerates dof k alone at unit rate, without velocity
// or gravity: RNEA with qdd = e_k, an independent path through the tree.
TEST(Algorithms, MassMatrixColumnsAreRneaResponses) {
  Case c = randomCase(7, true);
  c.model.gravity.setZero();
  const MatrixX<double> H = crba(c.model, c.q);
  const VectorX<double> zero = VectorX<double>::Zero(c.model.nv());
  for (int k = 0; k < c.model.nv(); ++k) {
    const VectorX<double> col = rnea(c.model, c.q, zero, VectorX<double>::Unit(c.model.nv(), k));
    EXPECT_LT((col - H.col(k)).norm(), 64 * kDoubleEps * H.norm()) << "column " << k;
  }
}

// A point mass m on a massless rod of length l (plus the link's tiny rotational inertia I about
// its centre of mass): (m l^2 + I) theta'' = -m g l sin(theta).
TEST(Algorithms, SimplePendulumMatchesItsEquationOfMotion) {
  const double l = 1.3, m = 2.0, g = 9.81, I = 1e-6 * m;
  const Model<double> model = pendulumChain<double>(1, l, m);
  for (double theta : {0.0, 0.4, 1.5, 3.0, -2.2}) {
    VectorX<double> q(1), qd(1), tau = VectorX<double>::Zero(1);
    q << theta;
    qd << 0.7;
    const double expected = -m * g * l * std::sin(theta) / (m * l * l + I);
    EXPECT_NEAR(aba(model, q, qd, tau)(0), expected, 16 * kDoubleEps * g / l);
    EXPECT_NEAR(forwardDynamicsCrba(model, q, qd, tau)(0), expected, 16 * kDoubleEps * g / l);
  }
}

// Lagrange's equations of the double pendulum in absolute angles t1 = q1, t2 = q1 + q2 (point
// masses, each link with rotational inertia I_i about its mass):
//   ((m1 + m2) l1^2 + I1) t1'' + m2 l1 l2 cos(t1 - t2) t2'' + m2 l1 l2 sin(t1 - t2) t2'^2
//       + (m1 + m2) g l1 sin(t1) = 0
//   (m2 l2^2 + I2) t2'' + m2 l1 l2 cos(t1 - t2) t1'' - m2 l1 l2 sin(t1 - t2) t1'^2
//       + m2 g l2 sin(t2) = 0
TEST(Algorithms, DoublePendulumMatchesItsEquationsOfMotion) {
  const double l = 0.8, m = 1.5, g = 9.81, I = 1e-6 * m;
  const Model<double> model = pendulumChain<double>(2, l, m);
  for (auto [q1, q2, w1, w2] :
       {std::array{0.3, -0.5, 1.0, 2.0}, {2.0, 1.0, -3.0, 0.5}, {-1.0, 2.5, 0.0, 0.0}}) {
    const double t1 = q1, t2 = q1 + q2, u1 = w1, u2 = w1 + w2;
    Eigen::Matrix2d M;
    M << 2 * m * l * l + I, m * l * l * std::cos(t1 - t2), m * l * l * std::cos(t1 - t2),
        m * l * l + I;
    const Eigen::Vector2d rhs(
        -m * l * l * std::sin(t1 - t2) * u2 * u2 - 2 * m * g * l * std::sin(t1),
        m * l * l * std::sin(t1 - t2) * u1 * u1 - m * g * l * std::sin(t2));
    const Eigen::Vector2d tdd = M.lu().solve(rhs);
    VectorX<double> q(2), qd(2);
    q << q1, q2;
    qd << w1, w2;
    const VectorX<double> qdd = aba(model, q, qd, VectorX<double>::Zero(2));
    // The closed form's own 2x2 solve and the recursions: kappa(M) eps relative.
    const double JacobiCond = M.norm() * M.inverse().norm();
    const double tol = 64 * JacobiCond * kDoubleEps * (rhs.norm() / (m * l * l) + 1);
    EXPECT_NEAR(qdd(0), tdd(0), tol);
    EXPECT_NEAR(qdd(1), tdd(1) - tdd(0), tol);
  }
}

// Central differences along each velocity direction (through the configuration's exponential
// map, so quaternions stay on their sphere): error O(eps^2 f''') + O(ulp f / eps); eps = 1e-5
// makes both about 1e-10 for these unit-sized trees.
TEST(Algorithms, GravityForcesAreTheGradientOfPotentialEnergy) {
  const double eps = 1e-5;
  for (bool floating : {false, true}) {
    const Case c = randomCase(3, floating);
    const VectorX<double> zero = VectorX<double>::Zero(c.model.nv());
    const VectorX<double> G = rnea(c.model, c.q, zero, zero);
    for (int k = 0; k < c.model.nv(); ++k) {
      VectorX<double> qp = c.q, qm = c.q;
      const VectorX<double> e = VectorX<double>::Unit(c.model.nv(), k);
      integrateConfiguration(c.model, qp, e, eps);
      integrateConfiguration(c.model, qm, e, -eps);
      const double dV = (potentialEnergy(c.model, qp) - potentialEnergy(c.model, qm)) / (2 * eps);
      EXPECT_NEAR(G(k), dV, 1e-7) << "dof " << k;
    }
  }
}

TEST(Algorithms, PointJacobianMatchesFiniteDifferences) {
  const double eps = 1e-5;
  for (bool floating : {false, true}) {
    const Case c = randomCase(5, floating);
    const Vector3<double> point(0.1, -0.2, 0.3);
    for (int link : {0, 5, 11}) {
      const Matrix6X<double> J = pointJacobian(c.model, c.q, link, point);
      VectorX<double> qp = c.q, qm = c.q;
      integrateConfiguration(c.model, qp, c.qd, eps);
      integrateConfiguration(c.model, qm, c.qd, -eps);
      const Vector3<double> v =
          (pointPosition(c.model, qp, link, point) - pointPosition(c.model, qm, link, point)) /
          (2 * eps);
      // R+ R-^T = exp(2 eps [w]) in base axes; link poses map base to link coordinates (E).
      const Matrix3<double> dR =
          linkPose(c.model, qp, link).E.transpose() * linkPose(c.model, qm, link).E;
      const Eigen::AngleAxisd aa(dR);
      const Vector3<double> w = aa.axis() * aa.angle() / (2 * eps);
      const Vector6<double> Jqd = J * c.qd;
      EXPECT_LT((Jqd.head<3>() - w).norm(), 1e-8) << "link " << link;
      EXPECT_LT((Jqd.tail<3>() - v).norm(), 1e-8) << "link " << link;
    }
  }
}

// Linear momentum is the total mass times the velocity of the centre of mass.
TEST(Algorithms, LinearMomentumIsMassTimesCentreOfMassVelocity) {
  const double eps = 1e-5;
  const Case c = randomCase(9, true);
  double mass = 0;
  for (const Link<double>& l : c.model.links()) mass += l.mass;
  VectorX<double> qp = c.q, qm = c.q;
  integrateConfiguration(c.model, qp, c.qd, eps);
  integrateConfiguration(c.model, qm, c.qd, -eps);
  const Vector3<double> vcom = (centerOfMass(c.model, qp) - centerOfMass(c.model, qm)) / (2 * eps);
  EXPECT_LT((momentum(c.model, c.q, c.qd).tail<3>() - mass * vcom).norm(), 1e-8 * mass);
}

// Potential energy is -M g . com.
TEST(Algorithms, PotentialEnergyIsThatOfTheCentreOfMass) {
  const Case c = randomCase(11, true);
  double mass = 0;
  for (const Link<double>& l : c.model.links()) mass += l.mass;
  EXPECT_NEAR(potentialEnergy(c.model, c.q),
              -mass * c.model.gravity.dot(centerOfMass(c.model, c.q)), 1e-12 * mass * 9.81 * 10);
}

// In float the same identity holds to float rounding: kappa(H) n eps_float.
TEST(Algorithms, AbaEqualsCrbaInFloat) {
  const Model<float> model = randomTree<float>({.links = 8, .seed = 4});
  VectorX<float> q, qd;
  randomState(model, 4, q, qd);
  const VectorX<float> tau = VectorX<float>::Ones(model.nv());
  const VectorX<float> a = aba(model, q, qd, tau);
  const VectorX<float> b = forwardDynamicsCrba(model, q, qd, tau);
  const MatrixX<float> H = crba(model, q);
  const double tol = 16 * 8 * condition(H.cast<double>()) * std::numeric_limits<float>::epsilon();
  EXPECT_LT((a - b).norm() / b.norm(), tol);
}
