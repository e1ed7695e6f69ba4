#include "deformable/filtered_ldlt.h"

#include <Eigen/OrderingMethods>
#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/union_find.h"

namespace inertia::detail {

namespace {

using Triplet = Eigen::Triplet<double, int>;

// The order of a part's vertices (local indices): approximate minimum degree on the graph of
// its springs.
std::vector<std::uint32_t> minimumDegreeOrder(std::span<const Spring> all,
                                              std::span<const std::uint32_t> springs,
                                              std::size_t vertices,
                                              std::span<const std::uint32_t> local) {
  std::vector<Triplet> edges;
  edges.reserve(vertices + 2 * springs.size());
  for (std::size_t i = 0; i < vertices; ++i) edges.emplace_back(int(i), int(i), 1.0);
  for (const std::uint32_t k : springs) {
    const int a = int(local[all[k].a]), b = int(local[all[k].b]);
    edges.emplace_back(a, b, 1.0), edges.emplace_back(b, a, 1.0);
  }
  const Eigen::Index size = Eigen::Index(vertices);
  Eigen::SparseMatrix<double> graph(size, size);
  graph.setFromTriplets(edges.begin(), edges.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
  Eigen::AMDOrdering<int>()(graph, inverse);  // inverse.indices()[p]: the p-th vertex
  return {inverse.indices().begin(), inverse.indices().end()};
}

// The vertex pairs a part's springs join, as {column, row} blocks of the upper triangle in the
// elimination order `order` (local indices), sorted and each once.
std::vector<std::array<std::uint32_t, 2>> upperBlocks(std::span<const Spring> all,
                                                      std::span<const std::uint32_t> springs,
                                                      std::span<const std::uint32_t> local,
                                                      std::span<const std::uint32_t> order) {
  std::vector<std::uint32_t> position(order.size());
  for (std::size_t p = 0; p < order.size(); ++p) position[order[p]] = std::uint32_t(p);
  std::vector<std::array<std::uint32_t, 2>> blocks;
  blocks.reserve(springs.size());
  for (const std::uint32_t k : springs) {
    const std::uint32_t a = position[local[all[k].a]], b = position[local[all[k].b]];
    if (a != b) blocks.push_back({std::max(a, b), std::min(a, b)});
  }
  std::sort(blocks.begin(), blocks.end());
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
  return blocks;
}

// The blocks strictly below the diagonal of the factor of a part's vertex graph, counted over
// its elimination tree by Liu's row subtrees (as Eigen's symbolic analysis counts them) without
// building the factor; counting stops once past `budget`.
std::int64_t factorBlocks(std::span<const std::array<std::uint32_t, 2>> upper, std::size_t vertices,
                          std::int64_t budget) {
  constexpr std::uint32_t kNone = ~0u;
  std::vector<std::uint32_t> parent(vertices, kNone), flag(vertices, kNone);
  std::int64_t count = 0;
  std::size_t e = 0;
  for (std::uint32_t k = 0; k < vertices; ++k) {
    flag[k] = k;
    for (; e < upper.size() && upper[e][0] == k; ++e)
      for (std::uint32_t i = upper[e][1]; flag[i] != k; i = parent[i]) {
        if (parent[i] == kNone) parent[i] = k;
        flag[i] = k;
        if (++count > budget) return count;
      }
  }
  return count;
}

}  // namespace

void FilteredLdlt::connect(std::span<const Spring> all, std::span<const std::uint32_t> springs,
                           std::span<const std::uint32_t> vertices,
                           std::span<const std::uint32_t> local,
                           std::span<const std::uint32_t> order) {
  // position[local index] = block of A.
  std::vector<std::uint32_t> position(vertices.size());
  ordered_.resize(vertices.size());
  for (std::size_t p = 0; p < order.size(); ++p)
    position[order[p]] = std::uint32_t(p), ordered_[p] = vertices[order[p]];

  // One block per pair of vertices some spring joins, stored above the diagonal.
  springs_.assign(springs.begin(), springs.end());
  springEnds_.resize(springs.size());
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> pairs;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    std::uint32_t r = position[local[all[springs[s]].a]], c = position[local[all[springs[s]].b]];
    springEnds_[s] = {r, c};
    if (r == c) continue;
    if (r > c) std::swap(r, c);
    pairs.emplace_back(r, c, std::uint32_t(s));
  }
  std::sort(pairs.begin(), pairs.end());
  springBlock_.assign(springs.size(), -1);
  blockEnds_.clear();
  for (const auto& [r, c, s] : pairs) {
    if (blockEnds_.empty() || blockEnds_.back() != std::array{r, c}) blockEnds_.push_back({r, c});
    springBlock_[s] = std::int32_t(blockEnds_.size() - 1);
  }

