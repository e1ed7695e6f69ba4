// The threads a world steps with.
#pragma once

#include <memory>

namespace inertia {

/// A set of worker threads shared by the stages of a step: at most `threads` run at once
/// (0: one per core). The library's parallel stages run on it; results never depend on its
/// size. Wraps a oneTBB arena, which stays out of the public headers.
class ThreadPool {
 public:
  explicit ThreadPool(int threads = 0);
  ~ThreadPool();
  ThreadPool(ThreadPool&&) noexcept;
  ThreadPool& operator=(ThreadPool&&) noexcept;

  /// The most threads that work at once, the caller's included.
  int threadCount() const;

  struct Impl;  ///< Internal (src/core/thread_pool_impl.h).
  Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace inertia
