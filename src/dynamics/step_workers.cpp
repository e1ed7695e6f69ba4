#include "step_workers.h"

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <exception>
#include <thread>
#include <utility>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace inertia::detail {

namespace {

// Pauses before a helper sleeps: tens of microseconds (a pause takes 10 to 150 cycles, by
// processor), more than the gap between two solver stages, less than a long serial stage such
// as the broad phase's tree update in a wave of reinsertions.
constexpr int kSpins = 2000;

// A short wait in a spin: pauses, then yields the core, so that a machine with more busy
// threads than cores does not starve.
void backoff(int& spins) {
  if (spins < kSpins) {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
    ++spins;
  } else {
    std::this_thread::yield();
  }
}

}  // namespace

void StepWorkers::start(tbb::task_arena* arena, DriverFn driver, void* ctx) {
  const int n = arena ? arena->max_concurrency() : 1;
  if (n <= 1) {
    driver(ctx, *this);
    return;
  }
  threads_ = n;
  arena->execute([&] {
    tbb::task_group group;
    std::exception_ptr error;
    try {
      for (int i = 1; i < n; ++i) group.run([this] { helperLoop(); });
      // Isolated: a thread that waits on TBB work inside the step (a stage that runs a
      // tbb::parallel_for of its own, a user's field) must not pick up a helper task that has
      // not started, whose loop would only end with the step it is waiting in.
      tbb::this_task_arena::isolate([&] { driver(ctx, *this); });
    } catch (...) {
      error = std::current_exception();
    }
    claim_.store(std::uint64_t(kExit) << 32, std::memory_order_release);
    publish(kExit);
    group.wait();
    if (error) std::rethrow_exception(error);
  });
}

void StepWorkers::post(BlockFn fn, void* ctx, std::uint32_t blocks) {
  // Close the last stage first (no block left to claim under its epoch), so that a helper
  // which reads part of this stage's description under the old epoch claims nothing: it reads
  // the description with acquire, which orders this store before its next look at claim_.
  claim_.store((std::uint64_t(epoch_) << 32) | kClosed, std::memory_order_relaxed);
  fn_.store(fn, std::memory_order_release);
  ctx_.store(ctx, std::memory_order_release);
  blocks_.store(blocks, std::memory_order_release);
  done_.store(0, std::memory_order_relaxed);
  const std::uint32_t epoch = ++epoch_;
  claim_.store(std::uint64_t(epoch) << 32, std::memory_order_release);
  publish(epoch);
  runBlocks(epoch);
  int spins = 0;
  while (done_.load(std::memory_order_acquire) != blocks) backoff(spins);
  // A block that threw on any worker: the stage is over (its blocks all counted), so the
  // exception goes on from the main worker, which ends the step.
  if (failed_.exchange(false, std::memory_order_acq_rel))
    std::rethrow_exception(std::exchange(error_, nullptr));
}

// Publishes an epoch and wakes the sleeping helpers. A helper tests the epoch under the mutex
// before it sleeps, and the epoch is stored before the mutex is taken here, so no helper can
// sleep on an epoch already past.
void StepWorkers::publish(std::uint32_t epoch) {
  posted_.store(epoch, std::memory_order_release);
  { const std::lock_guard<std::mutex> lock(sleepMutex_); }
  sleep_.notify_all();
}

void StepWorkers::helperLoop() {
  std::uint32_t seen = 0;
  for (;;) {
    std::uint32_t epoch = 0;
    int spins = 0;
    // Spin through the short gaps between stages; sleep through the main worker's long
    // serial stages (a futex), so an idle helper leaves its core to others.
    while ((epoch = posted_.load(std::memory_order_acquire)) == seen) {
      if (spins < kSpins) {
        backoff(spins);
      } else {
        std::unique_lock<std::mutex> lock(sleepMutex_);
        sleep_.wait(lock, [&] { return posted_.load(std::memory_order_acquire) != seen; });
      }
    }
    if (epoch == kExit) return;
    seen = epoch;
    tbb::this_task_arena::isolate([&] { runBlocks(epoch); });
  }
}

void StepWorkers::runBlocks(std::uint32_t epoch) {
  // The stage's description, read after the epoch was seen. If the main worker has moved on
  // to a later stage meanwhile, the claim below sees a different epoch and runs nothing.
  const BlockFn fn = fn_.load(std::memory_order_acquire);
  void* const ctx = ctx_.load(std::memory_order_acquire);
  const std::uint32_t blocks = blocks_.load(std::memory_order_acquire);
  std::uint64_t word = claim_.load(std::memory_order_acquire);
  std::uint32_t ran = 0;
  for (;;) {
    if (std::uint32_t(word >> 32) != epoch || std::uint32_t(word) >= blocks) break;
    if (claim_.compare_exchange_weak(word, word + 1, std::memory_order_acq_rel,
                                     std::memory_order_acquire)) {
      try {
        fn(ctx, std::uint32_t(word));
      } catch (...) {
        if (!failed_.exchange(true, std::memory_order_acq_rel)) error_ = std::current_exception();
      }
      ++ran;
      ++word;  // the expected word of the next claim; a failed exchange corrects it
    }
  }
  // Once per worker and stage, not per block: the count is a contended cache line.
  if (ran > 0) done_.fetch_add(ran, std::memory_order_release);
}

}  // namespace inertia::detail
