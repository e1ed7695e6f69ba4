#include "fast_path.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
// The vector sets need x86-64 and float lanes; elsewhere, and for double, only the scalar one.
#if (defined(__x86_64__) || defined(__i386__)) && defined(__SSE2__) && !defined(INERTIA_DOUBLE)
#define INERTIA_PARTICLES_VECTOR 1
#include <immintrin.h>
#else
#define INERTIA_PARTICLES_VECTOR 0
#endif

namespace inertia::detail {

namespace {

#if INERTIA_PARTICLES_VECTOR
// The 4 bits of a comparison mask as 4 bytes of 0 or 1 (little endian), for the dead flags.
constexpr std::uint32_t kMaskBytes[16] = {
    0x00000000, 0x00000001, 0x00000100, 0x00000101, 0x00010000, 0x00010001, 0x00010100, 0x00010101,
    0x01000000, 0x01000001, 0x01000100, 0x01000101, 0x01010000, 0x01010001, 0x01010100, 0x01010101};
// The number of bits set in 4, as a table of nibbles.
inline unsigned popcount4(unsigned m) { return unsigned((0x4332322132212110ull >> (4 * m)) & 0xF); }
#endif

namespace scalar {
#define INERTIA_TARGET
using V = Real;
using M = bool;
constexpr std::size_t W = 1;
inline V load(const Real* p) { return *p; }
inline void store(Real* p, V v) { *p = v; }
inline V set1(Real x) { return x; }
inline V zero() { return Real(0); }
inline V add(V a, V b) { return a + b; }
inline V sub(V a, V b) { return a - b; }
inline V mul(V a, V b) { return a * b; }
inline V div(V a, V b) { return a / b; }
inline V sqrt(V a) { return std::sqrt(a); }
inline V neg(V a) { return -a; }
// As minps and maxps: the second operand when the comparison fails (NaN, or +0 against -0).
inline V min(V a, V b) { return a < b ? a : b; }
inline V max(V a, V b) { return a > b ? a : b; }
inline M eq(V a, V b) { return a == b; }
inline M lt(V a, V b) { return a < b; }
inline M le(V a, V b) { return a <= b; }
inline M ge(V a, V b) { return a >= b; }
inline M gt(V a, V b) { return a > b; }
inline M unordered(V a, V b) { return std::isnan(a) || std::isnan(b); }
inline M none() { return false; }
inline M and_(M a, M b) { return a && b; }
inline M or_(M a, M b) { return a || b; }
inline M andnot(M a, M b) { return !a && b; }
inline V select(M m, V a, V b) { return m ? a : b; }
inline unsigned bits(M m) { return m ? 1u : 0u; }
inline std::size_t popcount(unsigned m) { return m; }
inline void storeFlags(std::uint8_t* d, unsigned m) { *d = std::uint8_t(m); }
inline void transpose3(V p0, V p1, V p2, V& x, V& y, V& z) { x = p0, y = p1, z = p2; }
inline void spread3(V s, V& o0, V& o1, V& o2) { o0 = o1 = o2 = s; }
inline void pattern3(Real g0, Real g1, Real g2, V& o0, V& o1, V& o2) { o0 = g0, o1 = g1, o2 = g2; }
inline void prefetch(const Real*) {}
#include "fast_path.inc"
#undef INERTIA_TARGET

// The whole scalar set as plain loops over the batch, one per stage, as the loops these
// kernels replaced were, so that the path of double and of other processors keeps their speed
// (the benchmark in double, one thread: 13.2-13.7 ms a step against 12.3-13.4 ms before, on a
// loaded machine); the tests forcing the scalar set take it too. stepRange() finishes the
// vector sets' batches. The same operations on the same values as stepRange().
void stepLoops(const ParticleStepBatch& a, ParticleStepCounts& counts) {
  const std::size_t n = a.count;
  const Real h = a.h;
  // The batch's arrays never overlap: said, so that the compiler vectorises the loops.
  Real* __restrict x = a.x;
  Real* __restrict v = a.v;
  Real* __restrict start = a.start;
  Real* __restrict ages = a.age;
  std::uint8_t* __restrict flags = a.dead;
  const Real* __restrict m = a.m;
  const Real* __restrict life = a.life;
  Real buffer[3 * kMaxParticleBatch];
  const Real* __restrict acc = a.acc;
  if (!acc) {
    std::fill_n(buffer, 3 * n, Real(0));
    for (std::size_t t = 0; t < a.termCount; ++t) {
      const ParticleFieldTerm& term = a.terms[t];
      if (term.gravity) {
        const Real g0 = term.g0, g1 = term.g1, g2 = term.g2;
        for (std::size_t i = 0; i < n; ++i) {
          buffer[3 * i] += g0;
          buffer[3 * i + 1] += g1;
          buffer[3 * i + 2] += g2;
        }
      } else {
        // max((-k) / m, -1 / h), as stepRange's (a drag's rate is at most 1 / h)
        const Real negK = term.negK, negMaxRate = -(1 / h);
        for (std::size_t i = 0; i < n; ++i) {
          const Real s = std::max(negK / m[i], negMaxRate);
          buffer[3 * i] += s * v[3 * i];
          buffer[3 * i + 1] += s * v[3 * i + 1];
          buffer[3 * i + 2] += s * v[3 * i + 2];
        }
      }
    }
    acc = buffer;
  }
  for (std::size_t j = 0; j < 3 * n; ++j) {
    const Real vj = v[j] + h * acc[j];
    v[j] = vj;
    start[j] = x[j];
    x[j] = x[j] + h * vj;
  }
  std::size_t deaths = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Real age = ages[i] + h;
    ages[i] = age;
    const bool dead = age >= life[i];
    flags[i] = dead;
    deaths += dead;
  }
  counts.deaths += deaths;
  if (!a.tests) return;
  // Test by test over the batch (vectorised), then the list.
  std::uint8_t touch[kMaxParticleBatch];
  std::fill_n(touch, n, std::uint8_t(0));
  const Real* __restrict radius = a.radius;
  for (std::size_t k = 0; k < std::min(a.testCount, kMaxParticleStepTests); ++k) {
    const ParticleNearTest t = a.tests[k];
    if (t.plane) {
      for (std::size_t i = 0; i < n; ++i) {
        const Real da = t.n0 * start[3 * i] + t.n1 * start[3 * i + 1] + t.n2 * start[3 * i + 2];
        const Real db = t.n0 * x[3 * i] + t.n1 * x[3 * i + 1] + t.n2 * x[3 * i + 2];
        touch[i] |= min(da, db) < t.offset + radius[i];
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        const Real r = radius[i];
        // Bitwise on ints, not && on bools: no branches, so the loop vectorises.
        const int in = int(min(start[3 * i], x[3 * i]) - r <= t.hi0) &
                       int(max(start[3 * i], x[3 * i]) + r >= t.lo0) &
                       int(min(start[3 * i + 1], x[3 * i + 1]) - r <= t.hi1) &
                       int(max(start[3 * i + 1], x[3 * i + 1]) + r >= t.lo1) &
                       int(min(start[3 * i + 2], x[3 * i + 2]) - r <= t.hi2) &
                       int(max(start[3 * i + 2], x[3 * i + 2]) + r >= t.lo2);
        touch[i] |= in;
      }
    }
  }
  std::size_t listed = counts.listed;
  for (std::size_t i = 0; i < n; ++i)
    if (touch[i]) a.list[listed++] = std::uint16_t(i);
  counts.listed = listed;
}
}  // namespace scalar

#if INERTIA_PARTICLES_VECTOR
namespace sse2 {
#define INERTIA_TARGET
using V = __m128;
using M = __m128;
constexpr std::size_t W = 4;
inline V load(const float* p) { return _mm_loadu_ps(p); }
inline void store(float* p, V v) { _mm_storeu_ps(p, v); }
inline V set1(float x) { return _mm_set1_ps(x); }
inline V zero() { return _mm_setzero_ps(); }
inline V add(V a, V b) { return _mm_add_ps(a, b); }
inline V sub(V a, V b) { return _mm_sub_ps(a, b); }
inline V mul(V a, V b) { return _mm_mul_ps(a, b); }
inline V div(V a, V b) { return _mm_div_ps(a, b); }
inline V sqrt(V a) { return _mm_sqrt_ps(a); }
inline V neg(V a) { return _mm_xor_ps(a, _mm_set1_ps(-0.0f)); }
inline V min(V a, V b) { return _mm_min_ps(a, b); }
inline V max(V a, V b) { return _mm_max_ps(a, b); }
inline M eq(V a, V b) { return _mm_cmpeq_ps(a, b); }
inline M lt(V a, V b) { return _mm_cmplt_ps(a, b); }
inline M le(V a, V b) { return _mm_cmple_ps(a, b); }
inline M ge(V a, V b) { return _mm_cmpge_ps(a, b); }
inline M gt(V a, V b) { return _mm_cmpgt_ps(a, b); }
inline M unordered(V a, V b) { return _mm_cmpunord_ps(a, b); }
inline M none() { return _mm_setzero_ps(); }
inline M and_(M a, M b) { return _mm_and_ps(a, b); }
inline M or_(M a, M b) { return _mm_or_ps(a, b); }
inline M andnot(M a, M b) { return _mm_andnot_ps(a, b); }
inline V select(M m, V a, V b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); }
inline unsigned bits(M m) { return unsigned(_mm_movemask_ps(m)); }
inline std::size_t popcount(unsigned m) { return popcount4(m); }
inline void storeFlags(std::uint8_t* d, unsigned m) { std::memcpy(d, &kMaskBytes[m], 4); }
// Four particles' 12 coordinates (3 registers) to x, y and z registers.
inline void transpose3(V p0, V p1, V p2, V& x, V& y, V& z) {
  const V t0 = _mm_shuffle_ps(p0, p1, _MM_SHUFFLE(1, 0, 2, 1));  // y0 z0 y1 z1
  const V t1 = _mm_shuffle_ps(p1, p2, _MM_SHUFFLE(2, 1, 3, 2));  // x2 y2 x3 y3
  x = _mm_shuffle_ps(p0, t1, _MM_SHUFFLE(2, 0, 3, 0));
  y = _mm_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 1, 2, 0));
  z = _mm_shuffle_ps(t0, p2, _MM_SHUFFLE(3, 0, 3, 1));
}
// s0 s0 s0 s1 | s1 s1 s2 s2 | s2 s3 s3 s3: each particle's scalar over its 3 components.
inline void spread3(V s, V& o0, V& o1, V& o2) {
  o0 = _mm_shuffle_ps(s, s, _MM_SHUFFLE(1, 0, 0, 0));
  o1 = _mm_shuffle_ps(s, s, _MM_SHUFFLE(2, 2, 1, 1));
  o2 = _mm_shuffle_ps(s, s, _MM_SHUFFLE(3, 3, 3, 2));
}
// A 3-vector repeated over 12 consecutive floats.
inline void pattern3(float g0, float g1, float g2, V& o0, V& o1, V& o2) {
  o0 = _mm_setr_ps(g0, g1, g2, g0), o1 = _mm_setr_ps(g1, g2, g0, g1),
  o2 = _mm_setr_ps(g2, g0, g1, g2);
}
inline void prefetch(const float* p) {
  _mm_prefetch(reinterpret_cast<const char*>(p), _MM_HINT_T0);
}
#include "fast_path.inc"
#undef INERTIA_TARGET
}  // namespace sse2

