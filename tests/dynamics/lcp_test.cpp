// The dense LCP solvers against oracles: brute-force enumeration of every active set (the
// unique solution of a positive definite LCP), the box KKT conditions, hand-solved friction,
// and degenerate or infeasible problems that must end with a clear status, never NaN.
#include "dynamics/lcp.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <optional>
#include <random>

#include "../epsilon.h"
#include "../draws.h"

using namespace inertia::detail;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using inertia::test::kDoubleEps;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A random symmetric positive definite matrix B B^T + 0.1 I (its smallest eigenvalue is at
// least 0.1, its largest about (sqrt(n) + 1)^2, so cond <= 1e3 for n <= 8).
MatrixXd randomSpd(int n, std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = g(rng);
  return B * B.transpose() + 0.1 * MatrixXd::Identity(n, n);
}

VectorXd randomVector(int n, std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = g(rng);
  return v;
}

double condition(const MatrixXd& A) {
  const Eigen::SelfAdjointEigenSolver<MatrixXd> es(A);
  return es.eigenvalues().maxCoeff() / es.eigenvalues().minCoeff();
}

// Forward error allowed for a solution computed by pivoting with backward-stable solves:
// a multiple of cond * eps (the constant covers the O(n) pivots at n <= 8).
double tolerance(const MatrixXd& A, const VectorXd& z) {
  return 1e3 * condition(A) * kDoubleEps * (1 + z.cwiseAbs().maxCoeff());
}

// Oracle: the standard LCP by trying all 2^n sets of positive z (the first one that is
// complementary; for a P-matrix it is the only one).
std::optional<VectorXd> enumerateLcp(const MatrixXd& M, const VectorXd& q) {
  const int n = static_cast<int>(q.size());
  for (int mask = 0; mask < (1 << n); ++mask) {
    std::vector<int> S;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) S.push_back(i);
    const int k = static_cast<int>(S.size());
    VectorXd z = VectorXd::Zero(n);
    if (k > 0) {
      MatrixXd Mss(k, k);
      VectorXd qs(k);
      for (int i = 0; i < k; ++i) {
        qs[i] = -q[S[i]];
        for (int j = 0; j < k; ++j) Mss(i, j) = M(S[i], S[j]);
      }
      const VectorXd zs = Mss.fullPivLu().solve(qs);
      for (int i = 0; i < k; ++i) z[S[i]] = zs[i];
    }
    const VectorXd w = M * z + q;
    if (z.minCoeff() >= -1e-12 && w.minCoeff() >= -1e-12) return z;
  }
  return std::nullopt;
}

// Oracle: the boxed LCP by trying all 3^n assignments (free, at lo, at hi).
std::optional<VectorXd> enumerateBoxed(const MatrixXd& A, const VectorXd& b, const VectorXd& lo,
                                       const VectorXd& hi) {
  const int n = static_cast<int>(b.size());
  int total = 1;
  for (int i = 0; i < n; ++i) total *= 3;
  for (int code = 0; code < total; ++code) {
    std::vector<int> state(static_cast<std::size_t>(n));
    int c = code;
    bool finite = true;
    for (int i = 0; i < n; ++i) {
      state[static_cast<std::size_t>(i)] = c % 3;
      c /= 3;
      if (state[static_cast<std::size_t>(i)] == 1 && !std::isfinite(lo[i])) finite = false;
      if (state[static_cast<std::size_t>(i)] == 2 && !std::isfinite(hi[i])) finite = false;
    }
    if (!finite) continue;
    std::vector<int> F;
    VectorXd z = VectorXd::Zero(n);
    for (int i = 0; i < n; ++i) {
      const int s = state[static_cast<std::size_t>(i)];
      if (s == 0) F.push_back(i);
      if (s == 1) z[i] = lo[i];
      if (s == 2) z[i] = hi[i];
    }
    const int k = static_cast<int>(F.size());
    if (k > 0) {
      const VectorXd r = A * z + b;
      MatrixXd Aff(k, k);
      VectorXd rf(k);
      for (int i = 0; i < k; ++i) {
        rf[i] = -r[F[i]];
        for (int j = 0; j < k; ++j) Aff(i, j) = A(F[i], F[j]);
      }
      const VectorXd zf = Aff.ldlt().solve(rf);
      for (int i = 0; i < k; ++i) z[F[i]] = zf[i];
    }
    const VectorXd w = A * z + b;
    bool ok = true;
    for (int i = 0; i < n && ok; ++i) {
      const int s = state[static_cast<std::size_t>(i)];
      if (s == 0) ok = z[i] >= lo[i] - 1e-12 && z[i] <= hi[i] + 1e-12;
      if (s == 1) ok = w[i] >= -1e-12;
      if (s == 2) ok = w[i] <= 1e-12;
    }
    if (ok) return z;
  }
  return std::nullopt;
}

