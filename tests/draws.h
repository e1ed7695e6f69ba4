// Random vectors and rotations drawn in a fixed order, shared by the collision and geometry
// tests. `Vec3(u(rng), u(rng), u(rng))` leaves the order of the three draws to the compiler
// (function arguments are unsequenced): GCC draws z first, clang x, so the two tested
// different cases. These helpers draw in GCC's order, last coordinate first: every compiler
// tests the cases the tests were written and checked with.
#pragma once

#include <random>

#include "inertia/core/types.h"

namespace inertia::test {

/// V(x, y, z) from three calls of `draw`, z's first.
template <class V, class Draw>
V draw3(Draw&& draw) {
  const auto z = draw();
  const auto y = draw();
  const auto x = draw();
  return V(x, y, z);
}

/// V(w, x, y, z) (a quaternion's coefficients) from four calls of `draw`, z's first.
template <class V, class Draw>
V draw4(Draw&& draw) {
  const auto z = draw();
  const auto y = draw();
  const auto x = draw();
  const auto w = draw();
  return V(w, x, y, z);
}

/// A rotation drawn in float, kept as drawn for a case reproduced bit for bit from its printed
/// floats; a unit quaternion to float's precision only, so double normalises it again.
inline Quat unitAsDrawn(const Quat& drawn) {
  return sizeof(Real) == 4 ? drawn : Quat(drawn.normalized());
}

/// A uniformly random rotation (a normalised Gaussian quaternion).
inline Quat randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return draw4<Quat>([&] { return Real(n(rng)); }).normalized();
}

/// A vector with coordinates uniform in [lo, hi).
inline Vec3 randomVec(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  return draw3<Vec3>([&] { return Real(u(rng)); });
}

}  // namespace inertia::test
