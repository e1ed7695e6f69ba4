// The contact solver's passes over bundles (contact_solver.h), written once for lanes of
// SIMD registers. contact_solver.cpp includes this file once per instruction set, each time
// in its own namespace and with INERTIA_PACK_BYTES set to the native vector width (16: SSE2,
// 32: AVX2, 64: AVX-512), so no inline function is shared between the builds.
//
// Every operation is lane-wise IEEE arithmetic, so a lane computes the same bits in every
// build and in a bundle of one constraint as in a full one. The AVX-512 build's target has
// fused multiply-adds; the project's -ffp-contract=off (CMakeLists.txt) is what keeps the
// compiler from fusing a product and a sum there, which would round once instead of twice.

// GCC's generic vectors: one native register, and the integer vector its comparisons give.
using Native = Real __attribute__((vector_size(INERTIA_PACK_BYTES)));
using NativeMask = decltype(Native{} < Native{});
inline constexpr int kPerNative = INERTIA_PACK_BYTES / int(sizeof(Real));
// A kernel runs a bundle slice by slice. A slice is 32 bytes of lanes (8 floats, 4 doubles)
// in the SSE2 and AVX2 builds: a bundle's two bodies are twelve values, twelve of AVX2's
// sixteen registers (SSE2 already needs two registers a value), and a wider slice spills.
// The AVX-512 build has thirty-two registers and runs the whole bundle in one slice.
inline constexpr int kSliceLanes = std::max(kPerNative, int(32 / sizeof(Real)));
inline constexpr int kNatives = kSliceLanes / kPerNative;
inline constexpr int kSlices = kLanes / kSliceLanes;
static_assert(kNatives * kPerNative == kSliceLanes && kSlices * kSliceLanes == kLanes);

inline Native nativeSqrt(Native x) {
// _mm512_sqrt_* reads an undefined source that GCC 12 warns of; the masked form has none.
#if INERTIA_PACK_BYTES == 64 && defined(INERTIA_DOUBLE)
  return Native(_mm512_mask_sqrt_pd(__m512d(x), __mmask8(0xFF), __m512d(x)));
#elif INERTIA_PACK_BYTES == 64
  return Native(_mm512_mask_sqrt_ps(__m512(x), __mmask16(0xFFFF), __m512(x)));
#elif INERTIA_PACK_BYTES == 32 && defined(INERTIA_DOUBLE)
  return Native(_mm256_sqrt_pd(__m256d(x)));
#elif INERTIA_PACK_BYTES == 32
  return Native(_mm256_sqrt_ps(__m256(x)));
#elif defined(__SSE2__) && defined(INERTIA_DOUBLE)
  return Native(_mm_sqrt_pd(__m128d(x)));
#elif defined(__SSE2__)
  return Native(_mm_sqrt_ps(__m128(x)));
#else
  for (int i = 0; i < kPerNative; ++i) x[i] = std::sqrt(x[i]);
  return x;
#endif
}

// Whether any lane of a comparison's result is set.
inline bool nativeAny(NativeMask m) {
#if INERTIA_PACK_BYTES == 64 && defined(INERTIA_DOUBLE)
  return _mm512_test_epi64_mask(__m512i(m), __m512i(m)) != 0;
#elif INERTIA_PACK_BYTES == 64
  return _mm512_test_epi32_mask(__m512i(m), __m512i(m)) != 0;
#elif INERTIA_PACK_BYTES == 32 && defined(INERTIA_DOUBLE)
  return _mm256_movemask_pd(__m256d(m)) != 0;
#elif INERTIA_PACK_BYTES == 32
  return _mm256_movemask_ps(__m256(m)) != 0;
#elif defined(__SSE2__) && defined(INERTIA_DOUBLE)
  return _mm_movemask_pd(__m128d(m)) != 0;
#elif defined(__SSE2__)
  return _mm_movemask_ps(__m128(m)) != 0;
#else
  for (int i = 0; i < kPerNative; ++i)
    if (m[i]) return true;
  return false;
#endif
}

/// One slice's kSliceLanes values in registers.
struct Pack {
  Native n[kNatives];

  static Pack load(const Real* lanes) {
    Pack p;
    std::memcpy(p.n, lanes, sizeof p.n);
    return p;
  }
  void store(Real* lanes) const { std::memcpy(lanes, n, sizeof n); }
  static Pack splat(Real x) {
    Pack p;
    for (Native& v : p.n) v = Native{} + x;
    return p;
  }
  static Pack zero() { return splat(0); }
};

struct Mask {
  NativeMask n[kNatives];
};

#define INERTIA_PACK_OP(op)                                              \
  [[gnu::always_inline]] inline Pack operator op(Pack a, const Pack& b) { \
    for (int i = 0; i < kNatives; ++i) a.n[i] = a.n[i] op b.n[i];         \
    return a;                                                             \
  }
INERTIA_PACK_OP(+)
INERTIA_PACK_OP(-)
INERTIA_PACK_OP(*)
INERTIA_PACK_OP(/)
#undef INERTIA_PACK_OP

#define INERTIA_PACK_CMP(op)                                              \
  [[gnu::always_inline]] inline Mask operator op(const Pack& a, const Pack& b) { \
    Mask m;                                                                \
    for (int i = 0; i < kNatives; ++i) m.n[i] = a.n[i] op b.n[i];          \
    return m;                                                              \
  }