// The box KKT conditions at z with bounds lo, hi, to tolerance tol: returns the first broken.
std::string kktViolation(const VectorXd& z, const VectorXd& w, const VectorXd& lo,
                         const VectorXd& hi, double tol) {
  for (Eigen::Index i = 0; i < z.size(); ++i) {
    if (z[i] < lo[i] - tol || z[i] > hi[i] + tol) return "z out of bounds at " + std::to_string(i);
    const bool atLo = z[i] <= lo[i] + tol, atHi = z[i] >= hi[i] - tol;
    if (atLo && atHi) continue;  // lo = hi: any w
    if (atLo && w[i] < -tol) return "w < 0 at lower bound, row " + std::to_string(i);
    if (atHi && w[i] > tol) return "w > 0 at upper bound, row " + std::to_string(i);
    if (!atLo && !atHi && std::abs(w[i]) > tol) return "w != 0 inside, row " + std::to_string(i);
  }
  return "";
}

}  // namespace

// Positive definite LCPs of sizes 1..8 (60 each) have one solution; Lemke and Dantzig
// (without bounds: lo = 0, hi = inf) both find the one enumeration finds.
TEST(Lcp, BothMethodsMatchEnumerationOnRandomSpd) {
  std::mt19937 rng(7);
  int nonTrivial = 0;
  for (int n = 1; n <= 8; ++n) {
    for (int trial = 0; trial < 60; ++trial) {
      const MatrixXd M = randomSpd(n, rng);
      const VectorXd q = randomVector(n, rng);
      const auto oracle = enumerateLcp(M, q);
      ASSERT_TRUE(oracle.has_value());
      const double tol = tolerance(M, *oracle);
      if (oracle->maxCoeff() > 0) ++nonTrivial;

      VectorXd z;
      const LcpResult lemke = solveLemke(M, q, z);
      ASSERT_TRUE(lemke.converged) << "n=" << n << " " << lcpStatusName(lemke.status);
      EXPECT_LE((z - *oracle).cwiseAbs().maxCoeff(), tol) << "lemke n=" << n;
      EXPECT_LE(lemke.residual, tol);

      BoxedLcp p;
      p.A = M;
      p.b = q;
      p.lo = VectorXd::Zero(n);
      p.hi = VectorXd::Constant(n, kInf);
      VectorXd y;
      const LcpResult dantzig = solveDantzig(p, y);
      ASSERT_TRUE(dantzig.converged) << "n=" << n << " " << lcpStatusName(dantzig.status);
      EXPECT_LE((y - *oracle).cwiseAbs().maxCoeff(), tol) << "dantzig n=" << n;
      EXPECT_LE(dantzig.residual, tol);
    }
  }
  EXPECT_GT(nonTrivial, 400);  // most problems have active contacts: the test exercises pivots
}

// Boxed LCPs of sizes 1..6 with random finite and infinite bounds: Dantzig matches the
// enumeration of all 3^n assignments, and the KKT conditions hold.
TEST(Lcp, DantzigMatchesEnumerationOnRandomBoxes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 2);
  int interior = 0, atBound = 0;
  for (int n = 1; n <= 6; ++n) {
    for (int trial = 0; trial < 40; ++trial) {
      BoxedLcp p;
      p.A = randomSpd(n, rng);
      p.b = 2 * randomVector(n, rng);
      p.lo.resize(n);
      p.hi.resize(n);
      for (int i = 0; i < n; ++i) {
        p.lo[i] = (trial + i) % 5 == 0 ? -kInf : -u(rng);
        p.hi[i] = (trial + i) % 7 == 0 ? kInf : u(rng);
      }
      const auto oracle = enumerateBoxed(p.A, p.b, p.lo, p.hi);
      ASSERT_TRUE(oracle.has_value());
      const double tol = tolerance(p.A, *oracle);
      VectorXd z;
      const LcpResult r = solveDantzig(p, z);
      ASSERT_TRUE(r.converged) << lcpStatusName(r.status);
      EXPECT_LE((z - *oracle).cwiseAbs().maxCoeff(), tol) << "n=" << n << " trial " << trial;
      EXPECT_EQ(kktViolation(z, p.A * z + p.b, p.lo, p.hi, tol), "");
      for (int i = 0; i < n; ++i) {
        if (z[i] > p.lo[i] + tol && z[i] < p.hi[i] - tol)
          ++interior;
        else
          ++atBound;
      }
    }
  }
  EXPECT_GT(interior, 50);
  EXPECT_GT(atBound, 50);
}

