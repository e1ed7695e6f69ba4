// The step's workers (src/dynamics/step_workers.h): every item of a stage runs exactly once,
// a stage sees everything the stages before it wrote, whoever wrote it, and a step ends (its
// helpers exit) also when the driver throws.
#include "dynamics/step_workers.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

using inertia::detail::StepWorkers;

namespace {

// Each count and grain on 1, 2 and 4 threads (4 on a 2-core machine: more workers than cores
// must still finish), counting how often each item ran. In sequence a stage is one block.
TEST(StepWorkers, EveryItemRunsOnce) {
  for (int threads : {1, 2, 4}) {
    tbb::task_arena arena(threads);
    StepWorkers::run(&arena, [&](StepWorkers& w) {
      EXPECT_EQ(w.threadCount(), threads);
      for (std::size_t count : {0, 1, 7, 64, 1000, 100003}) {
        for (std::size_t grain : {1, 3, 64, 5000}) {
          std::vector<int> runs(count, 0);
          w.parallelFor(count, grain, [&](std::size_t first, std::size_t last) {
            if (threads > 1) {
              ASSERT_LE(last - first, grain);
            }
            for (std::size_t i = first; i < last; ++i) ++runs[i];
          });
          for (std::size_t i = 0; i < count; ++i)
            ASSERT_EQ(runs[i], 1) << "item " << i << " of " << count << ", grain " << grain << ", "
                                  << threads << " threads";
        }
      }
    });
  }
}

// A stage with a side job: the side job runs once and every item once, whatever the count,
// grain and number of threads, and a side job that throws ends the step.
TEST(StepWorkers, SideJobRunsOnceBesideTheBlocks) {
  for (int threads : {1, 2, 4}) {
    tbb::task_arena arena(threads);
    StepWorkers::run(&arena, [&](StepWorkers& w) {
      for (std::size_t count : {0, 1, 7, 1000, 100003}) {
        for (std::size_t grain : {1, 64, 5000}) {
          std::vector<int> runs(count, 0);
          int sides = 0;
          w.parallelForBeside([&] { ++sides; }, count, grain,
                              [&](std::size_t first, std::size_t last) {
                                for (std::size_t i = first; i < last; ++i) ++runs[i];
                              });
          ASSERT_EQ(sides, 1) << count << " items, grain " << grain << ", " << threads;
          for (std::size_t i = 0; i < count; ++i)
            ASSERT_EQ(runs[i], 1) << "item " << i << " of " << count << ", grain " << grain;
        }
      }
    });
    EXPECT_THROW(StepWorkers::run(&arena,
                                  [](StepWorkers& w) {
                                    w.parallelForBeside([] { throw std::runtime_error("side"); },
                                                        100, 1, [](std::size_t, std::size_t) {});
                                  }),
                 std::runtime_error)
        << threads << " threads";
  }
}

// A chain of stages, each reading what the stage before wrote in another order: item i of a
// stage adds item (i * 7919) % n of the last (written by any worker). The sums are those of
// the same chain in sequence; a stage that started before the last one's writes were visible,
// or a block run twice or under the wrong stage, would change them.
TEST(StepWorkers, StagesSeeTheWritesOfTheStagesBefore) {
  constexpr std::size_t n = 4096;
  constexpr int stages = 2000;
  auto chain = [&](tbb::task_arena* arena) {
    std::vector<std::uint64_t> a(n), b(n);
    std::iota(a.begin(), a.end(), std::uint64_t(1));
    StepWorkers::run(arena, [&](StepWorkers& w) {
      for (int s = 0; s < stages; ++s) {
        w.parallelFor(n, std::size_t(1) + std::size_t(s % 97),
                      [&](std::size_t first, std::size_t last) {
                        for (std::size_t i = first; i < last; ++i)
                          b[i] = a[i] + a[(i * 7919) % n] + 1;
                      });
        std::swap(a, b);
      }
    });
    return a;
  };
  const std::vector<std::uint64_t> sequence = chain(nullptr);
  tbb::task_arena two(2), four(4);
  EXPECT_EQ(chain(&two), sequence);
  EXPECT_EQ(chain(&four), sequence);
}

// Blocks that run TBB work of their own (a user's field that is itself parallel) finish: a
// worker waiting in its nested loop must not take up a helper that has not started, whose loop
// would only end with the step it waits in (the step hung before the waits were isolated).
TEST(StepWorkers, NestedTbbWorkInABlockDoesNotHang) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 3);
  for (int step = 0; step < 20; ++step) {
    tbb::task_arena arena(6);
    std::atomic<long> sum{0};
    StepWorkers::run(&arena, [&](StepWorkers& w) {
      for (int s = 0; s < 5; ++s)
        w.parallelFor(16, 1, [&](std::size_t, std::size_t) {
          tbb::parallel_for(
              tbb::blocked_range<int>(0, 16, 1),
              [&](const tbb::blocked_range<int>& r) {
                // Long enough that the waiting worker looks for other tasks meanwhile.
                std::this_thread::sleep_for(std::chrono::microseconds(50));
                sum += r.begin();
              },
              tbb::simple_partitioner());
        });
    });
    ASSERT_EQ(sum.load(), 5 * 16 * (15 * 16 / 2)) << "step " << step;
  }
}

// An exception from a block, on whichever worker runs it, ends the step once the stage is done
// and reaches the caller: no hang.
TEST(StepWorkers, BlockExceptionEndsTheStep) {
  for (int threads : {1, 2, 4}) {
    tbb::task_arena arena(threads);
    int stagesAfter = 0;
    EXPECT_THROW(StepWorkers::run(&arena,
                                  [&](StepWorkers& w) {
                                    w.parallelFor(1000, 1, [](std::size_t first, std::size_t last) {
                                      if (first <= 777 && 777 < last)
                                        throw std::runtime_error("block");
                                    });
                                    ++stagesAfter;
                                  }),
                 std::runtime_error)
        << threads << " threads";
    EXPECT_EQ(stagesAfter, 0);
  }
}

// An exception from the driver reaches the caller after the helpers have left: no hang, and
// the arena works for the next step.
TEST(StepWorkers, DriverExceptionEndsTheStep) {
  tbb::task_arena arena(2);
  EXPECT_THROW(StepWorkers::run(&arena,
                                [](StepWorkers& w) {
                                  w.parallelFor(100, 1, [](std::size_t, std::size_t) {});
                                  throw std::runtime_error("driver");
                                }),
               std::runtime_error);
  int ran = 0;
  StepWorkers::run(&arena, [&](StepWorkers& w) {
    std::vector<int> hits(10, 0);
    w.parallelFor(10, 1, [&](std::size_t first, std::size_t) { hits[first] = 1; });
    ran = std::accumulate(hits.begin(), hits.end(), 0);
  });
  EXPECT_EQ(ran, 10);
}

}  // namespace
