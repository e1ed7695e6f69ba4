// Internal: which instruction set the library's SIMD kernels use (the contact solver's bundles,
// the particle step). Every kernel computes the same bits in each set, so the choice changes
// speed only; tests force each set in turn to compare them.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace inertia::detail {

/// Instruction sets of the kernels, in increasing width.
enum class SimdLevel : std::uint8_t { Scalar, Sse2, Avx2, Avx512 };

inline const char* simdLevelName(SimdLevel level) {
  switch (level) {
    case SimdLevel::Scalar:
      return "scalar";
    case SimdLevel::Sse2:
      return "SSE2";
    case SimdLevel::Avx2:
      return "AVX2";
    case SimdLevel::Avx512:
      return "AVX-512";
  }
  return "?";
}

/// The widest set this processor (and its operating system, which must save the wider
/// registers) runs: AVX-512 (the F subset), AVX2 or SSE2 (the x86-64 baseline) on x86,
/// scalar elsewhere; capped by the environment variable INERTIA_SIMD ("avx2" or "sse2"), to
/// compare the sets or to keep a processor that lowers its clock for 512-bit work off AVX-512.
/// Another value of INERTIA_SIMD is ignored with a warning on stderr. Detected once.
inline SimdLevel cpuSimdLevel() {
#if defined(__x86_64__) || defined(__i386__)
  static const SimdLevel level = [] {
    __builtin_cpu_init();
    SimdLevel found = SimdLevel::Sse2;
    if (__builtin_cpu_supports("avx512f"))
      found = SimdLevel::Avx512;
    else if (__builtin_cpu_supports("avx2"))
      found = SimdLevel::Avx2;
    if (const char* cap = std::getenv("INERTIA_SIMD")) {
      const std::string_view name(cap);
      if (name == "sse2")
        found = SimdLevel::Sse2;
      else if (name == "avx2")
        found = std::min(found, SimdLevel::Avx2);
      else if (name != "avx512")
        std::fprintf(stderr, "inertia: INERTIA_SIMD=%s ignored: expected avx512, avx2 or sse2\n",
                     cap);
    }
    return found;
  }();
  return level;
#else
  return SimdLevel::Scalar;
#endif
}

/// One family of kernels' choice: the widest it supports unless a test forced a narrower one.
class SimdChoice {
 public:
  explicit SimdChoice(SimdLevel best) : best_(best) {}
  SimdLevel best() const { return best_; }
  SimdLevel current() const {
    const int forced = forced_.load(std::memory_order_relaxed);
    return forced < 0 ? best_ : SimdLevel(forced);
  }
  /// Forces `level` (clamped to best()) and returns the previous choice. For tests comparing
  /// the sets bit for bit; not meant to change while kernels run.
  SimdLevel force(SimdLevel level) {
    const SimdLevel previous = current();
    forced_.store(int(std::min(level, best_)), std::memory_order_relaxed);
    return previous;
  }

 private:
  SimdLevel best_;
  std::atomic<int> forced_{-1};  // -1: none
};

}  // namespace inertia::detail