// A random contact problem: a column of k rigid bodies (random mass 0.5..2 kg, random
// rotated inertia), body 0 on the static ground, body i on body i-1, each contact at two
// random points with a normal tilted up to 20 degrees from +y and a random mu in 0.1..1.
// Rows per point: normal, then its two tangents. A = J M^-1 J^T (6 rows per body on its 6 degrees
// of freedom), b = J v - approach.
struct ContactProblem {
  BoxedLcp lcp;
  int points = 0;
};

ContactProblem randomContacts(int k, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1), pos(0.5, 2), mu(0.1, 1);
  const int pts = 2 * k, n = 3 * pts;
  MatrixXd J = MatrixXd::Zero(n, 6 * k), Minv = MatrixXd::Zero(6 * k, 6 * k);
  VectorXd v(6 * k);
  for (int i = 0; i < k; ++i) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(3 * u(rng), inertia::test::draw3<Eigen::Vector3d>([&] { return u(rng); }).normalized())
            .toRotationMatrix();
    const Eigen::Vector3d I = inertia::test::draw3<Eigen::Vector3d>([&] { return pos(rng); });
    Minv.block(6 * i, 6 * i, 3, 3) = Eigen::Matrix3d::Identity() / pos(rng);
    Minv.block(6 * i + 3, 6 * i + 3, 3, 3) = R * I.cwiseInverse().asDiagonal() * R.transpose();
    for (int c = 0; c < 6; ++c) v[6 * i + c] = 0.3 * u(rng);
  }
  ContactProblem out;
  out.points = pts;
  out.lcp.lo = VectorXd::Zero(n);
  out.lcp.hi = VectorXd::Zero(n);
  for (int p = 0; p < pts; ++p) {
    const int upper = p / 2, lower = upper - 1;  // bodies; -1: the ground
    // z drawn before x, as draw3 does (tests/draws.h).
    const double tz = u(rng), tx = u(rng);
    const Eigen::Vector3d tilt(0.35 * tx, 1, 0.35 * tz);
    const Eigen::Vector3d nrm = tilt.normalized();
    const Eigen::Vector3d t1 = nrm.unitOrthogonal(), t2 = nrm.cross(t1);
    const double rz = u(rng), rx = u(rng);
    const Eigen::Vector3d rB(0.5 * rx, -0.5, 0.5 * rz), rA(rB.x(), 0.5, rB.z());
    const Eigen::Vector3d dirs[3] = {nrm, t1, t2};
    for (int d = 0; d < 3; ++d) {
      const int row = 3 * p + d;
      J.block(row, 6 * upper, 1, 3) = dirs[d].transpose();
      J.block(row, 6 * upper + 3, 1, 3) = rB.cross(dirs[d]).transpose();
      if (lower >= 0) {
        J.block(row, 6 * lower, 1, 3) = -dirs[d].transpose();
        J.block(row, 6 * lower + 3, 1, 3) = -rA.cross(dirs[d]).transpose();
      }
    }
    out.lcp.hi[3 * p] = kInf;
    const double m = mu(rng);
    out.lcp.links.push_back({3 * p + 1, 3 * p, m});
    out.lcp.links.push_back({3 * p + 2, 3 * p, m});
  }
  // Two points leave the rotation about the line through them free (rank 5 per body): a
  // constraint force mixing of 0.01 (ODE's CFM) makes A definite, cond ~ 1e3.
  out.lcp.A = J * Minv * J.transpose() + 0.01 * MatrixXd::Identity(n, n);
  out.lcp.b = J * v;
  for (int p = 0; p < pts; ++p) out.lcp.b[3 * p] -= 0.5;  // approaching: the normals push
  return out;
}