INERTIA_PACK_CMP(<)
INERTIA_PACK_CMP(>)
INERTIA_PACK_CMP(<=)
INERTIA_PACK_CMP(==)
INERTIA_PACK_CMP(!=)
#undef INERTIA_PACK_CMP

[[gnu::always_inline]] inline Pack operator-(Pack a) {
  for (Native& v : a.n) v = -v;
  return a;
}
[[gnu::always_inline]] inline Pack& operator+=(Pack& a, const Pack& b) { return a = a + b; }
[[gnu::always_inline]] inline Pack& operator-=(Pack& a, const Pack& b) { return a = a - b; }
[[gnu::always_inline]] inline Mask operator&(Mask a, const Mask& b) {
  for (int i = 0; i < kNatives; ++i) a.n[i] = a.n[i] & b.n[i];
  return a;
}
[[gnu::always_inline]] inline bool any(const Mask& m) {
  bool set = false;
  for (const NativeMask& v : m.n) set = set || nativeAny(v);
  return set;
}
/// m ? a : b, lane by lane.
[[gnu::always_inline]] inline Pack select(const Mask& m, const Pack& a, const Pack& b) {
  Pack r;
  for (int i = 0; i < kNatives; ++i) r.n[i] = m.n[i] ? a.n[i] : b.n[i];
  return r;
}
// As std::max and std::min: (a < b) ? b : a and (b < a) ? b : a.
[[gnu::always_inline]] inline Pack max(const Pack& a, const Pack& b) { return select(a < b, b, a); }
[[gnu::always_inline]] inline Pack min(const Pack& a, const Pack& b) { return select(b < a, b, a); }
[[gnu::always_inline]] inline Pack sqrt(Pack a) {
  for (Native& v : a.n) v = nativeSqrt(v);
  return a;
}

