// Shared by the particle tests: an immortal particle at a given place, speed and size.
#pragma once

#include <limits>

#include "inertia/particles/pool.h"

namespace inertia::test {

/// A particle that never dies, at x with velocity v and the given radius (default mass).
inline ParticlePool::Spawn particle(const Vec3& x, const Vec3& v, Real radius = 0) {
  ParticlePool::Spawn s;
  s.position = x;
  s.velocity = v;
  s.radius = radius;
  s.lifetime = std::numeric_limits<Real>::infinity();
  return s;
}

}  // namespace inertia::test
