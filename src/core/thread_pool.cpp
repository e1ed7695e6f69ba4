#include "inertia/core/thread_pool.h"

#include "core/thread_pool_impl.h"
#include "inertia/core/error.h"

namespace inertia {

ThreadPool::ThreadPool(int threads) {
  require(threads >= 0, "ThreadPool: threads must be >= 0 (0: one per core)");
  impl_ = std::make_unique<Impl>(threads);
}
ThreadPool::~ThreadPool() = default;
ThreadPool::ThreadPool(ThreadPool&&) noexcept = default;
ThreadPool& ThreadPool::operator=(ThreadPool&&) noexcept = default;

int ThreadPool::threadCount() const { return impl_->arena.max_concurrency(); }

}  // namespace inertia
