// Internal: dense direct solvers of linear complementarity problems, for small systems.
//
// - Lemke's complementary pivoting method (Lemke 1965; Cottle, Pang & Stone, "The Linear
//   Complementarity Problem", 1992, section 4.4) for the standard LCP
//       w = M z + q,  w >= 0,  z >= 0,  w.z = 0,
//   with the covering vector of ones and the lexicographic minimum-ratio rule (no cycling on
//   degenerate problems). It terminates with a solution for every P-matrix and for
//   copositive-plus M whose LCP is feasible (positive semidefinite M, Stewart-Trinkle
//   friction); otherwise with a secondary ray (status Unbounded).
// - Dantzig's principal pivoting method for the boxed LCP (Baraff 1994, "Fast contact force
//   computation for nonpenetrating rigid bodies"; ODE's dLCP):
//       w = A z + b,  lo <= z <= hi,  z_i = lo_i => w_i >= 0,  z_i = hi_i => w_i <= 0,
//       lo_i < z_i < hi_i => w_i = 0,
//   A symmetric positive definite (semidefinite A needs a regularisation, see lcp_contact.cpp).
//   Variables are added one at a time; each is driven towards complementarity while the ones
//   already added keep theirs, every step a linear solve on the free set (Eigen LDLT). Friction
//   rows have bounds that depend on other variables (ODE's "findex"): lo = -hi, hi = sum of
//   coefficient * z_source (mu * z_normal). They are found by a fixed point on the bounds,
//   then the active set it settles on is solved exactly with the bounds as linear equations
//   (Eigen LU) and checked.
//
// Everything is in double whatever `Real` is: the pivoting decisions compare quantities that
// cancel, and the tests compare against exact enumeration. No allocation-free promise: these
// solvers are for validation and teaching.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

namespace inertia::detail {

/// The bound of a row without one.
inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

enum class LcpStatus {
  Solved,          ///< Complementary solution found.
  IterationLimit,  ///< The pivot cap was reached (cycling or a too hard problem).
  Unbounded,       ///< Lemke: secondary ray; Dantzig: a direction without a blocking bound.
  NotConverged,    ///< Dantzig: the friction bounds' fixed point did not settle.
  Singular,        ///< Dantzig: the free set's matrix could not be factored.
  InvalidInput,    ///< Wrong sizes, non-finite data or lo > 0 / hi < 0.
};

const char* lcpStatusName(LcpStatus status);

struct LcpResult {
  LcpStatus status = LcpStatus::InvalidInput;
  bool converged = false;  ///< status == Solved.
  int iterations = 0;      ///< Pivots (Lemke), pivots over all passes (Dantzig).
  /// Natural residual max_i |mid(z_i - lo_i, z_i - hi_i, w_i)| (min(z_i, w_i) without bounds):
  /// zero exactly at a solution; mixes the units of z and w, so meaningful on scaled problems.
  double residual = 0;
};

struct LemkeOptions {
  int maxPivots = 0;              ///< 0: 50 n + 100.
  double pivotTolerance = 1e-11;  ///< Entries below this times the column's scale are zero.
};

/// Lemke's method. On entry z may hold a guess (size n): the set of its positive entries is
/// tried first (one linear solve, kept only if it is a solution). On return z holds the
/// solution; z = 0 and status != Solved when it fails. Never produces NaN from finite input.
LcpResult solveLemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, Eigen::VectorXd& z,
                     const LemkeOptions& options = {});

/// A bound that depends on other variables: row `row` is boxed in [-limit, limit] with
/// limit = sum over its links of coefficient * max(z[source], 0). Rows with links ignore lo/hi.
struct LcpLink {
  int row = 0;
  int source = 0;
  double coefficient = 0;
};

struct BoxedLcp {
  Eigen::MatrixXd A;   ///< n x n, symmetric positive definite.
  Eigen::VectorXd b;   ///< w = A z + b.
  Eigen::VectorXd lo;  ///< <= 0, may be -infinity.
  Eigen::VectorXd hi;  ///< >= 0, may be +infinity.
  std::vector<LcpLink> links;
};

struct DantzigOptions {
  int maxPivots = 0;            ///< Per pass; 0: 20 n + 100.
  int maxBoundIterations = 30;  ///< Fixed-point passes on the friction bounds.
  double tolerance = 1e-10;     ///< Relative, on the bounds' change and the final checks.
};

/// The bounds of every row for a given z (links applied).
void boxBounds(const BoxedLcp& p, const Eigen::VectorXd& z, Eigen::VectorXd& lo,
               Eigen::VectorXd& hi);

/// Natural residual of the boxed LCP at z, with the bounds that z implies.
double boxedResidual(const BoxedLcp& p, const Eigen::VectorXd& z);

/// Dantzig's method on the boxed LCP. On entry z may hold a guess (size n): the active set it
/// implies is solved first (one LU, kept only if it passes the KKT check, then iterations is
/// 0), and its normals give the first friction bounds (else the first pass is frictionless).
/// On return z holds the solution; on failure the best iterate (finite) and status says why.
LcpResult solveDantzig(const BoxedLcp& problem, Eigen::VectorXd& z,
                       const DantzigOptions& options = {});

}  // namespace inertia::detail
