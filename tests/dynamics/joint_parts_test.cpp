// A joint's row block against an independent K^-1 (joint_parts.cpp): K = J M^-1 J^T made in
// double from the rows' Jacobians and the bodies' inverse mass matrices, inverted by a full-
// pivot LU. LDLT is backward stable, so its inverse is off by at most a small multiple of
// N kappa(K) eps relative; the tests allow 16 N kappa eps. A singular K (two rows on one
// freedom) gets a pseudo-inverse (K X K = K), and a K past float's range a finite one.
#include "dynamics/joint_parts.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "../draws.h"

using namespace inertia;
using namespace inertia::detail;
using inertia::test::randomRotation;
using inertia::test::randomVec;

namespace {

using MatD = Eigen::MatrixXd;

// A body with inverse mass m and a random world inverse inertia with principal values in
// [lo, hi) (1/(kg m^2)).
SolverBody randomBody(std::mt19937_64& rng, Real m, double lo, double hi) {
  SolverBody b;
  b.invMass = m;
  const Mat3 r = randomRotation(rng).toRotationMatrix();
  b.invInertia = r * randomVec(rng, lo, hi).asDiagonal() * r.transpose();
  return b;
}

// K = J M^-1 J^T in double, J's row i = [-l, -ja, l, jb] on (vA, wA, vB, wB).
MatD exactK(const RowBlock& block, const SolverBody& a, const SolverBody& b) {
  const int n = block.count;
  MatD j = MatD::Zero(n, 12), minv = MatD::Zero(12, 12);
  for (int i = 0; i < n; ++i) {
    const JointRow& r = block.rows[std::size_t(i)];
    j.block<1, 3>(i, 0) = -r.linear.cast<double>().transpose();
    j.block<1, 3>(i, 3) = -r.ja.cast<double>().transpose();
    j.block<1, 3>(i, 6) = r.linear.cast<double>().transpose();
    j.block<1, 3>(i, 9) = r.jb.cast<double>().transpose();
  }
  minv.block<3, 3>(0, 0) = double(a.invMass) * Eigen::Matrix3d::Identity();
  minv.block<3, 3>(3, 3) = a.invInertia.cast<double>();
  minv.block<3, 3>(6, 6) = double(b.invMass) * Eigen::Matrix3d::Identity();
  minv.block<3, 3>(9, 9) = b.invInertia.cast<double>();
  return j * minv * j.transpose();
}

// The block's K^-1 (count x count, column-major), in double.
MatD inverseOf(const RowBlock& block) {
  const int n = block.count;
  MatD x(n, n);
  for (int c = 0; c < n; ++c)
    for (int r = 0; r < n; ++r) x(r, c) = double(block.inverseMass[std::size_t(c * n + r)]);
  return x;
}

double kappa(const MatD& k) {
  const Eigen::JacobiSVD<MatD> svd(k);
  return svd.singularValues()(0) / svd.singularValues()(k.rows() - 1);
}

constexpr double kEps = std::numeric_limits<Real>::epsilon();

}  // namespace

TEST(JointRowBlock, InverseMatchesAnIndependentInverseForOneToSixRows) {
  std::mt19937_64 rng(1701);
  double worst = 0;
  for (int k = 0; k < 600; ++k) {
    const int n = 1 + k % 6;
    const SolverBody a = randomBody(rng, Real(0.5), 0.2, 5), b = randomBody(rng, Real(2), 0.2, 5);
    RowBlock block;
    block.clear();
    for (int i = 0; i < n; ++i) {
      const Vec3 dir = randomVec(rng, -1, 1).normalized();
      // Linear rows with lever arms up to 1 m, and angular rows, mixed.
      if (i % 2 == 0)
        block.add(linearRow(dir, randomVec(rng, -1, 1), randomVec(rng, -1, 1)));
      else
        block.add(angularRow(dir));
    }
    block.prepare(a, b, RowBlock::Vector::Zero(n));
    const MatD exact = exactK(block, a, b);
    const double cond = kappa(exact);
    const MatD inv = exact.fullPivLu().inverse();
    const double error = (inverseOf(block) - inv).norm() / inv.norm();
    ASSERT_LE(error, 16 * n * cond * kEps) << k << " rows " << n << " condition " << cond;
    worst = std::max(worst, error / (n * cond * kEps));
  }
  std::printf("row blocks: worst error %.2f N kappa eps\n", worst);
}

// A ball joint's three anchor rows by the closed-form adjugate (invertPoint) and by the rows'
// LDLT (invertRows): the same K^-1 to the LDLT's accuracy.
TEST(JointRowBlock, PointBlockAgreesWithItsRowsLdlt) {
  std::mt19937_64 rng(1702);
  for (int k = 0; k < 200; ++k) {
    const SolverBody a = randomBody(rng, Real(1), 0.5, 3), b = randomBody(rng, Real(0.3), 0.5, 3);
    const Vec3 rA = randomVec(rng, -1, 1), rB = randomVec(rng, -1, 1);
    RowBlock point;
    point.setPoint(rA, rB);
    ASSERT_TRUE(point.invertPoint(a, b)) << k;
    RowBlock rows;
    for (int i = 0; i < 3; ++i) rows.add(linearRow(Vec3::Unit(i), rA, rB));
    rows.prepare(a, b, RowBlock::Vector::Zero(3));
    const MatD exact = exactK(rows, a, b);
    const MatD x = inverseOf(rows);
    const double tol = 16 * 3 * kappa(exact) * kEps * x.norm();
    const std::array<std::array<int, 2>, 6> packed{
        {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}}};
    for (std::size_t e = 0; e < packed.size(); ++e)
      ASSERT_NEAR(point.inverseMass[e], x(packed[e][0], packed[e][1]), tol) << k << " entry " << e;
  }
}

// Two rows on one freedom: K is singular. The free direction gets no impulse, so X is K's
// pseudo-inverse: K X K = K to rounding, and X is finite.
TEST(JointRowBlock, TwoRowsOnOneFreedomGiveAPseudoInverse) {
  std::mt19937_64 rng(1703);
  const SolverBody a = randomBody(rng, Real(1), 0.5, 3), b = randomBody(rng, Real(1), 0.5, 3);
  const JointRow row = linearRow(Vec3(0, 1, 0), Vec3(Real(0.3), 0, 0), Vec3(0, 0, Real(0.2)));
  RowBlock block;
  block.add(row);
  block.add(row);
  block.prepare(a, b, RowBlock::Vector::Zero(2));
  const MatD k = exactK(block, a, b), x = inverseOf(block);
  ASSERT_TRUE(x.allFinite());
  EXPECT_LE((k * x * k - k).norm(), 64 * kEps * k.norm());
}

// A 4e-18 kg bead's rows 1e5 m from its centre: K's entries pass float's range (the world fuzz
// target's input world-light-body-joint-block-nan). K is made again in double; whatever Real
// cannot resolve is left free, and K^-1 stays finite.
TEST(JointRowBlock, AKPastFloatsRangeGivesAFiniteInverse) {
  SolverBody world, bead;
  bead.invMass = Real(2.5e17);
  bead.invInertia = Real(6e29) * Mat3::Identity();
  RowBlock block;
  for (int i = 0; i < 3; ++i)
    block.add(linearRow(Vec3::Unit(i), Vec3::Zero(), Vec3(Real(1e5), 0, 0)));
  block.add(angularRow(Vec3::UnitZ()));
  block.prepare(world, bead, RowBlock::Vector::Zero(4));
  EXPECT_TRUE(inverseOf(block).allFinite());
}
