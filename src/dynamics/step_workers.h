// Internal: workers that live for a whole step (Box2D v3's solver stages, on TBB's threads).
//
// A step is written as a sequence on the calling thread (the main worker). Where a stage has
// independent work, the main worker posts it as `count` items cut into blocks, and the blocks
// into at most kMaxUnits claim units. Every worker, the main one included, starts at its own
// share of the units (worker w of n at about unit w U / n) and claims units forward with a
// compare-and-swap on each unit's word, then backward from its share's start: as in Box2D v3's
// b2ExecuteStage, a worker finds the bodies of its share in its own cache in the next pass
// over the same constraints, and a late or slow worker's units are taken from its share's
// end. The main worker waits for the last unit before it goes on. Helper workers spin between
// stages and sleep on a condition variable when the main worker's serial work lasts longer,
// so a stage costs a few cache-line transfers rather than a fork and join of TBB tasks. The
// main worker can run every unit alone: a helper that TBB starts late, or never, only joins
// later stages, so nothing waits on it.
//
// Items of a stage must be independent (they write disjoint data); then the result is the
// same whatever the number of workers and whichever worker ran which block.
#pragma once

#include <tbb/task_arena.h>

#include <array>
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
    postBlocks(static_cast<NoSide*>(nullptr), count, grain, f);
  }

  /// parallelFor(count, grain, f) with side() run once beside the blocks, as a unit of the
  /// stage that the main worker starts with while the others take the blocks: serial work
  /// that shares no data with the blocks runs in their time. In sequence, side() first.
  template <class Side, class F>
  void parallelForBeside(Side&& side, std::size_t count, std::size_t grain, F&& f) {
    if (grain == 0) grain = 1;
    if (threads_ <= 1 || count == 0) {
      side();
      if (count > 0) f(std::size_t(0), count);
      return;
    }
    postBlocks(&side, count, grain, f);
  }

  /// A grain that gives each worker about `perWorker` blocks of at least `minGrain` items: for
  /// items whose cost does not depend on how they are grouped.
  std::size_t grainFor(std::size_t count, std::size_t minGrain = 64, int perWorker = 4) const {
    const std::size_t parts = std::size_t(threads_) * std::size_t(perWorker);
    const std::size_t grain = (count + parts - 1) / parts;
    return grain < minGrain ? minGrain : grain;
  }

  /// parallelFor with grainFor(count, minGrain, perWorker).
  template <class F>
  void parallelFor(std::size_t count, F&& f, std::size_t minGrain = 64, int perWorker = 4) {
    parallelFor(count, grainFor(count, minGrain, perWorker), std::forward<F>(f));
  }

 private:
  using UnitFn = void (*)(void*, std::uint32_t);
  using DriverFn = void (*)(void*, StepWorkers&);

  template <class D>
  static void callDriver(void* d, StepWorkers& w) {
    (*static_cast<D*>(d))(w);
  }

  // Claim units of one stage: enough for every worker's share and for stealing to balance,
  // few enough that a stage's claim words fit in a few cache lines.
  static constexpr std::uint32_t kMaxUnits = 256;
  static constexpr std::uint32_t kExit = 0xffffffffu;  // the epoch that ends the helpers

  struct NoSide {
    void operator()() const {}
  };

  // Posts f's blocks over [0, count) as one stage, preceded by (*side)() as unit 0 when side
  // is not null.
  template <class Side, class F>
  void postBlocks(Side* side, std::size_t count, std::size_t grain, F& f) {
    struct Ctx {
      Side* side;
      F* f;
      std::size_t count, grain, blocks;
      std::uint32_t first, units;  // first: the unit of block 0 (1 after a side job)
    } ctx{side, &f, count, grain, (count + grain - 1) / grain, side ? 1u : 0u, 0};
    const std::size_t most = kMaxUnits - ctx.first;
    ctx.units = static_cast<std::uint32_t>(ctx.blocks < most ? ctx.blocks : most);
    post(
        [](void* p, std::uint32_t unit) {
          const Ctx& c = *static_cast<const Ctx*>(p);
          if (unit < c.first) {
            (*c.side)();
            return;
          }
          // Unit first + u runs blocks [u B / U, (u + 1) B / U).
          const std::size_t u = unit - c.first;
          for (std::size_t block = u * c.blocks / c.units; block < (u + 1) * c.blocks / c.units;
               ++block) {
            const std::size_t begin = block * c.grain;
            (*c.f)(begin, begin + c.grain < c.count ? begin + c.grain : c.count);
          }
        },
        &ctx, ctx.first + ctx.units);
  }

  StepWorkers() = default;
  void start(tbb::task_arena* arena, DriverFn driver, void* ctx);
  void post(UnitFn fn, void* ctx, std::uint32_t units);
  void publish(std::uint64_t word);
  void helperLoop();
  // Claims and runs units of the stage of `word` (epoch and unit count), from worker's share.
  void runUnits(std::uint64_t word, int worker);
  bool claim(std::uint32_t unit, std::uint32_t epoch);

  int threads_ = 1;
  int cores_ = 1;            // the cores this process may run on
  std::uint32_t epoch_ = 0;  // the main worker's count of posted stages
  // The posted stage in one cache line: its epoch (high 32 bits) and unit count (low), which
  // the helpers spin on, and what runs a unit. The main worker writes fn_ and ctx_ only when
  // every unit of the last stage has run, so a helper that reads them late (a later stage's)
  // finds every unit of its own stage claimed, and runs nothing.
  struct alignas(64) Posted {
    std::atomic<std::uint64_t> word{0};
    std::atomic<UnitFn> fn{nullptr};
    std::atomic<void*> ctx{nullptr};
  } posted_;
  alignas(64) std::atomic<std::uint32_t> done_{0};  // units of the stage run
  // Per unit, the last epoch in which a worker claimed it: a worker of epoch e claims a unit
  // whose word is below e (epochs only grow, so a worker of an ended stage claims nothing).
  alignas(64) std::array<std::atomic<std::uint32_t>, kMaxUnits> claimed_{};
  alignas(64) std::atomic<int> nextWorker_{1};  // a helper's share index, on its first stage
  // Helpers asleep on sleep_ (a condition variable with its mutex, not std::atomic::wait,
  // whose notify in Debian 12's libstdc++ (GCC 12) was seen to lose a wakeup): the main worker
  // takes the mutex and notifies only when one is.
  std::atomic<int> sleepers_{0};
  std::mutex sleepMutex_;
  std::condition_variable sleep_;
  // The first exception a block threw, on whichever worker; rethrown by the main worker when
  // the stage is done.
  std::atomic<bool> failed_{false};
  std::exception_ptr error_;
};

}  // namespace inertia::detail
