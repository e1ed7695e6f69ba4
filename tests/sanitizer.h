// Whether the tests run under AddressSanitizer and UBSan (the asan preset: Debug at -O1, with
// the library's validation on). Its runs are about 30 times slower than the default preset's,
// so the few oracles that sweep thousands of samples check a fraction of them there: the
// sanitizers look for memory errors and undefined behaviour on the code paths taken, which a
// fraction of the samples takes as well, while the default and double presets check them all.
#pragma once

namespace inertia::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

/// `full` in the default and double presets, `sanitized` under the sanitizers.
constexpr int samplesFor(int full, int sanitized) { return kSanitized ? sanitized : full; }

}  // namespace inertia::test
