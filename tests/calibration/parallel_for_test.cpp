// calibration/parallel_for.hpp: every index once, whatever the threads; a task's exception
// reaches the caller after the others ran; calls nest and run from several threads at once
// without deadlock; two threads asked for are two threads.
#include "calibration/parallel_for.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

namespace tofcomp::calibration {
namespace {

// Generous bound for a wait that only a missing thread could exceed.
constexpr auto kMeetingTimeout = std::chrono::seconds(60);

TEST(ParallelFor, RunsEveryIndexOnceOnAnyNumberOfThreads) {
  for (const int threads : {1, 2, 3, 8}) {
    std::vector<std::atomic<int>> runs(997);
    parallel_for(static_cast<int>(runs.size()), threads, [&](int i) { ++runs[static_cast<std::size_t>(i)]; });
    for (std::size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(runs[i].load(), 1) << threads << " " << i;
  }
  int calls = 0;
  parallel_for(0, 2, [&](int) { ++calls; });
  EXPECT_EQ(calls, 0);
}

TEST(ParallelFor, TheFirstFailureReachesTheCallerAfterTheOthersRan) {
  for (const int threads : {1, 2}) {
    std::atomic<int> ran{0};
    try {
      parallel_for(50, threads, [&](int i) {
        ++ran;
        if (i == 7) throw std::runtime_error("task 7 failed");
      });
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "task 7 failed");
    }
    EXPECT_EQ(ran.load(), 50) << threads;
  }
}

// Two tasks that can only end together: each waits for the other to start.
TEST(ParallelFor, TwoThreadsAskedForRunTwoTasksAtOnce) {
  std::mutex mutex;
  std::condition_variable arrived;
  int present = 0;
  bool met = true;
  parallel_for(2, 2, [&](int) {
    std::unique_lock<std::mutex> lock(mutex);
    ++present;
    arrived.notify_all();
    if (!arrived.wait_for(lock, kMeetingTimeout, [&] { return present == 2; })) met = false;
  });
  EXPECT_TRUE(met);
}

// Tasks that call parallel_for themselves (a fold's fit striping its sweeps), from two callers
// at once: every inner index runs once and nothing waits forever.
TEST(ParallelFor, NestedCallsFromSeveralThreadsComplete) {
  constexpr int kOuter = 6;
  constexpr int kInner = 40;
  std::vector<std::atomic<int>> runs(2 * kOuter * kInner);
  const auto caller = [&](int which) {
    parallel_for(kOuter, 2, [&](int outer) {
      parallel_for(kInner, 2, [&](int inner) {
        ++runs[static_cast<std::size_t>((which * kOuter + outer) * kInner + inner)];
      });
    });
  };
  std::thread other(caller, 1);
  caller(0);
  other.join();
  for (std::size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(runs[i].load(), 1) << i;
}

TEST(ParallelFor, RunnerUsesTheThreadsAskedFor) {
  const core::ParallelFor run = parallel_runner(2);
  std::vector<std::atomic<int>> runs(300);
  run(static_cast<int>(runs.size()), [&](int i) { ++runs[static_cast<std::size_t>(i)]; });
  for (std::size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(runs[i].load(), 1) << i;
  EXPECT_EQ(thread_count(3), 3);
  EXPECT_GE(thread_count(0), 1);
}

}  // namespace
}  // namespace tofcomp::calibration
