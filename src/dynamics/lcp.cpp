#include "lcp.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

namespace inertia::detail {

namespace {

double median3(double a, double b, double c) {
  return std::max(std::min(a, b), std::min(std::max(a, b), c));
}

bool squareFinite(const Eigen::MatrixXd& A, Eigen::Index n) {
  return A.rows() == n && A.cols() == n && A.allFinite();
}

double standardResidual(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                        const Eigen::VectorXd& z) {
  if (z.size() == 0) return 0;
  const Eigen::VectorXd w = M * z + q;
  return z.cwiseMin(w).cwiseAbs().maxCoeff();
}

LcpResult finish(LcpStatus status, int iterations, double residual) {
  LcpResult r;
  r.status = status;
  r.converged = status == LcpStatus::Solved;
  r.iterations = iterations;
  r.residual = residual;
  return r;
}

// ---- Lemke -----------------------------------------------------------------------------

// The tableau B^-1 [I, -M, -e, q]: columns 0..n-1 are w, n..2n-1 are z, 2n is the artificial
// z0, 2n+1 the basic solution. Columns 0..n-1 hold B^-1, which the lexicographic rule reads.
class LemkeTableau {
 public:
  LemkeTableau(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) : n_(q.size()) {
    T_.setZero(n_, 2 * n_ + 2);
    T_.leftCols(n_).setIdentity();
    T_.middleCols(n_, n_) = -M;
    T_.col(2 * n_).setConstant(-1);
    T_.col(2 * n_ + 1) = q;
    basis_.resize(static_cast<std::size_t>(n_));
    for (Eigen::Index i = 0; i < n_; ++i) basis_[static_cast<std::size_t>(i)] = i;
  }

  Eigen::Index z0() const { return 2 * n_; }
  Eigen::Index rhs() const { return 2 * n_ + 1; }
  Eigen::Index basic(Eigen::Index row) const { return basis_[static_cast<std::size_t>(row)]; }
  const Eigen::MatrixXd& table() const { return T_; }

  // Gauss-Jordan pivot: variable `col` enters the basis in row `r`.
  void pivot(Eigen::Index r, Eigen::Index col) {
    T_.row(r) /= T_(r, col);
    T_(r, col) = 1;
    for (Eigen::Index i = 0; i < n_; ++i) {
      if (i == r) continue;
      const double f = T_(i, col);
      if (f == 0) continue;
      T_.row(i) -= f * T_.row(r);
      T_(i, col) = 0;
    }
    // Feasibility is kept in exact arithmetic; rounding may leave -1e-17.
    for (Eigen::Index i = 0; i < n_; ++i) T_(i, rhs()) = std::max(T_(i, rhs()), 0.0);
    basis_[static_cast<std::size_t>(r)] = col;
  }

  // Lexicographic minimum ratio test on column `col` (Cottle-Pang-Stone 4.4.4): among rows
  // with a positive entry, the smallest rhs/entry; ties broken by the rows of B^-1 divided by
  // the entry, which are distinct, so the choice is unique and the method cannot cycle. The
  // artificial variable leaves first when it ties. -1: no positive entry (a ray).
  Eigen::Index ratioTest(Eigen::Index col, double tolerance) const {
    const double scale = T_.col(col).cwiseAbs().maxCoeff();
    if (!(scale > tolerance)) return -1;
    const double eps = tolerance * scale;
    Eigen::Index best = -1;
    for (Eigen::Index i = 0; i < n_; ++i) {
      const double a = T_(i, col);
      if (a <= eps) continue;
      if (best < 0) {
        best = i;
        continue;
      }
      const double ri = T_(i, rhs()) / a, rb = T_(best, rhs()) / T_(best, col);
      const double tie = 1e-12 * (1 + std::abs(rb));
      if (ri < rb - tie) {
        best = i;
      } else if (ri <= rb + tie) {
        if (basic(best) == z0()) continue;
        if (basic(i) == z0() || lexicallySmaller(i, best, col)) best = i;
      }
    }
    return best;
  }

 private:
  bool lexicallySmaller(Eigen::Index i, Eigen::Index j, Eigen::Index col) const {
    for (Eigen::Index k = 0; k < n_; ++k) {
      const double a = T_(i, k) / T_(i, col), b = T_(j, k) / T_(j, col);
      if (std::abs(a - b) > 1e-12 * (1 + std::abs(a) + std::abs(b))) return a < b;
    }
    return i < j;
  }

