// Internal: workers that live for a whole step (Box2D v3's solver stages, on TBB's threads).
//
// A step is written as a sequence on the calling thread (the main worker). Where a stage has
// independent work, the main worker posts it as `count` items cut into blocks; every worker,
// the main one included, claims blocks with a compare-and-swap on one atomic word until none
// is left, and the main worker waits for the last block before it goes on. Helper workers
// spin between stages and sleep on a futex when the main worker's serial work lasts longer,
// so a stage costs a few cache-line transfers rather than a fork and join of TBB tasks. The main
// worker can run every block alone: a helper that TBB starts late, or never, only joins later
// stages, so nothing waits on it.
//
// Items of a stage must be independent (they write disjoint data); then the result is the
// same whatever the number of workers and whichever worker ran which block.
#pragma once

#include <tbb/task_arena.h>

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>
#include <type_traits>
#include <utility>

namespace inertia::detail {

class StepWorkers {
 public:
  /// Runs `driver(workers)` on the calling thread with the arena's threads as helpers (none
  /// when `arena` is null or has one thread: then every stage runs in sequence).
  template <class Driver>
  static void run(tbb::task_arena* arena, Driver&& driver) {
    StepWorkers w;
    w.start(arena, &callDriver<std::remove_reference_t<Driver>>, &driver);
  }

  /// Workers taking part, the main one included (1 in sequence).
  int threadCount() const { return threads_; }

  /// Calls f(begin, end) over [0, count) in blocks of `grain` items (the last may be shorter)
  /// on every worker, and returns when all are done; in sequence, or when count <= grain,
  /// f(0, count) once. Items must be independent.
  template <class F>
  void parallelFor(std::size_t count, std::size_t grain, F&& f) {
    if (count == 0) return;
    if (grain == 0) grain = 1;
    if (threads_ <= 1 || count <= grain) {
      f(std::size_t(0), count);
      return;
    }
    struct Ctx {
      F* f;
      std::size_t count, grain;
    } ctx{&f, count, grain};
    const std::size_t blocks = (count + grain - 1) / grain;
    post(
        [](void* p, std::uint32_t block) {
          const Ctx& c = *static_cast<const Ctx*>(p);
          const std::size_t begin = std::size_t(block) * c.grain;
          const std::size_t end = begin + c.grain < c.count ? begin + c.grain : c.count;
          (*c.f)(begin, end);
        },
        &ctx, static_cast<std::uint32_t>(blocks));
  }

  /// parallelFor with a grain that gives each worker about `perWorker` blocks (at least
  /// `minGrain` items each): for items whose cost does not depend on how they are grouped.
  template <class F>
  void parallelFor(std::size_t count, F&& f, std::size_t minGrain = 64, int perWorker = 4) {
    const std::size_t parts = std::size_t(threads_) * std::size_t(perWorker);
    std::size_t grain = (count + parts - 1) / parts;
    if (grain < minGrain) grain = minGrain;
    parallelFor(count, grain, std::forward<F>(f));
  }

 private:
  using BlockFn = void (*)(void*, std::uint32_t);
  using DriverFn = void (*)(void*, StepWorkers&);

  template <class D>
  static void callDriver(void* d, StepWorkers& w) {
    (*static_cast<D*>(d))(w);
  }

  StepWorkers() = default;
  void start(tbb::task_arena* arena, DriverFn driver, void* ctx);
  void post(BlockFn fn, void* ctx, std::uint32_t blocks);
  void helperLoop();
  // Claims and runs blocks of stage `epoch` while any is left.
  void runBlocks(std::uint32_t epoch);

  static constexpr std::uint32_t kExit = 0xffffffffu;    // the epoch that ends the helpers
  static constexpr std::uint32_t kClosed = 0xffffffffu;  // a next block past any stage's count

  int threads_ = 1;
  std::uint32_t epoch_ = 0;  // the main worker's count of posted stages
  // Stage epoch in the high 32 bits, next unclaimed block in the low ones.
  alignas(64) std::atomic<std::uint64_t> claim_{0};
  // The posted stage: written by the main worker before it publishes the epoch in claim_.
  std::atomic<BlockFn> fn_{nullptr};
  std::atomic<void*> ctx_{nullptr};
  std::atomic<std::uint32_t> blocks_{0};
  alignas(64) std::atomic<std::uint32_t> done_{0};
  // The last posted epoch. Idle helpers sleep on sleep_ until it changes: a condition variable
  // with its mutex, not std::atomic::wait, whose notify in Debian 12's libstdc++ (GCC 12) was
  // seen to lose a wakeup (a helper asleep on an epoch already past, the step never ending).
  alignas(64) std::atomic<std::uint32_t> posted_{0};
  std::mutex sleepMutex_;
  std::condition_variable sleep_;
  void publish(std::uint32_t epoch);
  // The first exception a block threw, on whichever worker; rethrown by the main worker when
  // the stage is done.
  std::atomic<bool> failed_{false};
  std::exception_ptr error_;
};

}  // namespace inertia::detail
