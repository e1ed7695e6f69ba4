// Internal: disjoint sets, the one union-find of the library (the dynamics' islands, the
// deformables' impact zones).
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace inertia::detail {

/// Disjoint sets over nodes 0..n-1 (path halving; the smaller root wins a union, so the
/// roots do not depend on the order of the unions' arguments).
class UnionFind {
 public:
  void reset(std::size_t n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), 0u);
  }
  std::uint32_t find(std::uint32_t i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];
      i = parent_[i];
    }
    return i;
  }
  /// Joins the sets of a and b; false when they were one already.
  bool unite(std::uint32_t a, std::uint32_t b) {
    const std::uint32_t ra = find(a), rb = find(b);
    if (ra == rb) return false;
    parent_[std::max(ra, rb)] = std::min(ra, rb);
    return true;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

}  // namespace inertia::detail
