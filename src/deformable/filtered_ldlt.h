// A direct solve of the implicit step's Newton system with Baraff and Witkin's filter: the
// system S H S p = -S g with (I - S) p = 0, for H the Hessian of the incremental potential and
// S the filter (0 at a pinned or sticking vertex, I - n n^T at a sliding one), written as one
// symmetric positive definite matrix
//     A = S H S + (I - S)
// (on the filter's range it is S H S; on its complement, the identity, so A p = -S g gives
// (I - S) p = 0), assembled from the springs' 3 x 3 blocks and factored by a sparse LDL^T:
// Eigen's SimplicialLDLT, on vertices ordered once by approximate minimum degree (Amestoy,
// Davis and Duff 1996), so that the factor of a strand stays as sparse as the strand.
//
// The modified PCG converges to the same p (its iterates live in the filter's range and its
// residual is filtered); this gives it in one factorisation, which wins where the system is
// ill conditioned and its factor cheap: long, nearly inextensible strands held at many points
// (hair resting on a head), whose block-Jacobi PCG needs hundreds of iterations per solve.
// A sheet's or a volume's factor fills in (6 times the matrix at 40 x 40 cloth cells, 9 times
// at 100 x 100, growing with size), and PCG is faster there.
//
// The springs' connected components (hair's strands) are independent systems: they are
// grouped, in order of their first vertex, into parts of at least kPartVertices vertices, each
// factored on its own and on the step's workers. The parts do not depend on the number of
// workers, so neither do the bytes.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "dynamics/step_workers.h"
#include "inertia/deformable/model.h"

namespace inertia::detail {

/// A symmetric 3 x 3 block: xx, yy, zz, xy, xz, yz.
using SymmetricBlock = std::array<double, 6>;

/// The filter's 3 x 3 block at a vertex (global index), or null where it is the identity.
using ProjectionOf = const Eigen::Matrix3d* (*)(const void* context, std::uint32_t vertex);

/// One part: the filtered system over some vertices and the springs among them.
class FilteredLdlt {
 public:
  /// The pattern of H over `vertices` (global indices; `local` maps each to its index in that
  /// list) and `springs` (indices into `all`) in the elimination order `order` (local
  /// indices), and its symbolic factorisation.
  void connect(std::span<const Spring> all, std::span<const std::uint32_t> springs,
               std::span<const std::uint32_t> vertices, std::span<const std::uint32_t> local,
               std::span<const std::uint32_t> order);

  /// Assembles A from H = diag(diagonal) + the springs' blocks (+ at (a, a) and (b, b), - at
  /// (a, b) and (b, a)) and the filter, and factors it. False when the factorisation failed (A
  /// not numerically positive definite).
  bool factor(const Eigen::VectorXd& diagonal, std::span<const SymmetricBlock> blocks,
              ProjectionOf projection, const void* context);

  /// x = A^-1 b on this part's vertices (global vectors), after factor() succeeded.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

 private:
  void assemble(const Eigen::VectorXd& diagonal, std::span<const SymmetricBlock> blocks);
  void filter(ProjectionOf projection, const void* context);
  // Entry (row, col) of off-diagonal block `block` (rows of its first vertex).
  double& entry(std::size_t block, int row, int col) {
    return values_[blockColumns_[block][std::size_t(col)] + row];
  }
  // Entry (row, col), row <= col, of diagonal block p: column 3p + col ends with rows
  // 3p .. 3p + col (nothing below the diagonal is stored).
  double& diagonalEntry(std::size_t p, int row, int col) {
    return values_[diagonalEnds_[p][std::size_t(col)] - (col - row)];
  }

  // The part's vertices (global) in AMD's order: vertex ordered_[p] is block p of A.
  std::vector<std::uint32_t> ordered_;
  // The springs (global), each with its block (or -1 for one from a vertex to itself) and its
  // ends' blocks; per off-diagonal block, its two vertices' blocks (upper: first < second) and
  // the offsets in values_ of its three columns' first entries; per vertex block, where its
  // three columns end.
  std::vector<std::uint32_t> springs_;
  std::vector<std::int32_t> springBlock_;
  std::vector<std::array<std::uint32_t, 2>> springEnds_;
  std::vector<std::array<std::uint32_t, 2>> blockEnds_;
  std::vector<std::array<int, 3>> blockColumns_;
  std::vector<std::array<int, 3>> diagonalEnds_;
  Eigen::SparseMatrix<double> upper_;  // A's upper triangle, in AMD's order
  double* values_ = nullptr;           // upper_'s values
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper, Eigen::NaturalOrdering<int>>
      ldlt_;
  Eigen::VectorXd permuted_, inverseD_;
};

/// The whole system, split into parts by the springs' connected components.
class FilteredDirectSolve {
 public:
  /// Vertices per part at least (a part holds whole components).
  static constexpr std::size_t kPartVertices = 1024;

  // A cache of the springs' pattern and factors (Eigen's solvers do not copy): a copy or a
  // moved-to one starts empty and builds its own, the same, so a copied deformable steps to
  // the same bytes.
  FilteredDirectSolve() = default;
  FilteredDirectSolve(const FilteredDirectSolve&) {}
  FilteredDirectSolve(FilteredDirectSolve&&) noexcept {}
  FilteredDirectSolve& operator=(const FilteredDirectSolve&) {
    forget();
    return *this;
  }
  FilteredDirectSolve& operator=(FilteredDirectSolve&&) noexcept {
    forget();
    return *this;
  }

  /// Builds the parts when the springs' ends, the vertex count or maxFill changed since the
  /// last call, and says whether the direct solve is worth it here: whether the factors'
  /// non-zeros are at most maxFill times the matrices' (how much the elimination fills in).
  /// The count runs over the vertices' elimination tree before any factor is built and stops
  /// once past the bound (a large sheet or volume costs its ordering, not its factor); when
  /// not worth it no parts are kept (the answer is, for the same springs).
  bool connect(std::span<const Spring> springs, std::size_t vertices, double maxFill);

  /// factor() then solve() on every part, on `workers` when given; false (x unspecified) when
  /// a part's factorisation failed.
  bool solve(const Eigen::VectorXd& diagonal, std::span<const SymmetricBlock> blocks,
             ProjectionOf projection, const void* context, const Eigen::VectorXd& b,
             Eigen::VectorXd& x, StepWorkers* workers);

 private:
  void forget() {
    ends_.clear();
    vertices_ = 0;
    maxFill_ = 0;
    worthIt_ = false;
    parts_.clear();
  }
  static bool fillWithin(std::span<const Spring> springs,
                         const std::vector<std::vector<std::uint32_t>>& partVertices,
                         const std::vector<std::vector<std::uint32_t>>& partSprings,
                         std::span<const std::uint32_t> local,
                         const std::vector<std::vector<std::uint32_t>>& orders, double maxFill);

  std::vector<std::array<std::uint32_t, 2>> ends_;  // the springs' ends the parts are for
  std::size_t vertices_ = 0;
  double maxFill_ = 0;
  bool worthIt_ = false;
  std::vector<std::unique_ptr<FilteredLdlt>> parts_;  // Eigen's solvers do not move
  std::vector<std::uint8_t> factored_;                // per part, during solve()
};

}  // namespace inertia::detail
