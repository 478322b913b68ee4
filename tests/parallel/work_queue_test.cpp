#include "fricrom/work_queue.h"

#include <gtest/gtest.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>

namespace fricrom {
namespace {

TEST(WorkQueue, EveryPendingUnitRunsOnceAndFinishesOneAtATime) {
  for (int threads : {1, 2, 4}) {
    const std::vector<int> pending = {5, 1, 9, 3, 7, 0, 2, 8};
    std::vector<std::atomic<int>> runs(10);
    std::vector<int> order;
    std::atomic<int> inside{0};
    int overlap = 0;
    RunWorkUnits(
        pending, threads,
        [&](int i) {
          // Uneven costs, as FE points are, so the hand-out order and the finish order differ.
          std::this_thread::sleep_for(std::chrono::milliseconds(i % 3 == 0 ? 20 : 1));
          ++runs[i];
        },
        [&](int i) {
          if (++inside > 1) ++overlap;
          order.push_back(i);
          --inside;
        });
    for (int i = 0; i < 10; ++i) {
      const bool wanted = std::set<int>(pending.begin(), pending.end()).count(i) > 0;
      EXPECT_EQ(runs[i].load(), wanted ? 1 : 0) << "unit " << i << ", " << threads << " threads";
    }
    EXPECT_EQ(order.size(), pending.size());
    EXPECT_EQ(overlap, 0) << "finished() ran concurrently";
  }
}

TEST(WorkQueue, UsesSeveralThreadsWhenAsked) {
  std::mutex m;
  std::set<std::thread::id> ids;
  RunWorkUnits(
      {0, 1, 2, 3, 4, 5}, 2,
      [&](int) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        const std::lock_guard<std::mutex> g(m);
        ids.insert(std::this_thread::get_id());
      },
      [](int) {});
  EXPECT_EQ(ids.size(), 2u);
}

TEST(WorkQueue, FirstExceptionStopsTheHandOutAndIsRethrown) {
  for (int threads : {1, 2}) {
    std::atomic<int> started{0};
    std::vector<int> pending(100);
    for (int i = 0; i < 100; ++i) pending[i] = i;
    EXPECT_THROW(RunWorkUnits(
                     pending, threads,
                     [&](int i) {
                       ++started;
                       if (i == 3) throw std::runtime_error("unit 3 failed");
                       // Units take time, as real ones do: without it a second thread may finish
                       // all 100 before the failing one has reported (seen under load).
                       std::this_thread::sleep_for(std::chrono::milliseconds(1));
                     },
                     [](int) {}),
                 std::runtime_error);
    EXPECT_LT(started.load(), 100) << threads << " threads";
  }
}

TEST(WorkQueue, WorkerThreadsIsBoundedByTheUnits) {
  EXPECT_EQ(WorkerThreads(8, 3), 3);
  EXPECT_EQ(WorkerThreads(1, 50), 1);
  EXPECT_GE(WorkerThreads(0, 50), 1);
  EXPECT_EQ(WorkerThreads(4, 0), 1);
}

// The default follows the CPU affinity (what mpirun's binding or srun leaves a rank), not the
// machine's core count: pinned to one CPU, a run takes one thread.
TEST(WorkQueue, DefaultThreadsFollowTheAffinityMask) {
  cpu_set_t saved;
  CPU_ZERO(&saved);
  ASSERT_EQ(sched_getaffinity(0, sizeof saved, &saved), 0);
  EXPECT_EQ(UsableCores(), CPU_COUNT(&saved));
  EXPECT_LE(UsableCores(), static_cast<int>(std::thread::hardware_concurrency()));
  int first = 0;
  while (!CPU_ISSET(first, &saved)) ++first;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(first, &one);
  ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
  const int pinned = UsableCores(), threads = WorkerThreads(0, 50);
  ASSERT_EQ(sched_setaffinity(0, sizeof saved, &saved), 0);
  EXPECT_EQ(pinned, 1);
  EXPECT_EQ(threads, 1);
  EXPECT_EQ(WorkerThreads(3, 50), 3);  // an explicit request is kept
}

}  // namespace
}  // namespace fricrom
