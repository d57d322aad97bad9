// The solve worker pool: bounded queue, contained task failures, progress for /readyz.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <stdexcept>
#include <thread>

#include "worker_pool.hpp"

namespace slosh::service {
namespace {

using namespace std::chrono_literals;

// Issue 14: a task that throws used to end its worker thread (WorkerPool::run ran tasks
// unguarded); the pool must carry on and count it.
TEST(WorkerPool, AThrowingTaskDoesNotTakeItsWorkerDown) {
  WorkerPool pool(1, 4);
  ASSERT_TRUE(pool.try_submit([] { throw std::runtime_error("boom"); }));
  ASSERT_TRUE(pool.try_submit([] { throw 42; }));
  std::promise<int> done;
  ASSERT_TRUE(pool.try_submit([&done] { done.set_value(7); }));
  auto f = done.get_future();
  ASSERT_EQ(f.wait_for(10s), std::future_status::ready);
  EXPECT_EQ(f.get(), 7);
  EXPECT_EQ(pool.task_errors(), 2u);
}

// Issue 14: /readyz did not notice a pool that makes no progress.
TEST(WorkerPool, StalledForGrowsWhileWorkIsStuckAndResetsOnProgress) {
  WorkerPool pool(1, 4);
  EXPECT_EQ(pool.stalled_for(), std::chrono::steady_clock::duration::zero());  // idle
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  ASSERT_TRUE(pool.try_submit([gate] { gate.wait(); }));
  std::this_thread::sleep_for(100ms);
  EXPECT_GE(pool.stalled_for(), 90ms);
  release.set_value();
  for (int i = 0; i < 1000 && pool.busy() > 0; ++i) std::this_thread::sleep_for(1ms);
  EXPECT_EQ(pool.stalled_for(), std::chrono::steady_clock::duration::zero());
}

// Issue 14: a batch larger than the queue waits for room (submit_wait) while workers finish.
TEST(WorkerPool, SubmitWaitQueuesMoreTasksThanTheQueueHolds) {
  WorkerPool pool(2, 2);
  std::atomic<int> ran{0};
  for (int i = 0; i < 50; ++i) {
    ASSERT_TRUE(pool.submit_wait([&ran] {
      std::this_thread::sleep_for(1ms);
      ++ran;
    }));
  }
  for (int i = 0; i < 5000 && ran < 50; ++i) std::this_thread::sleep_for(1ms);
  EXPECT_EQ(ran, 50);
}

}  // namespace
}  // namespace slosh::service
