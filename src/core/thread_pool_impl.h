// Internal: the TBB arena behind a ThreadPool, for the library's parallel stages.
#pragma once

#include <tbb/task_arena.h>

#include "inertia/core/thread_pool.h"

namespace inertia {

struct ThreadPool::Impl {
  tbb::task_arena arena;
  explicit Impl(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}
};

}  // namespace inertia