// Compiled for AVX2 only (no FMA: its single rounding would change the bits), called only
// when the processor has it.
namespace avx2 {
#define INERTIA_TARGET __attribute__((target("avx2")))
using V = __m256;
using M = __m256;
constexpr std::size_t W = 8;
INERTIA_TARGET inline V load(const float* p) { return _mm256_loadu_ps(p); }
INERTIA_TARGET inline void store(float* p, V v) { _mm256_storeu_ps(p, v); }
INERTIA_TARGET inline V set1(float x) { return _mm256_set1_ps(x); }
INERTIA_TARGET inline V zero() { return _mm256_setzero_ps(); }
INERTIA_TARGET inline V add(V a, V b) { return _mm256_add_ps(a, b); }
INERTIA_TARGET inline V sub(V a, V b) { return _mm256_sub_ps(a, b); }
INERTIA_TARGET inline V mul(V a, V b) { return _mm256_mul_ps(a, b); }
INERTIA_TARGET inline V div(V a, V b) { return _mm256_div_ps(a, b); }
INERTIA_TARGET inline V sqrt(V a) { return _mm256_sqrt_ps(a); }
INERTIA_TARGET inline V neg(V a) { return _mm256_xor_ps(a, _mm256_set1_ps(-0.0f)); }
INERTIA_TARGET inline V min(V a, V b) { return _mm256_min_ps(a, b); }
INERTIA_TARGET inline V max(V a, V b) { return _mm256_max_ps(a, b); }
INERTIA_TARGET inline M eq(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
INERTIA_TARGET inline M lt(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
INERTIA_TARGET inline M le(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
INERTIA_TARGET inline M ge(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
INERTIA_TARGET inline M gt(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
INERTIA_TARGET inline M unordered(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_UNORD_Q); }
INERTIA_TARGET inline M none() { return _mm256_setzero_ps(); }
INERTIA_TARGET inline M and_(M a, M b) { return _mm256_and_ps(a, b); }
INERTIA_TARGET inline M or_(M a, M b) { return _mm256_or_ps(a, b); }
INERTIA_TARGET inline M andnot(M a, M b) { return _mm256_andnot_ps(a, b); }
INERTIA_TARGET inline V select(M m, V a, V b) { return _mm256_blendv_ps(b, a, m); }
INERTIA_TARGET inline unsigned bits(M m) { return unsigned(_mm256_movemask_ps(m)); }
inline std::size_t popcount(unsigned m) { return popcount4(m & 15) + popcount4(m >> 4); }
inline void storeFlags(std::uint8_t* d, unsigned m) {
  std::memcpy(d, &kMaskBytes[m & 15], 4);
  std::memcpy(d + 4, &kMaskBytes[m >> 4], 4);
}
// Eight particles' 24 coordinates (3 registers: x0 y0 z0 x1 y1 z1 x2 y2 | z2 x3 ... | ... z7)
// to x, y and z registers: two blends gather each coordinate's lanes, a permutation orders them.
INERTIA_TARGET inline void transpose3(V p0, V p1, V p2, V& x, V& y, V& z) {
  const V tx = _mm256_blend_ps(_mm256_blend_ps(p0, p1, 0b10010010), p2, 0b00100100);
  const V ty = _mm256_blend_ps(_mm256_blend_ps(p0, p1, 0b00100100), p2, 0b01001001);
  const V tz = _mm256_blend_ps(_mm256_blend_ps(p0, p1, 0b01001001), p2, 0b10010010);
  x = _mm256_permutevar8x32_ps(tx, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
  y = _mm256_permutevar8x32_ps(ty, _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
  z = _mm256_permutevar8x32_ps(tz, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
}
INERTIA_TARGET inline void spread3(V s, V& o0, V& o1, V& o2) {
  o0 = _mm256_permutevar8x32_ps(s, _mm256_setr_epi32(0, 0, 0, 1, 1, 1, 2, 2));
  o1 = _mm256_permutevar8x32_ps(s, _mm256_setr_epi32(2, 3, 3, 3, 4, 4, 4, 5));
  o2 = _mm256_permutevar8x32_ps(s, _mm256_setr_epi32(5, 5, 6, 6, 6, 7, 7, 7));
}
INERTIA_TARGET inline void pattern3(float g0, float g1, float g2, V& o0, V& o1, V& o2) {
  o0 = _mm256_setr_ps(g0, g1, g2, g0, g1, g2, g0, g1);
  o1 = _mm256_setr_ps(g2, g0, g1, g2, g0, g1, g2, g0);
  o2 = _mm256_setr_ps(g1, g2, g0, g1, g2, g0, g1, g2);
}
inline void prefetch(const float* p) {
  _mm_prefetch(reinterpret_cast<const char*>(p), _MM_HINT_T0);
}
#include "fast_path.inc"
#undef INERTIA_TARGET
}  // namespace avx2
#endif

}  // namespace

SimdChoice& particleChoice() {
#if INERTIA_PARTICLES_VECTOR
  static SimdChoice choice(std::min(cpuSimdLevel(), SimdLevel::Avx2));  // no AVX-512 kernels
#else
  static SimdChoice choice(SimdLevel::Scalar);
#endif
  return choice;
}

SimdLevel bestParticleSimd() { return particleChoice().best(); }
SimdLevel particleSimd() { return particleChoice().current(); }
SimdLevel setParticleSimd(SimdLevel isa) { return particleChoice().force(isa); }

ParticleStepCounts stepParticleBatch(SimdLevel isa, const ParticleStepBatch& batch) {
  ParticleStepCounts counts;
  if (isa == SimdLevel::Scalar) {
    scalar::stepLoops(batch, counts);
    return counts;
  }
  std::size_t i = 0;
#if INERTIA_PARTICLES_VECTOR
  if (isa == SimdLevel::Avx2)
    i = avx2::stepRange(batch, i, counts);
  else if (isa == SimdLevel::Sse2)
    i = sse2::stepRange(batch, i, counts);
#else
  (void)isa;
#endif
  scalar::stepRange(batch, i, counts);  // the last count % W
  return counts;
}

std::size_t settleParticlesOnPlane(SimdLevel isa, const ParticlePlaneSettle& settle) {
#if INERTIA_PARTICLES_VECTOR
  if (isa == SimdLevel::Avx2) return avx2::settleRange(settle);
  if (isa == SimdLevel::Sse2) return sse2::settleRange(settle);
#else
  (void)isa;
#endif
  std::copy_n(settle.list, settle.listed, settle.rest);
  return settle.listed;
}

}  // namespace inertia::detail
