// Loops over every core: each index once, the worker numbers in range, a throw carried back, and
// the thread count taken from DIGITIZER_THREADS.
#include "host/parallel/parallel_for.h"

#include <CppUTest/TestHarness.h>

#include <atomic>
#include <cstdlib>
#include <stdexcept>
#include <vector>

TEST_GROUP(ParallelFor) {
  void teardown() override { unsetenv("DIGITIZER_THREADS"); }
};

TEST(ParallelFor, VisitsEveryIndexOnceWithWorkersInRange) {
  setenv("DIGITIZER_THREADS", "4", 1);
  LONGS_EQUAL(4, dg::host::worker_count());
  std::vector<std::atomic<int>> seen(100000);
  std::atomic<bool> worker_in_range{true};
  dg::host::parallel_for(seen.size(), [&](size_t begin, size_t end, unsigned worker) {
    if (worker >= 4) worker_in_range = false;
    for (size_t i = begin; i < end; ++i) ++seen[i];
  }, 100);
  for (const auto& s : seen) LONGS_EQUAL(1, s.load());
  CHECK(worker_in_range);
}

TEST(ParallelFor, AShortLoopRunsOnTheCallerAlone) {
  setenv("DIGITIZER_THREADS", "8", 1);
  int calls = 0;  // not atomic: one caller, one call
  dg::host::parallel_for(10, [&](size_t begin, size_t end, unsigned worker) {
    ++calls;
    LONGS_EQUAL(0, begin);
    LONGS_EQUAL(10, end);
    LONGS_EQUAL(0, worker);
  }, 256);
  LONGS_EQUAL(1, calls);
  dg::host::parallel_for(0, [&](size_t, size_t, unsigned) { ++calls; });
  LONGS_EQUAL(1, calls);
}

TEST(ParallelFor, AThrowInAWorkerComesBackToTheCaller) {
  setenv("DIGITIZER_THREADS", "2", 1);
  std::atomic<size_t> done{0};
  try {
    dg::host::parallel_for(10000, [&](size_t begin, size_t end, unsigned) {
      if (begin <= 5000 && 5000 < end) throw std::runtime_error("chunk with 5000");
      done += end - begin;
    }, 100);
    FAIL("the throw was lost");
  } catch (const std::runtime_error& e) {
    STRCMP_EQUAL("chunk with 5000", e.what());
  }
  CHECK(done.load() < 10000);
}

TEST(ParallelFor, ABadThreadCountFallsBackToTheMachinesCores) {
  setenv("DIGITIZER_THREADS", "0", 1);
  CHECK(dg::host::worker_count() >= 1);
  setenv("DIGITIZER_THREADS", "two", 1);
  CHECK(dg::host::worker_count() >= 1);
  setenv("DIGITIZER_THREADS", "1", 1);
  LONGS_EQUAL(1, dg::host::worker_count());
}
