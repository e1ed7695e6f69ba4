// Machine epsilons, the units of the tests' round-off bounds. Shared, not redefined per file:
// the test files of a layer compile together in unity batches.
#pragma once

#include <limits>

#include "inertia/core/types.h"

namespace inertia::test {

/// Machine epsilon of Real: float-build tolerances scale with it.
inline constexpr Real kRealEps = std::numeric_limits<Real>::epsilon();
/// Machine epsilon of double, for oracles computed in double whatever Real is.
inline constexpr double kDoubleEps = std::numeric_limits<double>::epsilon();

}  // namespace inertia::test
