#include "step_workers.h"

#include <tbb/info.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <chrono>
#include <exception>
#include <thread>
#include <utility>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace inertia::detail {

namespace {

// Pauses before a waiting worker yields its core: tens of microseconds (a pause takes 10 to
// 150 cycles, by processor), more than the gap between two solver stages.
constexpr int kSpins = 2000;

// How long an idle helper stays awake (pausing, then yielding its core) before it sleeps, when
// the workers are no more than the cores: longer than the main worker's serial stages within a
// step, since a sleeping helper wakes tens of microseconds late and misses the stages that follow.
// Measured on the 820-box pyramid at 2 threads: with 2,000 pauses (about 0.1 ms here) and then
// sleep, the helper slept 3.6 times a step and the step took 2.49 ms; staying awake, 0.01 times
// and 1.93 ms.
constexpr std::chrono::microseconds kIdleAwake{1000};

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

std::uint32_t epochOf(std::uint64_t word) { return std::uint32_t(word >> 32); }
std::uint32_t unitsOf(std::uint64_t word) { return std::uint32_t(word); }

// Where worker w of n starts in a stage of `units` units (Box2D v3's b2GetWorkerStartIndex):
// the first unit of its contiguous share, or none when there are fewer units than workers.
bool shareStart(int worker, int workers, std::uint32_t units, std::uint32_t& start) {
  const auto w = std::uint32_t(worker), n = std::uint32_t(workers);
  if (units <= n) {
    start = w;
    return w < units;
  }
  const std::uint32_t per = units / n, rest = units % n;
  start = per * w + (w < rest ? w : rest);
  return true;
}

}  // namespace

void StepWorkers::start(tbb::task_arena* arena, DriverFn driver, void* ctx) {
  const int n = arena ? arena->max_concurrency() : 1;
  if (n <= 1) {
    driver(ctx, *this);
    return;
  }
  threads_ = n;
  cores_ = tbb::info::default_concurrency();  // honours the affinity mask
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
    publish(std::uint64_t(kExit) << 32);
    group.wait();
    if (error) std::rethrow_exception(error);
  });
}

void StepWorkers::post(UnitFn fn, void* ctx, std::uint32_t units) {
  // Every unit of the last stage has run (post waited for them), so no helper can claim one
  // under the last epoch while the description changes.
  posted_.fn.store(fn, std::memory_order_release);
  posted_.ctx.store(ctx, std::memory_order_release);
  done_.store(0, std::memory_order_relaxed);
  const std::uint64_t word = (std::uint64_t(++epoch_) << 32) | units;
  publish(word);
  runUnits(word, 0);
  int spins = 0;
  while (done_.load(std::memory_order_acquire) != units) backoff(spins);
  // A block that threw on any worker: the stage is over (its units all counted), so the
  // exception goes on from the main worker, which ends the step.
  if (failed_.exchange(false, std::memory_order_acq_rel))
    std::rethrow_exception(std::exchange(error_, nullptr));
}

// Publishes a stage and wakes the sleeping helpers. A helper counts itself in sleepers_ and
// tests the word under the mutex before it sleeps; the word is stored before sleepers_ is read
// here (both sequentially consistent), so either this sees the sleeper and notifies under the
// mutex, or the sleeper sees the new word and does not sleep.
void StepWorkers::publish(std::uint64_t word) {
  posted_.word.store(word, std::memory_order_seq_cst);
  if (sleepers_.load(std::memory_order_seq_cst) == 0) return;
  { const std::lock_guard<std::mutex> lock(sleepMutex_); }
  sleep_.notify_all();
}

void StepWorkers::helperLoop() {
  const int worker = nextWorker_.fetch_add(1, std::memory_order_relaxed);
  std::uint32_t seen = 0;
  for (;;) {
    std::uint64_t word = 0;
    int spins = 0;
    std::chrono::steady_clock::time_point idleSince{};
    // Spin through the gaps between stages and the main worker's serial stages; sleep when
    // the step has left the helpers idle for long (kIdleAwake), so an idle helper leaves its
    // core to others.
    while (epochOf(word = posted_.word.load(std::memory_order_acquire)) == seen) {
      if (spins < kSpins) {
        backoff(spins);
        continue;
      }
      const auto now = std::chrono::steady_clock::now();
      if (spins++ == kSpins) idleSince = now;
      // With more workers than cores, a helper awake takes a core from the serial stages.
      if (threads_ <= cores_ && now - idleSince < kIdleAwake) {
        std::this_thread::yield();
        continue;
      }
      std::unique_lock<std::mutex> lock(sleepMutex_);
      sleepers_.fetch_add(1, std::memory_order_seq_cst);
      sleep_.wait(lock,
                  [&] { return epochOf(posted_.word.load(std::memory_order_seq_cst)) != seen; });
      sleepers_.fetch_sub(1, std::memory_order_relaxed);
      spins = 0;
    }
    seen = epochOf(word);
    if (seen == kExit) return;
    tbb::this_task_arena::isolate([&] { runUnits(word, worker); });
  }
}

bool StepWorkers::claim(std::uint32_t unit, std::uint32_t epoch) {
  std::atomic<std::uint32_t>& c = claimed_[unit];
  std::uint32_t last = c.load(std::memory_order_relaxed);
  while (last < epoch)
    if (c.compare_exchange_weak(last, epoch, std::memory_order_acq_rel, std::memory_order_relaxed))
      return true;
  return false;
}

void StepWorkers::runUnits(std::uint64_t word, int worker) {
  const std::uint32_t epoch = epochOf(word), units = unitsOf(word);
  std::uint32_t start = 0;
  if (!shareStart(worker, threads_, units, start)) return;
  // The description, read after the word with acquire. If it is a later stage's, this stage
  // has ended (see post) and every claim below fails.
  const UnitFn fn = posted_.fn.load(std::memory_order_acquire);
  void* const ctx = posted_.ctx.load(std::memory_order_acquire);
  std::uint32_t ran = 0;
  auto runUnit = [&](std::uint32_t unit) {
    try {
      fn(ctx, unit);
    } catch (...) {
      if (!failed_.exchange(true, std::memory_order_acq_rel)) error_ = std::current_exception();
    }
    ++ran;
  };
  // Forward through the share and on (wrapping) until a claimed unit, then backward from the
  // share's start: a worker stops only at a unit another has taken, so every unit runs.
  for (std::uint32_t u = start; claim(u, epoch); u = u + 1 == units ? 0 : u + 1) runUnit(u);
  for (std::uint32_t u = start == 0 ? units - 1 : start - 1; claim(u, epoch);
       u = u == 0 ? units - 1 : u - 1)
    runUnit(u);
  // Once per worker and stage, not per unit: the count is a contended cache line.
  if (ran > 0) done_.fetch_add(ran, std::memory_order_release);
}

}  // namespace inertia::detail