// Contact problems with friction bounds tied to the normals (ODE's findex): the solution
// satisfies the box KKT conditions with the bounds its own normals give, and both regimes
// (friction saturated: sliding; inside its bounds: sticking) occur.
TEST(Lcp, DantzigFrictionBoundsFollowTheNormals) {
  std::mt19937 rng(3);
  int saturated = 0, sticking = 0;
  for (int k = 1; k <= 3; ++k) {
    for (int trial = 0; trial < 40; ++trial) {
      const ContactProblem c = randomContacts(k, rng);
      const BoxedLcp& p = c.lcp;
      VectorXd z;
      const LcpResult r = solveDantzig(p, z);
      ASSERT_TRUE(r.converged) << lcpStatusName(r.status) << " k=" << k << " trial " << trial;
      VectorXd lo, hi;
      boxBounds(p, z, lo, hi);
      const double tol = tolerance(p.A, z);
      EXPECT_EQ(kktViolation(z, p.A * z + p.b, lo, hi, tol), "") << "k=" << k << " trial " << trial;
      EXPECT_LE(r.residual, tol);
      EXPECT_NEAR(r.residual, boxedResidual(p, z), 1e-15);
      for (int i = 0; i < c.points; ++i)
        for (int t = 1; t <= 2; ++t) {
          if (std::abs(std::abs(z[3 * i + t]) - hi[3 * i + t]) <= tol)
            ++saturated;
          else
            ++sticking;
        }
    }
  }
  EXPECT_GT(saturated, 50);
  EXPECT_GT(sticking, 50);
}

// Warm start: given its own solution as the guess, Dantzig and Lemke take no pivot (the
// guessed active set is solved and passes the complementarity check); given a wrong guess,
// they still find the solution.
TEST(Lcp, WarmStartsAreCheckedBeforeUse) {
  std::mt19937 rng(21);
  int reused = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const ContactProblem c = randomContacts(2, rng);
    VectorXd z;
    ASSERT_TRUE(solveDantzig(c.lcp, z).converged);
    VectorXd again = z;
    const LcpResult warm = solveDantzig(c.lcp, again);
    ASSERT_TRUE(warm.converged);
    if (warm.iterations == 0) ++reused;
    const double tol = tolerance(c.lcp.A, z);
    EXPECT_LE((again - z).cwiseAbs().maxCoeff(), tol);
    VectorXd wrong = -z + VectorXd::Ones(z.size());  // every set guessed wrong
    const LcpResult cold = solveDantzig(c.lcp, wrong);
    ASSERT_TRUE(cold.converged);
    EXPECT_LE((wrong - z).cwiseAbs().maxCoeff(), tol);
  }
  EXPECT_EQ(reused, 40);

  for (int n = 2; n <= 8; ++n) {
    const MatrixXd M = randomSpd(n, rng);
    const VectorXd q = randomVector(n, rng);
    VectorXd z;
    ASSERT_TRUE(solveLemke(M, q, z).converged);
    const double tol = tolerance(M, z);
    if (z.maxCoeff() > 0) {  // a zero guess has no positive set to try
      VectorXd again = z;
      const LcpResult warm = solveLemke(M, q, again);
      ASSERT_TRUE(warm.converged);
      EXPECT_EQ(warm.iterations, 0) << n;
      EXPECT_LE((again - z).cwiseAbs().maxCoeff(), tol);
    }
    VectorXd wrong = VectorXd::Ones(n) - z;
    ASSERT_TRUE(solveLemke(M, q, wrong).converged);
    EXPECT_LE((wrong - z).cwiseAbs().maxCoeff(), tol) << n;
  }
}

