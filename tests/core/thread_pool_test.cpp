// ThreadPool: the thread count it promises, and a clear error for a negative one.
#include "inertia/core/thread_pool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <thread>

#include "inertia/core/error.h"

using namespace inertia;

TEST(ThreadPool, HoldsTheRequestedThreads) {
  EXPECT_EQ(ThreadPool(1).threadCount(), 1);
  EXPECT_EQ(ThreadPool(3).threadCount(), 3);
  // 0: one per core the process may use (at least one).
  const int all = ThreadPool(0).threadCount();
  EXPECT_GE(all, 1);
  EXPECT_LE(all, int(std::max(1u, std::thread::hardware_concurrency())));
  ThreadPool moved(ThreadPool(2));
  EXPECT_EQ(moved.threadCount(), 2);
}

TEST(ThreadPool, RejectsANegativeCount) {
  try {
    ThreadPool pool(-1);
    FAIL() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("threads must be >= 0"), std::string::npos);
  }
}
