// The random convex shape of the convex and world targets: a sphere, capsule, box, cylinder or
// hull. Each target draws lengths and hull points its own way (the convex target lets a length
// of 0 through to test the API's refusal; the world target clamps lengths to what a body may
// be), so those are arguments; the bytes are read in the same order either way, which keeps
// the committed corpora and findings meaning what they did.
#pragma once

#include <vector>

#include "fuzz_input.h"
#include "inertia/geometry/geometry.h"

namespace inertia::fuzz {

/// `length()` gives each size (m); a hull has `hullCount()` points from in.vec(hullScale).
template <class Length, class Count>
Shape randomShape(Input& in, Length length, Count hullCount, Real hullScale) {
  switch (in.pick(5)) {
    case 0:
      return Sphere{length()};
    case 1:
      return Capsule{length(), length()};
    case 2:
      return Box{Vec3{length(), length(), length()}};  // braces: read in order
    case 3:
      return Cylinder{length(), length()};
    default: {
      std::vector<Vec3> pts;
      const unsigned n = hullCount();
      for (unsigned i = 0; i < n; ++i) pts.push_back(in.vec(hullScale));
      return Shape(ConvexHull(pts));
    }
  }
}

}  // namespace inertia::fuzz