// One particle of unit mass sliding at 2 m/s along t1 and approaching at 1 m/s, mu = 0.5,
// by hand: the normal impulse stops the approach (1 N s), friction saturates at mu * 1 =
// 0.5 N s against the slide, which continues at 1.5 m/s. Dantzig on the boxed rows and Lemke
// on the Stewart-Trinkle form (directions +t1, -t1, +t2, -t2, slack gamma) both give it.
TEST(Lcp, SlidingParticleByHand) {
  BoxedLcp p;
  p.A = MatrixXd::Identity(3, 3);
  p.b = VectorXd(3);
  p.b << -1, 2, 0;
  p.lo = VectorXd::Zero(3);
  p.hi = VectorXd(3);
  p.hi << kInf, 0, 0;
  p.links = {{1, 0, 0.5}, {2, 0, 0.5}};
  VectorXd z;
  ASSERT_TRUE(solveDantzig(p, z).converged);
  EXPECT_NEAR(z[0], 1, 1e-12);
  EXPECT_NEAR(z[1], -0.5, 1e-12);
  EXPECT_NEAR(z[2], 0, 1e-12);

  // Unknowns: z_n, beta(+t1, -t1, +t2, -t2), gamma.
  MatrixXd M = MatrixXd::Zero(6, 6);
  M(0, 0) = 1;
  const double sign[4] = {1, -1, 1, -1};
  const int axis[4] = {0, 0, 1, 1};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) M(1 + i, 1 + j) = axis[i] == axis[j] ? sign[i] * sign[j] : 0;
    M(1 + i, 5) = 1;
    M(5, 1 + i) = -1;
  }
  M(5, 0) = 0.5;
  VectorXd q(6);
  q << -1, 2, -2, 0, 0, 0;
  VectorXd x;
  const LcpResult r = solveLemke(M, q, x);
  ASSERT_TRUE(r.converged) << lcpStatusName(r.status);
  EXPECT_NEAR(x[0], 1, 1e-12);
  EXPECT_NEAR(x[1] - x[2], -0.5, 1e-12);  // z_t1
  EXPECT_NEAR(x[3] - x[4], 0, 1e-12);     // z_t2
  EXPECT_NEAR(x[5], 1.5, 1e-12);          // gamma: the sliding speed after the impulse
  EXPECT_LE(r.residual, 1e-12);
}

// Lemke on positive semidefinite (copositive-plus) matrices: a rank-one M with a family of
// solutions, and a skew-symmetric bimatrix-like M (PSD: z^T M z = 0). Checked by the
// definition: z >= 0, w >= 0, z.w = 0.
TEST(Lcp, LemkeSolvesSemidefiniteCases) {
  struct Case {
    MatrixXd M;
    VectorXd q;
  };
  std::vector<Case> cases;
  {
    MatrixXd M(2, 2);
    M << 1, 1, 1, 1;
    VectorXd q(2);
    q << -1, -1;
    cases.push_back({M, q});
  }
  {
    MatrixXd M(3, 3);
    M << 0, 1, -1, -1, 0, 2, 1, -2, 0;
    MatrixXd Ms = M;
    Ms(0, 0) = 1;  // skew plus a PSD diagonal: PSD, not symmetric
    VectorXd q(3);
    q << -1, 1, 0.5;
    cases.push_back({Ms, q});
  }
  {
    // Singular PSD: B B^T with B 5 x 2.
    std::mt19937 rng(5);
    MatrixXd B(5, 2);
    for (int i = 0; i < 5; ++i) B.row(i) = randomVector(2, rng).transpose();
    const VectorXd zStar = (VectorXd(5) << 1, 0, 2, 0, 0.5).finished();
    const MatrixXd M = B * B.transpose();
    VectorXd q = -M * zStar;  // feasible by construction: z* gives w = 0
    q[1] += 1;
    q[3] += 1;
    cases.push_back({M, q});
  }
  for (std::size_t k = 0; k < cases.size(); ++k) {
    VectorXd z;
    const LcpResult r = solveLemke(cases[k].M, cases[k].q, z);
    ASSERT_TRUE(r.converged) << "case " << k << ": " << lcpStatusName(r.status);
    const VectorXd w = cases[k].M * z + cases[k].q;
    EXPECT_GE(z.minCoeff(), -1e-12) << k;
    EXPECT_GE(w.minCoeff(), -1e-10) << k;
    EXPECT_LE(std::abs(z.dot(w)), 1e-10) << k;
  }
}