struct V3 {
  Pack x, y, z;
};
[[gnu::always_inline]] inline Pack dot(const V3& a, const V3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
[[gnu::always_inline]] inline V3 operator-(const V3& a, const V3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
[[gnu::always_inline]] inline V3 operator*(const Pack& s, const V3& a) {
  return {s * a.x, s * a.y, s * a.z};
}
[[gnu::always_inline]] inline void subtract(V3& a, const V3& b) {
  a.x -= b.x;
  a.y -= b.y;
  a.z -= b.z;
}
[[gnu::always_inline]] inline void add(V3& a, const V3& b) {
  a.x += b.x;
  a.y += b.y;
  a.z += b.z;
}

[[gnu::always_inline]] inline V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Lanes [first, first + kSliceLanes) of a bundle's values: `at(w)` loads them, `at.store`
/// writes them.
struct Slice {
  int first = 0;

  [[gnu::always_inline]] Pack operator()(const WideReal& w) const {
    return Pack::load(w.lane + first);
  }
  [[gnu::always_inline]] V3 operator()(const WideReal (&w)[3]) const {
    return {(*this)(w[0]), (*this)(w[1]), (*this)(w[2])};
  }
  [[gnu::always_inline]] void store(const Pack& p, WideReal& w) const {
    p.store(w.lane + first);
  }
  [[gnu::always_inline]] void store(const V3& v, WideReal (&w)[3]) const {
    store(v.x, w[0]);
    store(v.y, w[1]);
    store(v.z, w[2]);
  }
  // A row-major 3x3 matrix per lane times v.
  [[gnu::always_inline]] V3 multiply(const WideReal (&m)[9], const V3& v) const {
    auto row = [&](int r) {
      return (*this)(m[3 * r]) * v.x + (*this)(m[3 * r + 1]) * v.y + (*this)(m[3 * r + 2]) * v.z;
    };
    return {row(0), row(1), row(2)};
  }
};

/// The velocities of a bundle's bodies on one side, lane by lane.
struct Side {
  V3 v, w;
};

// `Rows` values of the slice's bodies, lane by lane: values(body, row) for a lane's body, or
// none[row] for a static body or an empty lane. The row loops are unrolled so that each row
// reads a fixed offset: GCC then turns the lane loop into gathers (without, the passes were 18%
// slower).
template <int Rows, class Values>
[[gnu::always_inline]] inline std::array<Pack, Rows> gatherLanes(
    const std::array<int, kLanes>& index, const Slice& at, const SolverBody* bodies,
    Values values, const Real (&none)[Rows]) {
  alignas(64) Real c[Rows][kSliceLanes];
  for (int l = 0; l < kSliceLanes; ++l) {
    const int i = index[std::size_t(at.first + l)];
    if (i >= 0) {
#pragma GCC unroll 12
      for (int r = 0; r < Rows; ++r) c[r][l] = values(bodies[i], r);
    } else {
#pragma GCC unroll 12
      for (int r = 0; r < Rows; ++r) c[r][l] = none[r];
    }
  }
  std::array<Pack, Rows> out;
  for (int r = 0; r < Rows; ++r) std::memcpy(out[std::size_t(r)].n, c[r], sizeof out[0].n);
  return out;
}

#if INERTIA_PACK_BYTES >= 32 && !defined(INERTIA_DOUBLE)
// Float in the AVX2 and AVX-512 builds: a body's v and w are its first six floats, so the
// velocities move as one 8-float row per body (v, w, and two floats of dp that are read and
// never written) through an 8 x 8 transpose in registers. A lane loop moving them one value at
// a time was a quarter of the solver pass.
static_assert(sizeof(Real) == 4 && offsetof(SolverBody, w) == 3 * sizeof(Real) &&
              offsetof(SolverBody, dp) == 6 * sizeof(Real) &&
              offsetof(SolverBody, dR) == 9 * sizeof(Real));

#if INERTIA_PACK_BYTES == 64
// Two rows: lane l in the low half, lane l + 8 in the high half. The masked forms of the
// intrinsics: GCC 12 warns of the undefined source the unmasked ones read.
using Row8 = __m512;
constexpr __mmask16 kAll = 0xFFFF;
[[gnu::always_inline]] inline Row8 rowUnpackLo(Row8 a, Row8 b) { return _mm512_mask_unpacklo_ps(a, kAll, a, b); }
[[gnu::always_inline]] inline Row8 rowUnpackHi(Row8 a, Row8 b) { return _mm512_mask_unpackhi_ps(a, kAll, a, b); }
template <int Imm>
[[gnu::always_inline]] inline Row8 rowShuffle(Row8 a, Row8 b) { return _mm512_mask_shuffle_ps(a, kAll, a, b, Imm); }
// The low (High = false) or high 128-bit blocks of each half of a and b, interleaved by block.
template <bool High>
[[gnu::always_inline]] inline Row8 rowBlocks(Row8 a, Row8 b) {
  constexpr int o = High ? 4 : 0;
  const __m512i index = _mm512_setr_epi32(o, o + 1, o + 2, o + 3, o + 16, o + 17, o + 18, o + 19,
                                          o + 8, o + 9, o + 10, o + 11, o + 24, o + 25, o + 26,
                                          o + 27);
  return _mm512_permutex2var_ps(a, index, b);
}
#else
using Row8 = __m256;
[[gnu::always_inline]] inline Row8 rowUnpackLo(Row8 a, Row8 b) { return _mm256_unpacklo_ps(a, b); }
[[gnu::always_inline]] inline Row8 rowUnpackHi(Row8 a, Row8 b) { return _mm256_unpackhi_ps(a, b); }
template <int Imm>
[[gnu::always_inline]] inline Row8 rowShuffle(Row8 a, Row8 b) { return _mm256_shuffle_ps(a, b, Imm); }
template <bool High>
[[gnu::always_inline]] inline Row8 rowBlocks(Row8 a, Row8 b) {
  return _mm256_permute2f128_ps(a, b, High ? 0x31 : 0x20);
}
#endif

// Transposes the 8 x 8 matrix of rows r (in each 256-bit half independently): r[k][i]
// becomes r[i][k]. Its own inverse.
[[gnu::always_inline]] inline void transpose8(Row8 (&r)[8]) {
  Row8 t[8], s[8];
#pragma GCC unroll 8
  for (int j = 0; j < 4; ++j) {
    t[2 * j] = rowUnpackLo(r[2 * j], r[2 * j + 1]);
    t[2 * j + 1] = rowUnpackHi(r[2 * j], r[2 * j + 1]);
  }
#pragma GCC unroll 8
  for (int j = 0; j < 2; ++j) {
    s[4 * j] = rowShuffle<0x44>(t[4 * j], t[4 * j + 2]);
    s[4 * j + 1] = rowShuffle<0xEE>(t[4 * j], t[4 * j + 2]);
    s[4 * j + 2] = rowShuffle<0x44>(t[4 * j + 1], t[4 * j + 3]);
    s[4 * j + 3] = rowShuffle<0xEE>(t[4 * j + 1], t[4 * j + 3]);
  }
#pragma GCC unroll 8
  for (int k = 0; k < 4; ++k) {
    r[k] = rowBlocks<false>(s[k], s[k + 4]);
    r[k + 4] = rowBlocks<true>(s[k], s[k + 4]);
  }
}

// Eight consecutive floats of each lane's body, from first(body), or `none` for a static body
// or an empty lane, transposed: r[k] holds float k of every lane.
template <class First>
[[gnu::always_inline]] inline void gatherRows(const std::array<int, kLanes>& index,
                                              const Slice& at, const SolverBody* bodies,
                                              First first, const Real* none, Row8 (&r)[8]) {
  auto row = [&](int lane) {
    const int i = index[std::size_t(at.first + lane)];
    return i >= 0 ? first(bodies[i]) : none;
  };
#pragma GCC unroll 8
  for (int i = 0; i < 8; ++i) {
#if INERTIA_PACK_BYTES == 64
    const __m512d lo = _mm512_castps_pd(_mm512_castps256_ps512(_mm256_loadu_ps(row(i))));
    const __m256d hi = _mm256_castps_pd(_mm256_loadu_ps(row(i + 8)));
    r[i] = _mm512_castpd_ps(_mm512_mask_insertf64x4(lo, __mmask8(0xFF), lo, hi, 1));
#else
    r[i] = _mm256_loadu_ps(row(i));
#endif
  }
  transpose8(r);
}

[[gnu::always_inline]] inline Pack packOf(Row8 r) {
  static_assert(kNatives == 1);
  Pack p;
  p.n[0] = Native(r);
  return p;
}

// v and w, and two floats of dp that are not used.
[[gnu::always_inline]] inline Side gather(const std::array<int, kLanes>& index, const Slice& at,
                                          const SolverBody* bodies) {
  alignas(32) static constexpr Real kStill[8] = {};
  Row8 r[8];
  gatherRows(index, at, bodies, [](const SolverBody& b) { return b.v.data(); }, kStill, r);
  return {{packOf(r[0]), packOf(r[1]), packOf(r[2])}, {packOf(r[3]), packOf(r[4]), packOf(r[5])}};
}

// Only moving bodies are written, six floats each: lanes of a bundle never share one, while
// static and kinematic bodies (unchanged by impulses) may appear in several lanes and threads.
[[gnu::always_inline]] inline void scatter(const Side& s, const std::array<int, kLanes>& index,
                                           std::uint32_t write, const Slice& at,
                                           SolverBody* bodies) {
  Row8 r[8] = {Row8(s.v.x.n[0]), Row8(s.v.y.n[0]), Row8(s.v.z.n[0]),
               Row8(s.w.x.n[0]), Row8(s.w.y.n[0]), Row8(s.w.z.n[0]), Row8{}, Row8{}};
  transpose8(r);
  auto put = [&](int lane, Row8 row) {
    if (!((write >> lane) & 1u)) return;
    Real* p = bodies[index[std::size_t(lane)]].v.data();
#if INERTIA_PACK_BYTES == 64
    _mm512_mask_storeu_ps(p, __mmask16(0x3F), row);
#else
    _mm_storeu_ps(p, _mm256_castps256_ps128(row));
    _mm_storel_pi(reinterpret_cast<__m64*>(p + 4), _mm256_extractf128_ps(row, 1));
#endif
  };
#pragma GCC unroll 8
  for (int i = 0; i < 8; ++i) {
    put(at.first + i, r[i]);
#if INERTIA_PACK_BYTES == 64
    put(at.first + i + 8, _mm512_mask_shuffle_f32x4(r[i], kAll, r[i], r[i], 0xEE));
#endif
  }
}
#else
// Static bodies and empty lanes read zero velocities.
[[gnu::always_inline]] inline Side gather(const std::array<int, kLanes>& index, const Slice& at,
                                          const SolverBody* bodies) {
  constexpr Real kNone[6] = {};
  const auto p = gatherLanes<6>(
      index, at, bodies,
      [](const SolverBody& b, int r) { return r < 3 ? b.v[r] : b.w[r - 3]; }, kNone);
  return {{p[0], p[1], p[2]}, {p[3], p[4], p[5]}};
}

// Only moving bodies are written: lanes of a bundle never share one, while static and
// kinematic bodies (unchanged by impulses) may appear in several lanes and threads.
[[gnu::always_inline]] inline void scatter(const Side& s, const std::array<int, kLanes>& index,
                                           std::uint32_t write, const Slice& at,
                                           SolverBody* bodies) {
  alignas(64) Real c[6][kSliceLanes];
  const Pack* parts[6] = {&s.v.x, &s.v.y, &s.v.z, &s.w.x, &s.w.y, &s.w.z};
  for (int r = 0; r < 6; ++r) std::memcpy(c[r], parts[r]->n, sizeof c[r]);
  for (int l = 0; l < kSliceLanes; ++l) {
    if (!((write >> (at.first + l)) & 1u)) continue;
    SolverBody& b = bodies[index[std::size_t(at.first + l)]];
    b.v = Vec3(c[0][l], c[1][l], c[2][l]);
    b.w = Vec3(c[3][l], c[4][l], c[5][l]);
  }
}

#endif

// An impulse `lambda` along one row: direction d, Jacobian images wA = invIA (rA x d) and
// wB = invIB (rB x d).
[[gnu::always_inline]] inline void applyRow(Side& a, Side& b, const Pack& invMassA,
                                            const Pack& invMassB, const V3& d, const V3& wA,
                                            const V3& wB, const Pack& lambda) {
  subtract(a.v, (invMassA * lambda) * d);
  subtract(a.w, lambda * wA);
  add(b.v, (invMassB * lambda) * d);
  add(b.w, lambda * wB);
}

// The velocity along one row: d . (vB - vA) + wB . (rB x d) - wA . (rA x d).
[[gnu::always_inline]] inline Pack rowVelocity(const Side& a, const Side& b, const V3& d,
                                               const V3& rA, const V3& rB) {
  return dot(d, b.v - a.v) + dot(b.w, rB) - dot(a.w, rA);
}

// The rolling and spinning impulses L = sum of impulse * axis, applied through the inverse
// inertias' images of the axes.
[[gnu::always_inline]] inline void applyAngular(Side& a, Side& b, const WideConstraint& c,
                                                const Slice& at, const Pack& roll0, const Pack& roll1,
                                                const Pack& spin) {
  subtract(a.w, roll0 * at(c.iaT[0]));
  subtract(a.w, roll1 * at(c.iaT[1]));
  subtract(a.w, spin * at(c.iaN));
  add(b.w, roll0 * at(c.ibT[0]));
  add(b.w, roll1 * at(c.ibT[1]));
  add(b.w, spin * at(c.ibN));
}

// 1 / k for the effective mass k of a row, 0 for a row that no impulse can move (k = 0).
[[gnu::always_inline]] inline Pack invEffective(const Pack& k) {
  const Pack zero = Pack::zero();
  return select(k > zero, Pack::splat(1) / k, zero);
}

// The rows' angular Jacobians r x d, their images under the inverse inertias, and the
// effective masses, as computeMasses() does for one constraint. Points beyond a lane's own
// count keep masses of zero.
void prepareSlice(WideConstraint& c, const WideInertia& inertia, const Slice& at) {
  const Pack mSum = at(c.invMassA) + at(c.invMassB);
  const V3 n = at(c.normal);
  const V3 t[2] = {at(c.tangent[0]), at(c.tangent[1])};
  const Pack points = at(c.lanePoints), zero = Pack::zero();
  for (int i = 0; i < c.pointCount; ++i) {
    WidePoint& p = c.points[std::size_t(i)];
    const Mask real = points > Pack::splat(Real(i));
    const V3 rA = at(p.rA), rB = at(p.rB);
    // One row: returns its effective mass, stores its Jacobians.
    auto row = [&](const V3& d, WideReal (&ra)[3], WideReal (&rb)[3], WideReal (&wa)[3],
                   WideReal (&wb)[3]) {
      const V3 rdA = cross(rA, d), rdB = cross(rB, d);
      const V3 wdA = at.multiply(inertia.a, rdA), wdB = at.multiply(inertia.b, rdB);
      at.store(rdA, ra);
      at.store(rdB, rb);
      at.store(wdA, wa);
      at.store(wdB, wb);
      return select(real, invEffective(mSum + dot(rdA, wdA) + dot(rdB, wdB)), zero);
    };
    at.store(row(n, p.rnA, p.rnB, p.wnA, p.wnB), p.normalMass);
    for (int k = 0; k < 2; ++k)
      at.store(row(t[k], p.rtA[k], p.rtB[k], p.wtA[k], p.wtB[k]), p.tangentMass[k]);
  }
  if (c.angular) {
    for (int k = 0; k < 2; ++k) {
      const V3 ia = at.multiply(inertia.a, t[k]), ib = at.multiply(inertia.b, t[k]);
      at.store(ia, c.iaT[k]);
      at.store(ib, c.ibT[k]);
      at.store(invEffective(dot(t[k], ia) + dot(t[k], ib)), c.rollingMass[k]);
    }
    const V3 ia = at.multiply(inertia.a, n), ib = at.multiply(inertia.b, n);
    at.store(ia, c.iaN);
    at.store(ib, c.ibN);
    at.store(invEffective(dot(n, ia) + dot(n, ib)), c.spinningMass);
  }
}

void warmStartSlice(const WideConstraint& c, const Slice& at, SolverBody* bodies) {
  Side a = gather(c.bodyA, at, bodies), b = gather(c.bodyB, at, bodies);
  const Pack mA = at(c.invMassA), mB = at(c.invMassB);
  const V3 n = at(c.normal);
  const V3 t[2] = {at(c.tangent[0]), at(c.tangent[1])};
  for (int i = 0; i < c.pointCount; ++i) {
    const WidePoint& p = c.points[std::size_t(i)];
    applyRow(a, b, mA, mB, n, at(p.wnA), at(p.wnB), at(p.normalImpulse));
    for (int k = 0; k < 2; ++k)
      applyRow(a, b, mA, mB, t[k], at(p.wtA[k]), at(p.wtB[k]),
               at(p.tangentImpulse[k]));
  }
  if (c.angular)
    applyAngular(a, b, c, at, at(c.rollingImpulse[0]), at(c.rollingImpulse[1]),
                 at(c.spinningImpulse));
  scatter(a, c.bodyA, c.writeA, at, bodies);
  scatter(b, c.bodyB, c.writeB, at, bodies);
}

// Clamps the 2-vector (x, y) to the disc of radius `limit`. When no lane is outside (every
// contact of the bundle sticks, as in resting stacks) nothing changes, and the branch lets the
// next row start without waiting for the square root and the division, the longest latency of
// the pass. Otherwise lanes inside are scaled by 1, which is exact.
[[gnu::always_inline]] inline void clampDisc(Pack& x, Pack& y, const Pack& limit) {
  const Pack len2 = x * x + y * y;
  const Mask outside = len2 > limit * limit;
  if (!any(outside)) return;
  const Pack scale = select(outside, limit / sqrt(len2), Pack::splat(1));
  x = x * scale;
  y = y * scale;
}

// A bundle's state through a solve pass: its bodies' velocities and what every row reads.
struct SolveState {
  Side a, b;
  Pack mA, mB;
  V3 n;
  Pack totalNormal;
};

[[gnu::always_inline]] inline SolveState beginSolve(const WideConstraint& c, const Slice& at,
                                                    const SolverBody* bodies) {
  return {gather(c.bodyA, at, bodies), gather(c.bodyB, at, bodies), at(c.invMassA),
          at(c.invMassB), at(c.normal), Pack::zero()};
}

// The non-penetration row of point i.
[[gnu::always_inline]] inline void normalRow(WideConstraint& c, int i, SolveState& st,
                                             const Slice& at, const BiasMode& mode) {
  const Pack zero = Pack::zero(), one = Pack::splat(1);
  const Pack invH = Pack::splat(mode.invH);
  const Pack push = Pack::splat(-mode.pushVelocity);
  WidePoint& p = c.points[std::size_t(i)];
  const Pack s = at(p.separation);
  // s > 0: speculative, the gap may close within this substep, no more.
  Pack bias = zero, massScale = one, impulseScale = zero;
  if (mode.useBias) {
    if (mode.soft) {
      bias = max(at(c.biasRate) * s, push);
      massScale = at(c.massScale);
      impulseScale = at(c.impulseScale);
    } else {
      // Baumgarte: feed back a fraction of the overlap beyond the slop.
      bias = max(Pack::splat(mode.baumgarte) * invH * min(s + Pack::splat(mode.linearSlop), zero),
                 push);
    }
  }
  const Mask open = s > zero;
  bias = select(open, s * invH, bias);
  massScale = select(open, one, massScale);
  impulseScale = select(open, zero, impulseScale);

  const Pack vn = rowVelocity(st.a, st.b, st.n, at(p.rnA), at(p.rnB));
  const Pack accumulated = at(p.normalImpulse);
  const Pack impulse0 = -at(p.normalMass) * massScale * (vn + bias) - impulseScale * accumulated;
  Pack updated = max(accumulated + impulse0, zero);
  // The relax pass leaves a bouncy contact's open rows alone: their gap closes, if at all, in a
  // later substep, whose solve pass stops it there. Slowing the approach now would take the
  // speed that restitution gives back at the impact. A contact without restitution is relaxed
  // as Box2D v3 does: left alone, a body resting on a speculative gap would keep the speed that
  // closes it (a 70 kg ragdoll at rest kept 0.039 J).
  if (!mode.useBias) updated = select(open & (at(c.restitution) != zero), accumulated, updated);
  const Pack impulse = updated - accumulated;
  at.store(updated, p.normalImpulse);
  at.store(max(at(p.maxNormalImpulse), impulse), p.maxNormalImpulse);
  st.totalNormal += updated;
  applyRow(st.a, st.b, st.mA, st.mB, st.n, at(p.wnA), at(p.wnB), impulse);
}

// Coulomb friction at point i: the tangential impulse stays in the disc of radius mu * normal.
[[gnu::always_inline]] inline void frictionRows(WideConstraint& c, int i, SolveState& st,
                                                const Slice& at) {
  WidePoint& p = c.points[std::size_t(i)];
  const V3 t[2] = {at(c.tangent[0]), at(c.tangent[1])};
  Pack old[2], updated[2];
#pragma GCC unroll 2
  for (int k = 0; k < 2; ++k) {
    old[k] = at(p.tangentImpulse[k]);
    updated[k] =
        old[k] - at(p.tangentMass[k]) * rowVelocity(st.a, st.b, t[k], at(p.rtA[k]), at(p.rtB[k]));
  }
  clampDisc(updated[0], updated[1], at(c.friction) * at(p.normalImpulse));
#pragma GCC unroll 2
  for (int k = 0; k < 2; ++k) {
    applyRow(st.a, st.b, st.mA, st.mB, t[k], at(p.wtA[k]), at(p.wtB[k]), updated[k] - old[k]);
    at.store(updated[k], p.tangentImpulse[k]);
  }
}

// Rolling resistance (torque <= b N about the tangents) and spinning friction. A lane without
// them has a limit of zero and keeps impulses of zero.
[[gnu::always_inline]] inline void angularRows(WideConstraint& c, SolveState& st,
                                               const Slice& at) {
  const V3 t[2] = {at(c.tangent[0]), at(c.tangent[1])};
  const V3 dw = st.b.w - st.a.w;
  const Pack old[2] = {at(c.rollingImpulse[0]), at(c.rollingImpulse[1])};
  Pack roll[2];
  for (int k = 0; k < 2; ++k) roll[k] = old[k] - at(c.rollingMass[k]) * dot(dw, t[k]);
  clampDisc(roll[0], roll[1], at(c.rolling) * st.totalNormal);
  const Pack limit = at(c.spinning) * st.totalNormal;
  const Pack oldSpin = at(c.spinningImpulse);
  const Pack spin = min(max(oldSpin - at(c.spinningMass) * dot(dw, st.n), -limit), limit);
  applyAngular(st.a, st.b, c, at, roll[0] - old[0], roll[1] - old[1], spin - oldSpin);
  at.store(roll[0], c.rollingImpulse[0]);
  at.store(roll[1], c.rollingImpulse[1]);
  at.store(spin, c.spinningImpulse);
}

// One pass over N bundles of one colour with the same point count, row by row in step: the
// bundles share no moving body, so their rows are independent chains that the processor
// overlaps, and each computes what it would alone.
template <int N>
void solveSlices(WideConstraint* const (&cs)[N], const Slice& at, SolverBody* bodies,
                 const BiasMode& mode) {
  SolveState st[N];
#pragma GCC unroll 2
  for (int j = 0; j < N; ++j) st[j] = beginSolve(*cs[j], at, bodies);
  const int points = cs[0]->pointCount;
  for (int i = 0; i < points; ++i) {
#pragma GCC unroll 2
    for (int j = 0; j < N; ++j) normalRow(*cs[j], i, st[j], at, mode);
  }
  for (int i = 0; i < points; ++i) {
#pragma GCC unroll 2
    for (int j = 0; j < N; ++j) frictionRows(*cs[j], i, st[j], at);
  }
#pragma GCC unroll 2
  for (int j = 0; j < N; ++j) {
    if (cs[j]->angular) angularRows(*cs[j], st[j], at);
    scatter(st[j].a, cs[j]->bodyA, cs[j]->writeA, at, bodies);
    scatter(st[j].b, cs[j]->bodyB, cs[j]->writeB, at, bodies);
  }
}

// Points of a bouncy constraint whose gap is still open and that have not pushed yet: their
// approach is measured in the substep in which they touch (updateApproachSlice).
[[gnu::always_inline]] inline Mask approaching(const WideConstraint& c, const WidePoint& p,
                                               const Slice& at) {
  return (at(c.restitution) != Pack::zero()) & (at(p.maxNormalImpulse) == Pack::zero()) &
         (at(p.separation) > Pack::zero());
}

// Before a substep's velocity update: such points keep their normal velocity v0.
void beginApproachSlice(WideConstraint& c, const Slice& at, const SolverBody* bodies) {
  const Side a = gather(c.bodyA, at, bodies), b = gather(c.bodyB, at, bodies);
  const V3 n = at(c.normal);
  for (int i = 0; i < c.pointCount; ++i) {
    WidePoint& p = c.points[std::size_t(i)];
    at.store(select(approaching(c, p, at), rowVelocity(a, b, n, at(p.rnA), at(p.rnB)),
                    at(p.relativeVelocity)),
             p.relativeVelocity);
  }
}

// After it (v1): the normal velocity at which the gap s closes under the substep's constant
// normal acceleration a = (v1 - v0) / h, v^2 = v0^2 - 2 a s, whatever the time of the impact
// within the substep (the velocity of the whole substep, v1, is up to |a| h off).
//
// `flight` is the flight integrator's lag (flightLag: h for symplectic Euler, 0 for an exact
// method). Symplectic Euler under a constant acceleration conserves the modified energy
// Q = v^2 - 2 a y + a h v, not v^2 - 2 a y: a body dropped from rest at height H meets the
// ground at a speed V with V^2 + a h V = -2 a H, |a| h / 2 slower than sqrt(2 |a| H), and one
// launched at U climbs to (U^2 + a h U) / (-2 a). Newton's law on the modified energy,
// Q after = e^2 Q before, brings the apex back to e^2 H:
// U = (sqrt((a h)^2 + 4 e^2 (V^2 + a h V)) - a h) / 2, the point's launch (e |V| for h = 0).
void updateApproachSlice(WideConstraint& c, const Slice& at, const SolverBody* bodies, Real invH,
                         Real flight) {
  const Side a = gather(c.bodyA, at, bodies), b = gather(c.bodyB, at, bodies);
  const V3 n = at(c.normal);
  const Pack zero = Pack::zero();
  const Pack e = at(c.restitution);
  for (int i = 0; i < c.pointCount; ++i) {
    WidePoint& p = c.points[std::size_t(i)];
    const Pack v0 = at(p.relativeVelocity);
    const Pack v1 = rowVelocity(a, b, n, at(p.rnA), at(p.rnB));
    const Pack accel = (v1 - v0) * Pack::splat(invH);
    const Pack squared = v0 * v0 - (accel + accel) * at(p.separation);
    const Pack impact = select(v1 < zero, zero - sqrt(max(squared, zero)), v1);
    const Pack ah = accel * Pack::splat(flight);
    const Pack modified = max(impact * impact + ah * impact, zero);
    const Pack launch = (sqrt(ah * ah + Pack::splat(4) * e * e * modified) - ah) * Pack::splat(0.5);
    const Mask update = approaching(c, p, at);
    at.store(select(update, impact, v0), p.relativeVelocity);
    at.store(select(update, select(v1 < zero, launch, zero), at(p.launch)), p.launch);
  }
}

void restitutionSlice(WideConstraint& c, const Slice& at, SolverBody* bodies, Real threshold) {
  Side a = gather(c.bodyA, at, bodies), b = gather(c.bodyB, at, bodies);
  const Pack mA = at(c.invMassA), mB = at(c.invMassB);
  const V3 n = at(c.normal);
  const Pack zero = Pack::zero();
  const Pack e = at(c.restitution);
  const Mask bouncy = e != zero;
  for (int i = 0; i < c.pointCount; ++i) {
    WidePoint& p = c.points[std::size_t(i)];
    const Pack approach = at(p.relativeVelocity);
    const Pack maxImpulse = at(p.maxNormalImpulse);
    const Mask hit = bouncy & (approach <= Pack::splat(-threshold)) & (maxImpulse != zero);
    const Pack vn = rowVelocity(a, b, n, at(p.rnA), at(p.rnB));
    const Pack accumulated = at(p.normalImpulse);
    const Pack wanted = select(hit, at(p.normalMass) * (at(p.launch) - vn), zero);
    const Pack updated = max(accumulated + wanted, zero);
    const Pack impulse = updated - accumulated;
    at.store(updated, p.normalImpulse);
    at.store(max(maxImpulse, impulse), p.maxNormalImpulse);
    applyRow(a, b, mA, mB, n, at(p.wnA), at(p.wnB), impulse);
  }
  scatter(a, c.bodyA, c.writeA, at, bodies);
  scatter(b, c.bodyB, c.writeB, at, bodies);
}

// Each side's motion since the step's start, lane by lane: dR's columns and dp. Static bodies
// and empty lanes have not moved (identity, zero).
struct Motion {
  V3 column[3], dp;
};
#if INERTIA_PACK_BYTES >= 32 && !defined(INERTIA_DOUBLE)
// Two rows of eight floats per body: dp and dR's first five values (column-major); dR's last
// eight.
[[gnu::always_inline]] inline Motion gatherMotion(const std::array<int, kLanes>& index,
                                                  const Slice& at, const SolverBody* bodies) {
  // Both rows of a body that has not moved: dp zero, dR identity (0 0 0 1 0 0 0 1 from either
  // start).
  alignas(32) static constexpr Real kStill[8] = {0, 0, 0, 1, 0, 0, 0, 1};
  Row8 p[8], q[8];
  gatherRows(index, at, bodies, [](const SolverBody& b) { return b.dp.data(); }, kStill, p);
  gatherRows(index, at, bodies, [](const SolverBody& b) { return b.dR.data() + 1; }, kStill, q);
  return {{{packOf(p[3]), packOf(q[0]), packOf(q[1])},
           {packOf(q[2]), packOf(q[3]), packOf(q[4])},
           {packOf(q[5]), packOf(q[6]), packOf(q[7])}},
          {packOf(p[0]), packOf(p[1]), packOf(p[2])}};
}
#else
[[gnu::always_inline]] inline Motion gatherMotion(const std::array<int, kLanes>& index,
                                                  const Slice& at, const SolverBody* bodies) {
  constexpr Real kNone[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};  // identity, zero
  const auto p = gatherLanes<12>(
      index, at, bodies,
      [](const SolverBody& b, int r) { return r < 9 ? b.dR.data()[r] : b.dp[r - 9]; },  // dR column-major
      kNone);
  return {{{p[0], p[1], p[2]}, {p[3], p[4], p[5]}, {p[6], p[7], p[8]}}, {p[9], p[10], p[11]}};
}

#endif

// A 3-vector dot product summed in the order Eigen 3.4 sums it, so that the kernel gives the
// bits of the scalar code it replaced (a.dR.transpose() * n, n.dot(dp)): in float Eigen does not
// vectorise a sum of three and unrolls it as x0 y0 + (x1 y1 + x2 y2); in double it adds a
// packet of the first two, then the third. Any order would keep the sets equal to each other.
[[gnu::always_inline]] inline Pack eigenDot(const V3& a, const V3& b) {
  if constexpr (sizeof(Real) == 8)
    return (a.x * b.x + a.y * b.y) + a.z * b.z;
  else
    return a.x * b.x + (a.y * b.y + a.z * b.z);
}

// The points' separations, as ContactBundles::updateMotion documents. Once per position
// update: the iterations between two updates read them.
void updateMotionSlice(WideConstraint& c, const Slice& at, const SolverBody* bodies) {
  const Motion a = gatherMotion(c.bodyA, at, bodies), b = gatherMotion(c.bodyB, at, bodies);
  const V3 n = at(c.normal);
  // dR^T n: column k of dR dotted with n.
  const V3 movedA{eigenDot(a.column[0], n), eigenDot(a.column[1], n), eigenDot(a.column[2], n)};
  const V3 movedB{eigenDot(b.column[0], n), eigenDot(b.column[1], n), eigenDot(b.column[2], n)};
  const Pack offset = eigenDot(n, b.dp - a.dp);
  for (int i = 0; i < c.pointCount; ++i) {
    WidePoint& p = c.points[std::size_t(i)];
    at.store(offset + dot(movedB, at(p.rB)) - dot(movedA, at(p.rA)) + at(p.adjustedSeparation),
             p.separation);
  }
}

// Runs `kernel(slice)` on each slice of `c` that has a lane in use.
template <class Kernel>
[[gnu::always_inline]] inline void forSlices(const WideConstraint& c, Kernel kernel) {
  for (int first = 0; first < c.lanes; first += kSliceLanes) kernel(Slice{first});
}

void prepareBundle(WideConstraint& c, const WideInertia& inertia) {
  forSlices(c, [&](const Slice& at) { prepareSlice(c, inertia, at); });
}

// The passes over a range of bundles.
void warmStartRange(const WideConstraint* c, std::size_t count, SolverBody* bodies) {
  for (std::size_t k = 0; k < count; ++k)
    forSlices(c[k], [&](const Slice& at) { warmStartSlice(c[k], at, bodies); });
}
void solveRange(WideConstraint* c, std::size_t count, SolverBody* bodies, const BiasMode& mode) {
  for (std::size_t k = 0; k < count; ++k) {
    // Two bundles at once where they are alike. Not the overflow's, which may share bodies:
    // its bundles hold one constraint each.
    if (kSlices == 1 && k + 1 < count && c[k].lanes > 1 && c[k + 1].lanes > 1 &&
        c[k].pointCount == c[k + 1].pointCount) {
      WideConstraint* const pair[2] = {&c[k], &c[k + 1]};
      solveSlices(pair, Slice{0}, bodies, mode);
      ++k;
      continue;
    }
    forSlices(c[k], [&](const Slice& at) {
      WideConstraint* const one[1] = {&c[k]};
      solveSlices(one, at, bodies, mode);
    });
  }
}
void beginApproachRange(WideConstraint* c, std::size_t count, const SolverBody* bodies) {
  for (std::size_t k = 0; k < count; ++k)
    if (c[k].bouncy)
      forSlices(c[k], [&](const Slice& at) { beginApproachSlice(c[k], at, bodies); });
}
void updateApproachRange(WideConstraint* c, std::size_t count, const SolverBody* bodies,
                         Real invH, Real flight) {
  for (std::size_t k = 0; k < count; ++k)
    if (c[k].bouncy)
      forSlices(c[k], [&](const Slice& at) { updateApproachSlice(c[k], at, bodies, invH, flight); });
}
void restitutionRange(WideConstraint* c, std::size_t count, SolverBody* bodies, Real threshold) {
  for (std::size_t k = 0; k < count; ++k)
    if (c[k].bouncy)
      forSlices(c[k], [&](const Slice& at) { restitutionSlice(c[k], at, bodies, threshold); });
}
void updateMotionRange(WideConstraint* c, std::size_t count, const SolverBody* bodies) {
  for (std::size_t k = 0; k < count; ++k)
    forSlices(c[k], [&](const Slice& at) { updateMotionSlice(c[k], at, bodies); });
}
