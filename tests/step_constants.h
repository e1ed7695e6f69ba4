// The step the dynamics and world tests' scenes take. Shared, not redefined per file: the test
// files of a layer compile together in unity batches.
#pragma once

#include "inertia/core/types.h"

namespace inertia::test {

/// The step, 60 Hz (s).
inline constexpr Real kDt = Real(1.0 / 60);
/// Substeps per step where a test sets them (the soft step's default).
inline constexpr int kSubsteps = 4;
/// Gravity's magnitude (m/s^2).
inline constexpr Real kG = Real(9.81);

}  // namespace inertia::test