// Degenerate and impossible problems end with an answer or a clear status, never NaN.
TEST(Lcp, DegenerateAndInfeasibleProblemsTerminate) {
  // Duplicate rows (a box's redundant contact points): singular A, every split of the load
  // between the twins is a solution. Dantzig drives one twin; the other is held by it.
  {
    BoxedLcp p;
    p.A = MatrixXd::Constant(2, 2, 1.0);
    p.b = VectorXd::Constant(2, -1.0);
    p.lo = VectorXd::Zero(2);
    p.hi = VectorXd::Constant(2, kInf);
    VectorXd z;
    const LcpResult r = solveDantzig(p, z);
    ASSERT_TRUE(r.converged) << lcpStatusName(r.status);
    EXPECT_NEAR(z.sum(), 1, 1e-12);
    EXPECT_EQ(kktViolation(z, p.A * z + p.b, p.lo, p.hi, 1e-12), "");
    VectorXd x;
    const LcpResult l = solveLemke(p.A, p.b, x);
    ASSERT_TRUE(l.converged);
    EXPECT_NEAR(x.sum(), 1, 1e-12);
  }
  // All ratios tie at the first pivot (q constant, M = I): the lexicographic rule decides.
  {
    VectorXd z;
    const LcpResult r = solveLemke(MatrixXd::Identity(4, 4), VectorXd::Constant(4, -1.0), z);
    ASSERT_TRUE(r.converged);
    EXPECT_LE((z - VectorXd::Ones(4)).cwiseAbs().maxCoeff(), 1e-14);
  }
  // Degenerate zeros in q (resting contacts with zero relative velocity).
  {
    MatrixXd M(3, 3);
    M << 2, 1, 0, 1, 2, 1, 0, 1, 2;
    VectorXd q(3);
    q << 0, -1, 0;
    VectorXd z;
    const LcpResult r = solveLemke(M, q, z);
    ASSERT_TRUE(r.converged);
    const auto oracle = enumerateLcp(M, q);
    EXPECT_LE((z - *oracle).cwiseAbs().maxCoeff(), 1e-12);
  }
  // Infeasible: w_0 = -1 whatever z (a zero row). Lemke ends on a secondary ray, Dantzig on
  // a direction nothing blocks; both leave z finite.
  {
    MatrixXd M = MatrixXd::Zero(2, 2);
    M(1, 1) = 1;
    const VectorXd q = VectorXd::Constant(2, -1.0);
    VectorXd z;
    const LcpResult r = solveLemke(M, q, z);
    EXPECT_EQ(r.status, LcpStatus::Unbounded);
    EXPECT_FALSE(r.converged);
    EXPECT_TRUE(z.allFinite());
    BoxedLcp p;
    p.A = M;
    p.b = q;
    p.lo = VectorXd::Zero(2);
    p.hi = VectorXd::Constant(2, kInf);
    VectorXd y;
    const LcpResult d = solveDantzig(p, y);
    EXPECT_FALSE(d.converged);
    EXPECT_NE(d.status, LcpStatus::Solved);
    EXPECT_TRUE(y.allFinite());
  }
  // A pivot cap too small for the problem: IterationLimit, not a wrong answer.
  {
    std::mt19937 rng(9);
    const MatrixXd M = randomSpd(6, rng);
    const VectorXd q = -VectorXd::Ones(6) - M * VectorXd::Ones(6);  // every z positive
    VectorXd z;
    const LcpResult r = solveLemke(M, q, z, {.maxPivots = 3, .pivotTolerance = 1e-11});
    EXPECT_EQ(r.status, LcpStatus::IterationLimit);
    EXPECT_TRUE(z.allFinite());
  }
  // Invalid input: NaN, wrong sizes, a lower bound above zero.
  {
    VectorXd z;
    MatrixXd M = MatrixXd::Identity(2, 2);
    M(0, 1) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(solveLemke(M, VectorXd::Ones(2), z).status, LcpStatus::InvalidInput);
    EXPECT_EQ(solveLemke(MatrixXd::Identity(3, 3), VectorXd::Ones(2), z).status,
              LcpStatus::InvalidInput);
    BoxedLcp p;
    p.A = MatrixXd::Identity(1, 1);
    p.b = VectorXd::Ones(1);
    p.lo = VectorXd::Constant(1, 0.5);
    p.hi = VectorXd::Constant(1, 1.0);
    EXPECT_EQ(solveDantzig(p, z).status, LcpStatus::InvalidInput);
  }
}
