// The team that runs parallel loops (core/parallel.hpp): every part runs once, a waiting
// thread sleeps instead of spinning (libgomp's team spun for 6-9 ms before it slept, so 2
// threads were 11 times slower than 1 when another process held a core), exceptions reach
// the caller, and a loop inside a loop runs on its thread alone.
#include <gtest/gtest.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

#include "tsubu/core/parallel.hpp"

using namespace tsubu;

namespace {

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

TEST(ParallelTeam, EveryPartRunsOnceOnItsOwnRange) {
  for (int threads : {2, 3, 8}) {
    std::vector<int> calls(static_cast<std::size_t>(threads), 0);
    const std::size_t n = 10007;
    std::vector<int> seen(n, 0);
    for (int round = 0; round < 50; ++round) {
      for_each_thread(threads, [&](int t) {
        ++calls[static_cast<std::size_t>(t)];
        const auto [begin, end] = static_range(n, t, threads);
        for (std::size_t i = begin; i < end; ++i) ++seen[i];
      });
    }
    for (int c : calls) EXPECT_EQ(c, 50) << threads;
    for (int s : seen) ASSERT_EQ(s, 50) << threads;
  }
}

// The caller waits 100 ms for a part that sleeps (as a thread does that shares its core with
// another process): it sleeps too, using well under a millisecond of its core.
TEST(ParallelTeam, AWaitingThreadSleepsInsteadOfSpinning) {
  for_each_thread(2, [](int) {});  // the worker exists
  const double before = thread_cpu_seconds();
  const auto start = std::chrono::steady_clock::now();
  for_each_thread(2, [](int t) {
    if (t == 1) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  });
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(100));
  EXPECT_LT(thread_cpu_seconds() - before, 0.002) << "the caller spun while it waited";
}

TEST(ParallelTeam, AnExceptionReachesTheCallerAfterEveryPartEnded) {
  std::atomic<int> ended{0};
  EXPECT_THROW(for_each_thread(4,
                               [&](int t) {
                                 ++ended;
                                 if (t == 2) throw std::runtime_error("part 2");
                               }),
               std::runtime_error);
  EXPECT_EQ(ended.load(), 4);
  // The team still works.
  std::vector<int> parts(4, 0);
  for_each_thread(4, [&](int t) { parts[static_cast<std::size_t>(t)] = t; });
  EXPECT_EQ(std::accumulate(parts.begin(), parts.end(), 0), 6);
}

TEST(ParallelTeam, ALoopInsideALoopRunsOnItsThreadAlone) {
  std::vector<std::vector<int>> inner(3);
  for_each_thread(3, [&](int t) {
    for_each_thread(2, [&](int u) { inner[static_cast<std::size_t>(t)].push_back(u); });
  });
  for (const auto& v : inner) EXPECT_EQ(v, (std::vector<int>{0, 1}));
}
