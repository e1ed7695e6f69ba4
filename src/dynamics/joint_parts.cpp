// RowBlock's K^-1 for rows that are not a closed-form point constraint: a fixed-size LDLT per
// row count, in Real and, where Real's range or pivots fail, in double (joint_parts.h).
#include "joint_parts.h"

#include <Eigen/Cholesky>

namespace inertia::detail {

// K = J M^-1 J^T for N rows, in scalar S.
template <int N, class S>
Eigen::Matrix<S, N, N> RowBlock::massMatrix(const SolverBody& a, const SolverBody& b) const {
  const Eigen::Matrix<S, 3, 3> invA = a.invInertia.cast<S>(), invB = b.invInertia.cast<S>();
  std::array<Eigen::Matrix<S, 3, 1>, N> ia, ib;
  for (std::size_t i = 0; i < std::size_t(N); ++i) {
    ia[i] = invA * rows[i].ja.cast<S>();
    ib[i] = invB * rows[i].jb.cast<S>();
  }
  const S m = S(a.invMass) + S(b.invMass);
  Eigen::Matrix<S, N, N> k;
  for (std::size_t i = 0; i < std::size_t(N); ++i)
    for (std::size_t j = 0; j <= i; ++j)
      k(int(i), int(j)) = k(int(j), int(i)) =
          m * rows[i].linear.cast<S>().dot(rows[j].linear.cast<S>()) +
          rows[i].ja.cast<S>().dot(ia[j]) + rows[i].jb.cast<S>().dot(ib[j]);
  return k;
}
// K^-1 for N rows by a fixed-size LDLT (K is positive semi-definite; LDLT's pivoting keeps a
// singular K, two rows on one freedom, from blowing up). Where a pivot falls below 1e-4 of its
// row's diagonal (K's condition past 1e4 in that direction: an anchor at a lever far beyond
// a light body's radius of gyration), or K is not finite, the unscaled pivots carry rounding
// of K's largest entries, which may come out as noise of any size (a 2 mg bead welded 100 km
// away went to NaN in its first step, found by the world fuzz target); K is then made again
// in double, whose range holds what float's may not (a 4e-17 kg body on a 1e5 m arm has
// K_ii = 6e38: fuzz input world-light-body-joint-block-nan), and factored equilibrated by its
// diagonal, S = D^-1/2 K D^-1/2, whose pivots lie in [0, 1]. A pivot below N Real epsilons
// (the rounding the rows carry from Real, whatever the factorisation's precision) gets no
// impulse (K^-1 is S's pseudo-inverse, scaled back): a direction Real cannot resolve is left
// free rather than driven by noise.
template <int N>
void RowBlock::invert(const SolverBody& a, const SolverBody& b) {
  const Eigen::Matrix<Real, N, N> k = massMatrix<N, Real>(a, b);
  Eigen::Map<Eigen::Matrix<Real, N, N>> inverse(inverseMass.data());
  if constexpr (N == 1) {  // what LDLT's solve gives a 1 x 1 K
    inverse(0, 0) = k(0, 0) > std::numeric_limits<Real>::min() ? 1 / k(0, 0) : Real(0);
    return;
  }
  if (k.allFinite()) {
    const Eigen::LDLT<Eigen::Matrix<Real, N, N>> ldlt(k);
    // Pivot i is row P(i)'s diagonal less what the earlier rows explain of it.
    const Eigen::Matrix<Real, N, 1> diagonal = ldlt.transpositionsP() * k.diagonal();
    if (((ldlt.vectorD().array() >= Real(1e-4) * diagonal.array()) ||
         (diagonal.array() == 0 && ldlt.vectorD().array() == 0))
            .all()) {
      // Column by column, each a plain fixed-size vector solved in place: a matrix right-hand
      // side went through Eigen's blocked triangular solver (packing, GEMM kernels), 8% of
      // the ragdolls benchmark, and blocks of the identity and of this map as right-hand side
      // and result twice what this costs.
      for (int j = 0; j < N; ++j) {
        Eigen::Matrix<Real, N, 1> column = Eigen::Matrix<Real, N, 1>::Unit(j);
        ldlt.solveInPlace(column);
        inverse.col(j) = column;
      }
      return;
    }
  }
  using Wide = Eigen::Matrix<double, N, N>;
  const Wide wide = massMatrix<N, double>(a, b);
  // A diagonal below Real's smallest normal (0 in Real, as the rows' rounding has it) is a
  // direction left free, as in Real.
  constexpr double kSmallest = double(std::numeric_limits<Real>::min());
  Eigen::Matrix<double, N, 1> scale;
  for (int i = 0; i < N; ++i) scale(i) = wide(i, i) >= kSmallest ? 1 / std::sqrt(wide(i, i)) : 0.0;
  const Wide s = scale.asDiagonal() * wide * scale.asDiagonal();
  const Eigen::LDLT<Wide> scaled(s);
  const auto d = scaled.vectorD();
  Wide x = scaled.transpositionsP() * Wide::Identity();
  scaled.matrixL().solveInPlace(x);
  for (int i = 0; i < N; ++i)
    x.row(i) *= d(i) > N * double(std::numeric_limits<Real>::epsilon()) ? 1 / d(i) : 0.0;
  scaled.matrixU().solveInPlace(x);
  const Wide result =
      scale.asDiagonal() * (scaled.transpositionsP().transpose() * x) * scale.asDiagonal();
  // An entry past Real's range (a direction of near-infinite mass) gets no impulse either:
  // converting it would be undefined.
  constexpr double kLargest = double(std::numeric_limits<Real>::max());
  inverse = result.unaryExpr([](double v) { return std::abs(v) <= kLargest ? v : 0.0; })
                .template cast<Real>();
}

void RowBlock::invertRows(const SolverBody& a, const SolverBody& b) {
  switch (count) {
    case 1:
      return invert<1>(a, b);
    case 2:
      return invert<2>(a, b);
    case 3:
      return invert<3>(a, b);
    case 4:
      return invert<4>(a, b);
    case 5:
      return invert<5>(a, b);
    case 6:
      return invert<6>(a, b);
    default:
      return;
  }
}

}  // namespace inertia::detail
