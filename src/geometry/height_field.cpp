#include "inertia/geometry/height_field.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "inertia/core/error.h"

namespace inertia {

HeightField::HeightField(const std::vector<std::vector<Real>>& rows, Real spacing)
    : rows_(rows.size()), spacing_(spacing) {
  require(std::isfinite(spacing) && spacing > 0,
          "HeightField: spacing must be positive and finite, got " + std::to_string(spacing));
  require(rows.size() >= 2, "HeightField: needs at least 2 rows of heights");
  cols_ = rows[0].size();
  require(cols_ >= 2, "HeightField: needs at least 2 heights per row");
  heights_.reserve(rows_ * cols_);
  for (std::size_t i = 0; i < rows_; ++i) {
    require(rows[i].size() == cols_, "HeightField: row " + std::to_string(i) + " has " +
                                         std::to_string(rows[i].size()) + " heights, row 0 has " +
                                         std::to_string(cols_));
    for (std::size_t j = 0; j < cols_; ++j) {
      require(std::isfinite(rows[i][j]), "HeightField: height [" + std::to_string(i) + "][" +
                                             std::to_string(j) + "] is not finite");
      heights_.push_back(rows[i][j]);
    }
  }
  const auto [lo, hi] = std::minmax_element(heights_.begin(), heights_.end());
  minHeight_ = *lo;
  maxHeight_ = *hi;
}

std::array<std::array<Vec3, 3>, 2> HeightField::cellTriangles(std::size_t row,
                                                              std::size_t col) const {
  const Vec3 a = point(row, col), b = point(row, col + 1);
  const Vec3 c = point(row + 1, col + 1), d = point(row + 1, col);
  // Split along the diagonal a-c; (a, c, b) and (a, d, c) wind counter-clockwise seen from +y.
  return {{{a, c, b}, {a, d, c}}};
}

}  // namespace inertia