  std::vector<Triplet> entries;
  entries.reserve(6 * vertices.size() + 9 * blockEnds_.size());
  for (std::size_t p = 0; p < vertices.size(); ++p)
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) entries.emplace_back(int(3 * p) + r, int(3 * p) + c, 0.0);
  for (const auto& [r, c] : blockEnds_)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) entries.emplace_back(int(3 * r) + i, int(3 * c) + j, 0.0);
  const Eigen::Index n3 = Eigen::Index(3 * vertices.size());
  upper_.resize(n3, n3);
  upper_.setFromTriplets(entries.begin(), entries.end());  // rows sorted in each column
  upper_.makeCompressed();
  values_ = upper_.valuePtr();

  const int* rows = upper_.innerIndexPtr();
  const int* starts = upper_.outerIndexPtr();
  blockColumns_.resize(blockEnds_.size());
  for (std::size_t k = 0; k < blockEnds_.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const int column = int(3 * blockEnds_[k][1]) + c, row = int(3 * blockEnds_[k][0]);
      blockColumns_[k][std::size_t(c)] =
          int(std::lower_bound(rows + starts[column], rows + starts[column + 1], row) - rows);
    }
  diagonalEnds_.resize(vertices.size());
  for (std::size_t p = 0; p < vertices.size(); ++p)
    for (int c = 0; c < 3; ++c) diagonalEnds_[p][std::size_t(c)] = starts[3 * p + c + 1] - 1;
  ldlt_.analyzePattern(upper_);
}

// H = diag(diagonal) + the springs' blocks, unfiltered.
void FilteredLdlt::assemble(const Eigen::VectorXd& diagonal,
                            std::span<const SymmetricBlock> blocks) {
  std::fill(values_, values_ + upper_.nonZeros(), 0.0);
  for (std::size_t p = 0; p < ordered_.size(); ++p)
    for (int c = 0; c < 3; ++c)
      diagonalEntry(p, c, c) = diagonal[3 * Eigen::Index(ordered_[p]) + c];
  // Block entries in the order xx, yy, zz, xy, xz, yz.
  constexpr int kRow[6] = {0, 1, 2, 0, 0, 1}, kCol[6] = {0, 1, 2, 1, 2, 2};
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    if (springBlock_[s] < 0) continue;
    const SymmetricBlock& b = blocks[springs_[s]];
    for (const std::uint32_t p : springEnds_[s])
      for (std::size_t e = 0; e < 6; ++e) diagonalEntry(p, kRow[e], kCol[e]) += b[e];
    const std::size_t block = std::size_t(springBlock_[s]);
    for (std::size_t e = 0; e < 6; ++e) {
      entry(block, kRow[e], kCol[e]) -= b[e];
      if (kRow[e] != kCol[e]) entry(block, kCol[e], kRow[e]) -= b[e];
    }
  }
}

// A's blocks: S_r M S_c off the diagonal, S M S + I - S on it.
void FilteredLdlt::filter(ProjectionOf projection, const void* context) {
  for (std::size_t k = 0; k < blockEnds_.size(); ++k) {
    const Eigen::Matrix3d* sr = projection(context, ordered_[blockEnds_[k][0]]);
    const Eigen::Matrix3d* sc = projection(context, ordered_[blockEnds_[k][1]]);
    if (!sr && !sc) continue;
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m(r, c) = entry(k, r, c);
    if (sr) m = *sr * m;
    if (sc) m = m * *sc;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) entry(k, r, c) = m(r, c);
  }
  for (std::size_t p = 0; p < ordered_.size(); ++p) {
    const Eigen::Matrix3d* s = projection(context, ordered_[p]);
    if (!s) continue;
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) m(r, c) = m(c, r) = diagonalEntry(p, r, c);
    m = *s * m * *s + (Eigen::Matrix3d::Identity() - *s);
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) diagonalEntry(p, r, c) = 0.5 * (m(r, c) + m(c, r));
  }
}

bool FilteredLdlt::factor(const Eigen::VectorXd& diagonal, std::span<const SymmetricBlock> blocks,
                          ProjectionOf projection, const void* context) {
  assemble(diagonal, blocks);
  filter(projection, context);
  ldlt_.factorize(upper_);
  if (ldlt_.info() != Eigen::Success) return false;
  inverseD_ = ldlt_.vectorD().cwiseInverse();
  return inverseD_.allFinite() && (inverseD_.array() > 0).all();
}

void FilteredLdlt::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  permuted_.resize(3 * Eigen::Index(ordered_.size()));
  for (std::size_t p = 0; p < ordered_.size(); ++p)
    permuted_.segment<3>(3 * Eigen::Index(p)) = b.segment<3>(3 * Eigen::Index(ordered_[p]));
  ldlt_.matrixL().solveInPlace(permuted_);
  permuted_.array() *= inverseD_.array();
  ldlt_.matrixU().solveInPlace(permuted_);
  for (std::size_t p = 0; p < ordered_.size(); ++p)
    x.segment<3>(3 * Eigen::Index(ordered_[p])) = permuted_.segment<3>(3 * Eigen::Index(p));
}

