#include "inertia/collision/uniform_grid.h"

#include <algorithm>
#include <bit>

#include "inertia/core/error.h"

namespace inertia {

void UniformGrid::build(std::span<const Real> positions, Real cellSize) {
  require(std::isfinite(cellSize) && cellSize > 0, "UniformGrid::build: cellSize must be finite and > 0");
  require(positions.size() % 3 == 0, "UniformGrid::build: positions must hold 3 Reals per point");
  const std::size_t n = positions.size() / 3;
  cellSize_ = cellSize;
  inverse_ = 1 / cellSize;
  // About two buckets per point keeps chains short.
  const std::uint64_t buckets = std::bit_ceil(std::max<std::uint64_t>(16, 2 * n));
  mask_ = buckets - 1;
  start_.assign(buckets + 1, 0);
  bucketOf_.resize(n);
  order_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = bucket(cellOf(Eigen::Map<const Vec3>(&positions[3 * i])));
    bucketOf_[i] = b;
    ++start_[b + 1];
  }
  for (std::uint64_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  // Counting sort, stable: within a bucket, points keep their index order.
  cursor_.assign(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) order_[cursor_[bucketOf_[i]]++] = std::uint32_t(i);
}

}  // namespace inertia
