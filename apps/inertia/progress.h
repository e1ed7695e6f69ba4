// Progress of a long `inertia run` or `inertia render` on the terminal: printed only when stderr
// is a terminal, so CI logs and pipes stay clean, at most five times a second and once at the end.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>

namespace inertia::app {

class Progress {
 public:
  /// `unit` names what is counted ("step", "frame"); it must outlive the Progress.
  Progress(bool enabled, std::int64_t total, const char* unit)
      : enabled_(enabled && isatty(STDERR_FILENO)), total_(total), unit_(unit) {}
  void update(std::int64_t done) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_).count() < 0.2 && done < total_) return;
    last_ = now;
    std::fprintf(stderr, "\r%s %lld/%lld (%.0f%%)", unit_, (long long)done, (long long)total_,
                 100.0 * double(done) / double(total_));
  }
  /// Clears the line.
  void finish() {
    if (enabled_) std::fprintf(stderr, "\r%*s\r", 40, "");
  }

 private:
  bool enabled_;
  std::int64_t total_;
  const char* unit_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace inertia::app