// Components by the one union-find, in the order of their first (smallest) vertex, gathered
// into parts of at least kPartVertices vertices.
bool FilteredDirectSolve::connect(std::span<const Spring> springs, std::size_t vertices,
                                  double maxFill) {
  const bool same = vertices == vertices_ && maxFill == maxFill_ &&
                    springs.size() == ends_.size() &&
                    std::equal(springs.begin(), springs.end(), ends_.begin(),
                               [](const Spring& s, const std::array<std::uint32_t, 2>& e) {
                                 return s.a == e[0] && s.b == e[1];
                               });
  if (same) return worthIt_;
  vertices_ = vertices;
  maxFill_ = maxFill;
  ends_.resize(springs.size());
  for (std::size_t k = 0; k < springs.size(); ++k) ends_[k] = {springs[k].a, springs[k].b};
  UnionFind components;
  components.reset(vertices);
  for (const Spring& s : springs) components.unite(s.a, s.b);
  // part[root] for each component's root, then each vertex's part.
  std::vector<std::uint32_t> part(vertices), local(vertices);
  std::vector<std::vector<std::uint32_t>> partVertices, partSprings;
  for (std::uint32_t i = 0; i < vertices; ++i) {
    const std::uint32_t root = components.find(i);
    if (root == i) {  // a new component: in the last part, or a new one if that is full
      if (partVertices.empty() || partVertices.back().size() >= kPartVertices)
        partVertices.emplace_back();
      part[i] = std::uint32_t(partVertices.size() - 1);
    } else {
      part[i] = part[root];
    }
    local[i] = std::uint32_t(partVertices[part[i]].size());
    partVertices[part[i]].push_back(i);
  }
  partSprings.resize(partVertices.size());
  for (std::uint32_t k = 0; k < springs.size(); ++k) partSprings[part[springs[k].a]].push_back(k);
  std::vector<std::vector<std::uint32_t>> orders(partVertices.size());
  for (std::size_t p = 0; p < partVertices.size(); ++p)
    orders[p] = minimumDegreeOrder(springs, partSprings[p], partVertices[p].size(), local);
  parts_.clear();
  worthIt_ = fillWithin(springs, partVertices, partSprings, local, orders, maxFill);
  if (worthIt_)
    for (std::size_t p = 0; p < partVertices.size(); ++p) {
      parts_.push_back(std::make_unique<FilteredLdlt>());
      parts_.back()->connect(springs, partSprings[p], partVertices[p], local, orders[p]);
    }
  factored_.resize(parts_.size());
  return worthIt_;
}

// Whether the parts' factors hold at most maxFill times the non-zeros of their matrices' upper
// triangles, counted per 3 x 3 block: 6 per vertex and 9 per joined pair in A, 3 per vertex
// and 9 per block below the diagonal in L.
bool FilteredDirectSolve::fillWithin(std::span<const Spring> springs,
                                     const std::vector<std::vector<std::uint32_t>>& partVertices,
                                     const std::vector<std::vector<std::uint32_t>>& partSprings,
                                     std::span<const std::uint32_t> local,
                                     const std::vector<std::vector<std::uint32_t>>& orders,
                                     double maxFill) {
  if (std::isinf(maxFill)) return true;
  std::vector<std::vector<std::array<std::uint32_t, 2>>> upper(partVertices.size());
  double matrix = 0;
  for (std::size_t p = 0; p < partVertices.size(); ++p) {
    upper[p] = upperBlocks(springs, partSprings[p], local, orders[p]);
    matrix += 6.0 * double(partVertices[p].size()) + 9.0 * double(upper[p].size());
  }
  double budget = maxFill * matrix;
  for (std::size_t p = 0; p < partVertices.size(); ++p) {
    budget -= 3.0 * double(partVertices[p].size());
    if (budget < 0) return false;
    const auto blocks = std::int64_t(budget / 9);
    const std::int64_t used = factorBlocks(upper[p], partVertices[p].size(), blocks);
    if (used > blocks) return false;
    budget -= 9.0 * double(used);
  }
  return true;
}

bool FilteredDirectSolve::solve(const Eigen::VectorXd& diagonal,
                                std::span<const SymmetricBlock> blocks, ProjectionOf projection,
                                const void* context, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                StepWorkers* workers) {
  x.resize(b.size());
  const auto solvePart = [&](std::size_t p) {
    factored_[p] = parts_[p]->factor(diagonal, blocks, projection, context);
    if (factored_[p]) parts_[p]->solve(b, x);
  };
  if (workers)
    workers->parallelFor(parts_.size(), 1, [&](std::size_t first, std::size_t last) {
      for (std::size_t p = first; p < last; ++p) solvePart(p);
    });
  else
    for (std::size_t p = 0; p < parts_.size(); ++p) solvePart(p);
  return std::all_of(factored_.begin(), factored_.end(), [](std::uint8_t f) { return f != 0; });
}

}  // namespace inertia::detail
