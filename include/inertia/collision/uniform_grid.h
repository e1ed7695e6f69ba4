// A uniform grid over points, stored as a spatial hash (seeds 003: uniform grids for many
// objects of one size; Teschner et al. 2003, "Optimized spatial hashing"): the broad phase of
// particles colliding with each other.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "inertia/core/types.h"

namespace inertia {

/// Points binned into cubic cells of one size, hashed into a table of 2^k buckets and sorted by
/// bucket (a counting sort: linear time, no allocation once warmed up, and the same order for
/// the same input). A query visits the 27 cells around a point: every point within one cell
/// size of it is visited exactly once (plus some farther ones that share a bucket).
class UniformGrid {
 public:
  /// Bins `positions` (3 Reals per point, m) into cells of `cellSize` (m, > 0 and finite).
  void build(std::span<const Real> positions, Real cellSize);

  /// Calls f(index) for the points in the 27 cells around `p`: a superset of the points within
  /// cellSize of p, each index once.
  template <class F>
  void forEachNear(const Vec3& p, F&& f) const {
    const std::array<std::int64_t, 3> c = cellOf(p);
    std::uint32_t seen[27];
    int seenCount = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::uint32_t b = bucket({c[0] + dx, c[1] + dy, c[2] + dz});
          bool repeat = false;  // two cells may share a bucket: visit it once
          for (int s = 0; s < seenCount; ++s) repeat |= seen[s] == b;
          if (repeat) continue;
          seen[seenCount++] = b;
          for (std::uint32_t k = start_[b]; k < start_[b + 1]; ++k) f(order_[k]);
        }
  }

  Real cellSize() const { return cellSize_; }
  std::size_t bucketCount() const { return start_.empty() ? 0 : start_.size() - 1; }

 private:
  std::array<std::int64_t, 3> cellOf(const Vec3& p) const {
    return {std::int64_t(std::floor(p.x() * inverse_)), std::int64_t(std::floor(p.y() * inverse_)),
            std::int64_t(std::floor(p.z() * inverse_))};
  }
  std::uint32_t bucket(const std::array<std::int64_t, 3>& c) const {
    // Teschner's hash of the cell coordinates with three large primes.
    const std::uint64_t h = (std::uint64_t(c[0]) * 73856093u) ^ (std::uint64_t(c[1]) * 19349663u) ^
                            (std::uint64_t(c[2]) * 83492791u);
    return std::uint32_t(h & mask_);
  }

  Real cellSize_ = 1, inverse_ = 1;
  std::uint64_t mask_ = 0;
  std::vector<std::uint32_t> start_;   // bucket b holds order_[start_[b] .. start_[b+1])
  std::vector<std::uint32_t> order_;   // point indices sorted by bucket
  std::vector<std::uint32_t> bucketOf_;  // scratch of build()
  std::vector<std::uint32_t> cursor_;    // scratch of build()
};

}  // namespace inertia
