// Reading structured values from a fuzzer's bytes, and the check every target makes.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "inertia/core/types.h"

namespace inertia::fuzz {

/// Consumes a byte string front to back; past the end every read gives zeros.
class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  bool empty() const { return pos_ >= size_; }
  /// An integer in [0, n).
  unsigned pick(unsigned n) { return n == 0 ? 0 : unsigned(byte()) % n; }

  /// A real from a table of awkward values (0, tiny, huge, negative, near 1) or a scaled byte
  /// pair: sizes and coordinates that stress rounding without being non-finite.
  Real real(Real scale = 1) {
    static constexpr double kSpecial[] = {0, 1e-7, 1e-4, 1e-3, 0.5, 1, -1, 1e3, 1e5, -1e5, 1e-30};
    const std::uint8_t k = byte();
    if (k < 24) return Real(kSpecial[k % std::size(kSpecial)]);
    const int v = int(byte()) << 8 | byte();
    return Real((v - 32768) / 32768.0 * scale);
  }
  /// A positive size in [1e-4, 1e3] on a log scale, or a special small one.
  Real size() {
    const std::uint8_t k = byte();
    if (k < 8) return Real(k < 4 ? 1e-6 : 1e-4);
    return Real(std::pow(10.0, -4 + 7 * (k - 8) / 247.0));
  }
  // Reads in statements of their own: the order of a call's arguments is unspecified (gcc and
  // clang differ), and an input must mean the same world in both builds.
  Vec3 vec(Real scale = 1) {
    const Real x = real(scale), y = real(scale), z = real(scale);
    return Vec3(x, y, z);
  }
  Quat rotation() {
    const Real w = real(), x = real(), y = real(), z = real();
    const Quat q(w, x, y, z);
    if (!(q.norm() > Real(1e-3))) return Quat::Identity();
    return q.normalized();
  }
  Transform pose(Real scale = 1) {
    const Vec3 p = vec(scale);
    return {p, rotation()};
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

/// Aborts (a finding) when x holds a NaN or an infinity.
#define INERTIA_FUZZ_FINITE(x)                                                 \
  do {                                                                         \
    if (!::inertia::fuzz::allFinite(x)) {                                      \
      std::fprintf(stderr, "%s:%d: not finite: %s\n", __FILE__, __LINE__, #x); \
      std::abort();                                                            \
    }                                                                          \
  } while (0)

inline bool allFinite(Real x) { return std::isfinite(x); }
inline bool allFinite(const Vec3& v) { return v.allFinite(); }
inline bool allFinite(const Quat& q) { return q.coeffs().allFinite(); }

}  // namespace inertia::fuzz
