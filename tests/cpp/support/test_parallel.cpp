// The parallel loop that replaced OpenMP in the core: every index once, errors reach the caller.
#include "support/parallel.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace shadecut::detail {
namespace {

// One thread runs the whole loop as one range; several take at most a chunk at a time.
TEST(ParallelRanges, VisitsEveryIndexOnceInRangesOfAtMostTheChunk) {
  for (const int threads : {1, 2, 5}) {
    for (const int count : {0, 1, 7, 16, 17, 1000}) {
      std::vector<std::atomic<int>> visits(static_cast<std::size_t>(count));
      std::atomic<int> widest{0};
      parallel_ranges(count, 16, threads, [&](int begin, int end) {
        widest = std::max(widest.load(), end - begin);
        for (int i = begin; i < end; ++i) ++visits[std::size_t(i)];
      });
      for (int i = 0; i < count; ++i) EXPECT_EQ(visits[std::size_t(i)], 1) << i << " of " << count << ", " << threads;
      if (threads > 1) {
        EXPECT_LE(widest, 16);
      }
    }
  }
}

TEST(ParallelRanges, UsesSeveralThreadsWhenAskedAndOneWhenNot) {
  auto threads_seen = [](int threads) {
    std::mutex mutex;
    std::set<std::thread::id> ids;
    parallel_for(64, 1, threads, [&](int) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      const std::lock_guard<std::mutex> lock(mutex);
      ids.insert(std::this_thread::get_id());
    });
    return ids;
  };
  const std::set<std::thread::id> one = threads_seen(1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(*one.begin(), std::this_thread::get_id());
  EXPECT_GT(threads_seen(3).size(), 1u);
}

TEST(ParallelRanges, RethrowsTheBodysErrorAfterEveryThreadStopped) {
  std::atomic<int> running{0};
  EXPECT_THROW(parallel_ranges(1000, 1, 4,
                               [&](int begin, int) {
                                 ++running;
                                 if (begin == 10) throw std::runtime_error("pixel 10");
                                 --running;
                               }),
               std::runtime_error);
  EXPECT_EQ(running, 1);  // only the throwing body never finished: the others had all returned
}

// A loop in a loop's body, and loops of two callers at once: each still visits every index once.
TEST(ParallelRanges, LoopsInsideLoopsAndSideBySideEachVisitEveryIndex) {
  std::vector<std::atomic<int>> visits(64 * 64);
  parallel_for(64, 1, 2, [&](int row) { parallel_for(64, 4, 2, [&](int col) { ++visits[std::size_t(row * 64 + col)]; }); });
  auto side = [&](int offset) {
    for (int repeat = 0; repeat < 50; ++repeat)
      parallel_for(32 * 64, 16, 2, [&](int i) { ++visits[std::size_t(offset + i)]; });
  };
  std::thread other(side, 32 * 64);
  side(0);
  other.join();
  for (const auto& count : visits) EXPECT_EQ(count, 51);
}

TEST(ThreadCountScope, SetsTheDefaultForItsLifetimeOnThisThreadOnly) {
  const int outside = default_thread_count();
  EXPECT_GE(outside, 1);
  {
    const ThreadCountScope scope(3);
    EXPECT_EQ(default_thread_count(), 3);
    int other_thread = 0;
    std::thread([&] { other_thread = default_thread_count(); }).join();
    EXPECT_EQ(other_thread, outside);
    const ThreadCountScope unchanged(0);
    EXPECT_EQ(default_thread_count(), 3);
  }
  EXPECT_EQ(default_thread_count(), outside);
}

// The threads of this process, as the kernel lists them.
int process_thread_count() {
  int count = 0;
  for ([[maybe_unused]] const auto& task : std::filesystem::directory_iterator("/proc/self/task")) ++count;
  return count;
}

// A call asking for 64 threads left 64 asleep for the rest of the process; the pool now keeps at most
// one thread fewer than the cores.
TEST(ParallelRanges, KeepsNoMoreThreadsThanTheCoresAfterALoopAskingForMore) {
  parallel_for(64, 1, 2, [](int) {});  // the pool exists, with what a small loop needs
  const int before = process_thread_count();
  std::atomic<int> visits{0};
  parallel_for(64, 1, 64, [&](int) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ++visits;
  });
  EXPECT_EQ(visits, 64);
  const int cores = std::max(1, int(std::thread::hardware_concurrency()));
  EXPECT_LE(process_thread_count(), before + cores - 1);
  // The pool still runs loops on several threads afterwards.
  std::mutex mutex;
  std::set<std::thread::id> ids;
  parallel_for(64, 1, 64, [&](int) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const std::lock_guard<std::mutex> lock(mutex);
    ids.insert(std::this_thread::get_id());
  });
  EXPECT_GT(ids.size(), 1u);
}

}  // namespace
}  // namespace shadecut::detail
