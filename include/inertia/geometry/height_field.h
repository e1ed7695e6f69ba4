// Height fields: terrain as heights on a regular grid. Static only (no mass).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "inertia/core/types.h"

namespace inertia {

/// Terrain: a regular grid of heights in the local frame. Axes: y is up; row i lies at
/// z = i * spacing and column j at x = j * spacing, so sample (i, j) is the point
/// (j * spacing, heights[i][j], i * spacing) and the grid spans [0, (cols-1) spacing] in x and
/// [0, (rows-1) spacing] in z from the local origin (a corner, not the centre).
/// Solid is below the surface. Each cell (i, j) is split along the diagonal from (i, j) to
/// (i + 1, j + 1) into two triangles, both with upward-facing normals.
class HeightField {
 public:
  /// Builds a field from rows of heights (m) and the grid spacing (m). Throws InvalidArgument
  /// for fewer than 2 rows or columns, rows of different lengths, non-finite heights, or a
  /// non-positive or non-finite spacing.
  HeightField(const std::vector<std::vector<Real>>& rows, Real spacing);

  std::size_t rows() const { return rows_; }
  std::size_t cols() const { return cols_; }
  /// Grid spacing (m) in x and z.
  Real spacing() const { return spacing_; }
  /// Height of sample (row, col) (m).
  Real height(std::size_t row, std::size_t col) const { return heights_[row * cols_ + col]; }
  /// The local position of sample (row, col) (m).
  Vec3 point(std::size_t row, std::size_t col) const {
    return {Real(col) * spacing_, height(row, col), Real(row) * spacing_};
  }
  Real minHeight() const { return minHeight_; }
  Real maxHeight() const { return maxHeight_; }
  /// The two triangles of cell (row, col), 0 <= row < rows-1, 0 <= col < cols-1, each
  /// counter-clockwise seen from above.
  std::array<std::array<Vec3, 3>, 2> cellTriangles(std::size_t row, std::size_t col) const;

 private:
  std::vector<Real> heights_;  // row-major
  std::size_t rows_ = 0, cols_ = 0;
  Real spacing_ = 1;
  Real minHeight_ = 0, maxHeight_ = 0;
};

}  // namespace inertia