  Eigen::Index n_;
  Eigen::MatrixXd T_;
  std::vector<Eigen::Index> basis_;
};

// Warm start: the positive set of a guess (the last substep's solution) solved directly,
// M_SS z_S = -q_S (LU), kept only if complementary to rounding. A contact at rest keeps its
// set, so one factorisation replaces the pivots.
bool tryGuessedSet(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Eigen::VectorXd& g,
                   Eigen::VectorXd& z) {
  const Eigen::Index n = q.size();
  const double band = 1e-9 * g.cwiseAbs().maxCoeff();
  std::vector<Eigen::Index> S;
  for (Eigen::Index i = 0; i < n; ++i)
    if (g[i] > band) S.push_back(i);
  const auto k = static_cast<Eigen::Index>(S.size());
  if (k == 0) return false;
  Eigen::MatrixXd Mss(k, k);
  Eigen::VectorXd qs(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    qs[i] = -q[S[static_cast<std::size_t>(i)]];
    for (Eigen::Index j = 0; j < k; ++j)
      Mss(i, j) = M(S[static_cast<std::size_t>(i)], S[static_cast<std::size_t>(j)]);
  }
  const Eigen::VectorXd x = Mss.partialPivLu().solve(qs);
  if (!x.allFinite()) return false;
  Eigen::VectorXd candidate = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < k; ++i) candidate[S[static_cast<std::size_t>(i)]] = x[i];
  const double scale = q.cwiseAbs().maxCoeff() + M.cwiseAbs().maxCoeff() * x.cwiseAbs().maxCoeff();
  if (standardResidual(M, q, candidate) > 1e-10 * scale) return false;
  z = candidate.cwiseMax(0.0);
  return true;
}

// ---- Dantzig ---------------------------------------------------------------------------

enum class Set : signed char { Unprocessed, Free, AtLo, AtHi };

struct PassWork {
  std::vector<Set> set;
  std::vector<Eigen::Index> free;
  Eigen::VectorXd w, dz, dw, rhs;
  Eigen::MatrixXd Aff;
};

// One pass of Baraff's method with fixed bounds, from z = 0 (0 lies in every box). Variable d
// is driven along dz (dz_d = s, dz_F keeps w_F = 0, the rest fixed) until the first event: w_d
// reaches 0 (d becomes free), z_d reaches a bound, a free variable reaches a bound, or a
// variable at a bound sees its w reach 0 (it becomes free). With A positive definite the
// pivot A_dd - A_dF A_FF^-1 A_Fd is positive, so |w_d| falls at every non-degenerate step.
LcpStatus dantzigPass(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& lo,
                      const Eigen::VectorXd& hi, Eigen::VectorXd& z, PassWork& k, int maxPivots,
                      double tolW, int& pivots) {
  const Eigen::Index n = b.size();
  z.setZero(n);
  k.set.assign(static_cast<std::size_t>(n), Set::Unprocessed);
  k.w = b;
  const double tinyW = 1e-13 * A.diagonal().cwiseAbs().maxCoeff();
  auto set = [&](Eigen::Index i) -> Set& { return k.set[static_cast<std::size_t>(i)]; };
  for (Eigen::Index d = 0; d < n; ++d) {
    const double wd = k.w[d];
    if (wd >= -tolW && lo[d] >= 0) {
      set(d) = Set::AtLo;
      continue;
    }
    if (wd <= tolW && hi[d] <= 0) {
      set(d) = Set::AtHi;
      continue;
    }
    if (std::abs(wd) <= tolW) {
      set(d) = Set::Free;
      continue;
    }
    const double s = wd > 0 ? -1.0 : 1.0;
    for (;;) {
      if (++pivots > maxPivots) return LcpStatus::IterationLimit;
      k.free.clear();
      for (Eigen::Index j = 0; j < n; ++j)
        if (set(j) == Set::Free) k.free.push_back(j);
      const auto m = static_cast<Eigen::Index>(k.free.size());
      k.dz.setZero(n);
      k.dz[d] = s;
      if (m > 0) {
        k.Aff.resize(m, m);
        k.rhs.resize(m);
        for (Eigen::Index i = 0; i < m; ++i) {
          const Eigen::Index fi = k.free[static_cast<std::size_t>(i)];
          for (Eigen::Index j = 0; j < m; ++j)
            k.Aff(i, j) = A(fi, k.free[static_cast<std::size_t>(j)]);
          k.rhs[i] = -s * A(fi, d);
        }
        const Eigen::LDLT<Eigen::MatrixXd> ldlt(k.Aff);
        if (ldlt.info() != Eigen::Success) return LcpStatus::Singular;
        const Eigen::VectorXd x = ldlt.solve(k.rhs);
        if (!x.allFinite()) return LcpStatus::Singular;
        for (Eigen::Index i = 0; i < m; ++i) k.dz[k.free[static_cast<std::size_t>(i)]] = x[i];
      }
      k.dw.noalias() = A * k.dz;
      const double tinyZ = 1e-13 * k.dz.cwiseAbs().maxCoeff();

      double t = kUnbounded;
      Eigen::Index who = -1;
      Set to = Set::Unprocessed;
      auto consider = [&](double tc, Eigen::Index j, Set target) {
        if (tc < t) {
          t = tc;
          who = j;
          to = target;
        }
      };
      if (s * k.dw[d] > tinyW) consider(-k.w[d] / k.dw[d], d, Set::Free);
      if (s > 0 && hi[d] < kUnbounded) consider(hi[d] - z[d], d, Set::AtHi);
      if (s < 0 && lo[d] > -kUnbounded) consider(z[d] - lo[d], d, Set::AtLo);
      for (Eigen::Index j = 0; j < n; ++j) {
        if (j == d) continue;
        const Set sj = set(j);
        if (sj == Set::Free) {
          if (k.dz[j] < -tinyZ && lo[j] > -kUnbounded)
            consider((lo[j] - z[j]) / k.dz[j], j, Set::AtLo);
          if (k.dz[j] > tinyZ && hi[j] < kUnbounded)
            consider((hi[j] - z[j]) / k.dz[j], j, Set::AtHi);
        } else if (sj == Set::AtLo && lo[j] < hi[j]) {
          if (k.dw[j] < -tinyW) consider(-k.w[j] / k.dw[j], j, Set::Free);
        } else if (sj == Set::AtHi && lo[j] < hi[j]) {
          if (k.dw[j] > tinyW) consider(-k.w[j] / k.dw[j], j, Set::Free);
        }
      }
      if (who < 0) return LcpStatus::Unbounded;
      t = std::max(t, 0.0);
      z += t * k.dz;
      if (to == Set::AtLo) z[who] = lo[who];
      if (to == Set::AtHi) z[who] = hi[who];
      set(who) = to;
      // Recomputed rather than updated, so rounding does not accumulate over the pivots.
      k.w.noalias() = A * z;
      k.w += b;
      if (who == d) break;
    }
  }
  return LcpStatus::Solved;
}

// With the active set of a pass, the linked bounds become linear equations: a free row has
// w_i = 0, a row at a fixed bound z_i = bound, a linked row at its bound
// z_i = -/+ sum c z_source. Solving them together (LU, the system is not symmetric) gives the
// exact solution for that active set, where the fixed point only approaches it.
bool polish(const BoxedLcp& p, const std::vector<Set>& set, const Eigen::VectorXd& lo,
            const Eigen::VectorXd& hi, Eigen::VectorXd& z) {
  const Eigen::Index n = p.b.size();
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
  std::vector<char> linked(static_cast<std::size_t>(n), 0);
  for (const LcpLink& l : p.links) linked[static_cast<std::size_t>(l.row)] = 1;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Set s = set[static_cast<std::size_t>(i)];
    if (s == Set::Free) {
      G.row(i) = p.A.row(i);
      r[i] = -p.b[i];
    } else {
      G(i, i) = 1;
      if (!linked[static_cast<std::size_t>(i)]) r[i] = s == Set::AtHi ? hi[i] : lo[i];
    }
  }
  for (const LcpLink& l : p.links) {
    const Set s = set[static_cast<std::size_t>(l.row)];
    if (s == Set::Free) continue;
    G(l.row, l.source) += s == Set::AtHi ? -l.coefficient : l.coefficient;
  }
  const Eigen::VectorXd x = G.partialPivLu().solve(r);
  if (!x.allFinite()) return false;
  z = x;
  return true;
}

}  // namespace

