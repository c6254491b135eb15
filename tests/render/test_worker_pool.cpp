// The worker pool (render/worker_pool.h): every index runs exactly once per job, on a slot below thread_count();
// parallel_for returns only once every task has finished; the pool really runs tasks at the same time on as many
// threads as it says; and it is reused job after job. Renders are bit-identical across thread counts, so a pool
// with a thread fewer, or one that returns early, would otherwise only show as slowness or as a rare torn frame.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "render/worker_pool.h"

namespace pt {
namespace {

TEST(WorkerPool, RunsEveryIndexOnceOnAValidSlot) {
  for (int threads : {1, 2, 3, 5}) {
    WorkerPool pool(threads);
    ASSERT_EQ(pool.thread_count(), threads);
    for (uint32_t count : {0u, 1u, 7u, 1000u}) {
      std::vector<std::atomic<int>> runs(count);
      std::atomic<bool> bad_slot{false};
      pool.parallel_for(count, [&](uint32_t i, int slot) {
        runs[i].fetch_add(1);
        if (slot < 0 || slot >= threads) bad_slot = true;
      });
      for (uint32_t i = 0; i < count; ++i) ASSERT_EQ(runs[i].load(), 1) << threads << " threads, index " << i;
      EXPECT_FALSE(bad_slot.load());
    }
  }
}

TEST(WorkerPool, ReturnsOnlyWhenEveryTaskHasFinished) {
  WorkerPool pool(3);
  for (int job = 0; job < 20; ++job) {
    std::atomic<int> finished{0};
    pool.parallel_for(6, [&](uint32_t i, int) {
      std::this_thread::sleep_for(std::chrono::microseconds(200 * (i % 3)));
      finished.fetch_add(1);
    });
    ASSERT_EQ(finished.load(), 6) << "job " << job;
  }
}

TEST(WorkerPool, RunsAsManyTasksAtOnceAsItHasThreads) {
  // Each task waits until all `threads` tasks have started: only a pool that runs them on that many threads at
  // once gets through (the wait gives up after 20 s so that a broken pool fails instead of hanging).
  for (int threads : {2, 4}) {
    WorkerPool pool(threads);
    std::mutex m;
    std::condition_variable cv;
    int started = 0;
    std::atomic<int> gave_up{0};
    std::vector<std::atomic<int>> slots(threads);
    pool.parallel_for(uint32_t(threads), [&](uint32_t, int slot) {
      slots[slot].fetch_add(1);
      std::unique_lock lock(m);
      ++started;
      cv.notify_all();
      if (!cv.wait_for(lock, std::chrono::seconds(20), [&] { return started == threads; })) gave_up.fetch_add(1);
    });
    EXPECT_EQ(gave_up.load(), 0) << threads << " threads";
    for (int s = 0; s < threads; ++s) EXPECT_EQ(slots[s].load(), 1) << "slot " << s;
  }
}

TEST(WorkerPool, ZeroThreadsMeansTheHardwareConcurrency) {
  WorkerPool pool(0);
  EXPECT_EQ(pool.thread_count(), int(std::max(1u, std::thread::hardware_concurrency())));
}

}  // namespace
}  // namespace pt
