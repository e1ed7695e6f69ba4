// Random vectors drawn in a fixed order. `Vec3(u(rng), u(rng), u(rng))` leaves the order of the
// three draws to the compiler (function arguments are unsequenced): GCC draws z first, clang x,
// so the two tested different cases. These helpers draw in GCC's order, last coordinate first:
// every compiler tests the cases the tests were written and checked with.
#pragma once

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

}  // namespace inertia::test