const char* lcpStatusName(LcpStatus status) {
  switch (status) {
    case LcpStatus::Solved:
      return "solved";
    case LcpStatus::IterationLimit:
      return "iteration limit";
    case LcpStatus::Unbounded:
      return "unbounded (ray)";
    case LcpStatus::NotConverged:
      return "friction bounds not converged";
    case LcpStatus::Singular:
      return "singular";
    case LcpStatus::InvalidInput:
      return "invalid input";
  }
  return "?";
}

LcpResult solveLemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, Eigen::VectorXd& z,
                     const LemkeOptions& options) {
  const Eigen::Index n = q.size();
  const Eigen::VectorXd guess = z.size() == n && z.allFinite() ? z : Eigen::VectorXd();
  z.setZero(n);
  if (!squareFinite(M, n) || !q.allFinite()) return finish(LcpStatus::InvalidInput, 0, 0);
  if (n == 0 || q.minCoeff() >= 0) return finish(LcpStatus::Solved, 0, standardResidual(M, q, z));
  if (guess.size() == n && tryGuessedSet(M, q, guess, z))
    return finish(LcpStatus::Solved, 0, standardResidual(M, q, z));
  const int cap = options.maxPivots > 0 ? options.maxPivots : 50 * static_cast<int>(n) + 100;

  LemkeTableau T(M, q);
  // z0 enters at the row of the most negative q (the first such row: lexicographic for B = I).
  Eigen::Index r = 0;
  for (Eigen::Index i = 1; i < n; ++i)
    if (q[i] < q[r]) r = i;
  Eigen::Index leaving = T.basic(r);
  T.pivot(r, T.z0());
  int pivots = 1;
  for (;;) {
    // The complement of the variable that left enters.
    const Eigen::Index entering = leaving < n ? leaving + n : leaving - n;
    if (pivots >= cap) return finish(LcpStatus::IterationLimit, pivots, 0);
    r = T.ratioTest(entering, options.pivotTolerance);
    if (r < 0) return finish(LcpStatus::Unbounded, pivots, 0);
    leaving = T.basic(r);
    T.pivot(r, entering);
    ++pivots;
    if (leaving == T.z0()) break;
  }

  Eigen::VectorXd zt = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (T.basic(i) >= n && T.basic(i) < 2 * n) zt[T.basic(i) - n] = T.table()(i, T.rhs());
  // Refinement: the final basis solved afresh from M and q (LU), which removes the rounding
  // the pivots accumulated; kept when it is the better solution.
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index v = T.basic(i);
    if (v < n)
      B(v, i) = 1;
    else
      B.col(i) = -M.col(v - n);
  }
  const Eigen::VectorXd x = B.partialPivLu().solve(q);
  Eigen::VectorXd zr = Eigen::VectorXd::Zero(n);
  if (x.allFinite()) {
    for (Eigen::Index i = 0; i < n; ++i)
      if (T.basic(i) >= n) zr[T.basic(i) - n] = std::max(x[i], 0.0);
  }
  const double rt = standardResidual(M, q, zt);
  const double rr = x.allFinite() ? standardResidual(M, q, zr) : kUnbounded;
  z = rr < rt ? zr : zt;
  return finish(LcpStatus::Solved, pivots, std::min(rt, rr));
}

