// Internal: the inner loops of the particle step (symplectic Euler, ageing, the near-obstacle
// filter, particles settling on the ground plane), each in a scalar, an SSE2 and an AVX2
// version. The version is chosen once at run time from what the processor supports, so the
// library still runs on any x86-64 (and elsewhere through the scalar one). All versions compute
// the same bits: the same lane-wise IEEE operations (add, mul, div, sqrt, min, max, compares)
// on the same values in the same order, no fused multiply-add (-ffp-contract=off, and the
// AVX2 functions are compiled for "avx2" only, which does not enable FMA).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/simd.h"
#include "inertia/core/types.h"

namespace inertia::detail {

/// The set the particle kernels can use: cpuSimdLevel() for float, at most AVX2, scalar for
/// double.
SimdLevel bestParticleSimd();
/// The set the step uses: bestParticleSimd() unless a test forced another.
SimdLevel particleSimd();
/// Forces the set the next steps use, clamped to bestParticleSimd(); returns the previous one.
/// For tests comparing the versions bit for bit; not thread-safe against a running step.
SimdLevel setParticleSimd(SimdLevel isa);

/// One obstacle as the near test sees it: a plane (normal n, offset, skin included) or a world
/// box (inflated by the skin).
struct ParticleNearTest {
  bool plane;
  Real n0, n1, n2, offset;
  Real lo0, lo1, lo2, hi0, hi1, hi2;
};

/// A field the fused kernel evaluates itself: gravity (acc += g) or linear drag
/// (acc += (-k / m) v), neither with a region.
struct ParticleFieldTerm {
  bool gravity;
  Real g0, g1, g2;
  Real negK;
};
constexpr std::size_t kMaxParticleTerms = 8;
/// Particles per batch at most (the scalar set's buffers are this long).
constexpr std::size_t kMaxParticleBatch = 2048;
/// Obstacles the fused kernel filters against (with more, the caller culls them per batch).
constexpr std::size_t kMaxParticleStepTests = 8;

/// One batch of the fused symplectic Euler step: accelerations (from `terms`, summed in order
/// from zero, or read from `acc`), v += h a, x += h v keeping the start positions, age += h
/// with the dead flags, and, when `tests` is set, the list of particles whose swept box may
/// touch an obstacle.
struct ParticleStepBatch {
  std::size_t count = 0;  // <= kMaxParticleBatch
  Real h = 0;
  Real* x = nullptr;  // 3 Reals per particle
  Real* v = nullptr;  // 3 Reals per particle
  const Real* m = nullptr;
  Real* age = nullptr;
  const Real* life = nullptr;
  const Real* radius = nullptr;
  const Real* acc = nullptr;  // 3 Reals per particle, or null: from terms
  const ParticleFieldTerm* terms = nullptr;
  std::size_t termCount = 0;                // <= kMaxParticleTerms
  Real* start = nullptr;                    // out: start positions, 3 Reals per particle
  std::uint8_t* dead = nullptr;             // out: 1 when age >= lifetime
  const ParticleNearTest* tests = nullptr;  // null: no near list
  std::size_t testCount = 0;                // <= kMaxParticleStepTests
  std::uint16_t* list = nullptr;            // out: batch indices of the particles near an obstacle
  // The next batch's arrays (x, v, m, age, life, radius) and size, prefetched while this one
  // computes; nextCount 0 for none.
  const Real* next[6] = {};
  std::size_t nextCount = 0;
};
struct ParticleStepCounts {
  std::size_t deaths = 0, listed = 0;
};
ParticleStepCounts stepParticleBatch(SimdLevel isa, const ParticleStepBatch& batch);

/// Listed particles of a batch against the system's only plane, when they meet nothing else:
/// ParticleSystem::collidePlaneOnly for particles resting on the plane, landing on it or about
/// to, several at a time. A particle whose swept segment crosses the plane twice in the step,
/// whose path comes near another obstacle's bounds, or that is left over at the end goes to
/// `rest` for the scalar paths. Needs start positions (swept tests).
struct ParticlePlaneSettle {
  Real n0, n1, n2, offset;  // the plane: n . x <= offset is inside
  Real restitution, friction, threshold, skin;
  const Real* boxes = nullptr;  // other obstacles' bounds: lower xyz, upper xyz per obstacle
  std::size_t boxCount = 0;
  Real* x = nullptr;  // the batch's positions (end of the step), 3 Reals each
  Real* v = nullptr;
  const Real* start = nullptr;  // the batch's start positions, 3 Reals each
  const Real* radius = nullptr;
  const std::uint16_t* list = nullptr;
  std::size_t listed = 0;
  std::uint16_t* rest = nullptr;  // out; may be `list` itself
};
/// Returns the number of particles written to `rest` (in increasing order). The scalar set
/// settles none: all go to `rest`.
std::size_t settleParticlesOnPlane(SimdLevel isa, const ParticlePlaneSettle& settle);

}  // namespace inertia::detail