void boxBounds(const BoxedLcp& p, const Eigen::VectorXd& z, Eigen::VectorXd& lo,
               Eigen::VectorXd& hi) {
  lo = p.lo;
  hi = p.hi;
  for (const LcpLink& l : p.links) {
    hi[l.row] = 0;
    lo[l.row] = 0;
  }
  for (const LcpLink& l : p.links) hi[l.row] += l.coefficient * std::max(z[l.source], 0.0);
  for (const LcpLink& l : p.links) lo[l.row] = -hi[l.row];
}

double boxedResidual(const BoxedLcp& p, const Eigen::VectorXd& z) {
  if (z.size() == 0) return 0;
  Eigen::VectorXd lo, hi;
  boxBounds(p, z, lo, hi);
  const Eigen::VectorXd w = p.A * z + p.b;
  double r = 0;
  for (Eigen::Index i = 0; i < z.size(); ++i)
    r = std::max(r, std::abs(median3(z[i] - lo[i], z[i] - hi[i], w[i])));
  return r;
}

LcpResult solveDantzig(const BoxedLcp& p, Eigen::VectorXd& z, const DantzigOptions& options) {
  const Eigen::Index n = p.b.size();
  bool valid = squareFinite(p.A, n) && p.b.allFinite() && p.lo.size() == n && p.hi.size() == n;
  for (const LcpLink& l : p.links)
    valid = valid && l.row >= 0 && l.row < n && l.source >= 0 && l.source < n &&
            l.row != l.source && std::isfinite(l.coefficient) && l.coefficient >= 0;
  for (Eigen::Index i = 0; valid && i < n; ++i)
    valid = !std::isnan(p.lo[i]) && !std::isnan(p.hi[i]) && p.lo[i] <= 0 && p.hi[i] >= 0;
  const bool guess = z.size() == n && z.allFinite();
  if (!valid) {
    z.setZero(n);
    return finish(LcpStatus::InvalidInput, 0, 0);
  }
  if (n == 0) return finish(LcpStatus::Solved, 0, 0);
  const int cap = options.maxPivots > 0 ? options.maxPivots : 20 * static_cast<int>(n) + 100;
  const double bScale = p.b.cwiseAbs().maxCoeff();
  const double tolW = options.tolerance * bScale;

  Eigen::VectorXd lo, hi;
  // The z whose normals set the friction bounds of the next pass.
  Eigen::VectorXd zBound = guess ? z : Eigen::VectorXd::Zero(n).eval();
  boxBounds(p, zBound, lo, hi);
  PassWork work;
  int pivots = 0;
  auto small = [&](double residual, const Eigen::VectorXd& x) {
    return residual <= 1e3 * options.tolerance * (bScale + x.cwiseAbs().maxCoeff());
  };
  if (guess) {
    // Warm start: the active set the guess implies (a contact at rest keeps it from one
    // substep to the next), solved exactly and accepted only if it passes the KKT check.
    work.set.assign(static_cast<std::size_t>(n), Set::Free);
    const double zScale = z.cwiseAbs().maxCoeff();
    for (Eigen::Index i = 0; i < n; ++i) {
      const double band = 1e-9 * (std::abs(z[i]) + zScale);
      Set& s = work.set[static_cast<std::size_t>(i)];
      if (lo[i] == hi[i] || z[i] <= lo[i] + band)
        s = Set::AtLo;
      else if (z[i] >= hi[i] - band)
        s = Set::AtHi;
    }
    Eigen::VectorXd zw = z;
    if (polish(p, work.set, lo, hi, zw)) {
      const double r = boxedResidual(p, zw);
      if (small(r, zw)) {
        z = zw;
        return finish(LcpStatus::Solved, 0, r);
      }
    }
  }
  if (p.links.empty()) {
    const LcpStatus s = dantzigPass(p.A, p.b, lo, hi, z, work, cap, tolW, pivots);
    const double residual = boxedResidual(p, z);
    if (s != LcpStatus::Solved) return finish(s, pivots, residual);
    return finish(small(residual, z) ? LcpStatus::Solved : LcpStatus::NotConverged, pivots,
                  residual);
  }
  Eigen::VectorXd best = Eigen::VectorXd::Zero(n), zp;
  double bestResidual = kUnbounded;
  auto consider = [&](const Eigen::VectorXd& x) {
    const double r = boxedResidual(p, x);
    if (r < bestResidual) {
      bestResidual = r;
      best = x;
    }
  };
  for (int pass = 0; pass < std::max(options.maxBoundIterations, 1); ++pass) {
    const LcpStatus s = dantzigPass(p.A, p.b, lo, hi, z, work, cap * (pass + 1), tolW, pivots);
    if (s != LcpStatus::Solved) {
      if (bestResidual < kUnbounded) z = best;
      return finish(s, pivots, boxedResidual(p, z));
    }
    consider(z);
    // This pass's active set solved exactly with the linked bounds.
    zp = z;
    if (polish(p, work.set, lo, hi, zp)) consider(zp);
    if (small(bestResidual, best)) {
      z = best;
      return finish(LcpStatus::Solved, pivots, bestResidual);
    }
    // Next bounds: the plain fixed point first, then under-relaxed, as the usual failure is
    // an oscillation between two active sets.
    const double omega = pass < 4 ? 1.0 : 0.5;
    zBound = (1 - omega) * zBound + omega * z;
    boxBounds(p, zBound, lo, hi);
  }
  z = best;
  return finish(LcpStatus::NotConverged, pivots, bestResidual);
}

}  // namespace inertia::detail
