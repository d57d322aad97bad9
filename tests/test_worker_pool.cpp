// The solve worker pool: bounded queue, contained task failures, progress for /readyz.

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <future>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "engine/worker_pool.hpp"
#include "http/connection_pool.hpp"
#include "support/sanitizers.hpp"

namespace slosh::service {
namespace test_worker_pool {

using namespace std::chrono_literals;

// A task that throws used to end its worker thread (WorkerPool::run ran tasks
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

// /readyz did not notice a pool that makes no progress.
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

// A batch larger than the queue waits for room (submit_wait) while workers finish.
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

// An interactive task queued behind background (batch job) tasks runs first. The one
// worker is held by a latch while three background tasks and then one interactive task are
// queued; once released, the order of the runs is recorded.
TEST(WorkerPool, AnInteractiveTaskRunsBeforeQueuedBackgroundTasks) {
  WorkerPool pool(1, 8);
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  std::promise<void> holding;
  ASSERT_TRUE(pool.try_submit([gate, &holding] {
    holding.set_value();
    gate.wait();
  }));
  holding.get_future().wait();  // the worker is busy: everything below waits in the queues
  std::mutex m;
  std::vector<std::string> order;
  auto record = [&](std::string name) {
    return [&, name] {
      const std::lock_guard lock(m);
      order.push_back(name);
    };
  };
  for (const char* name : {"b1", "b2", "b3"}) {
    ASSERT_TRUE(pool.try_submit(record(name), TaskPriority::kBackground));
  }
  ASSERT_TRUE(pool.try_submit(record("i1"), TaskPriority::kInteractive));
  EXPECT_EQ(pool.queue_depth(TaskPriority::kBackground), 3u);
  EXPECT_EQ(pool.queue_depth(TaskPriority::kInteractive), 1u);
  EXPECT_EQ(pool.queue_depth(), 4u);
  release.set_value();
  for (int i = 0; i < 10000 && pool.started(TaskPriority::kBackground) < 3; ++i) {
    std::this_thread::sleep_for(1ms);
  }
  for (int i = 0; i < 10000 && pool.busy() > 0; ++i) std::this_thread::sleep_for(1ms);
  const std::lock_guard lock(m);
  EXPECT_EQ(order, (std::vector<std::string>{"i1", "b1", "b2", "b3"}));
  EXPECT_EQ(pool.started(TaskPriority::kInteractive), 2u);  // the latch task and i1
  EXPECT_EQ(pool.started(TaskPriority::kBackground), 3u);
}

// Background tasks have their own queue, so a full background queue leaves the
// interactive room (and its 503) as it was: interactive overload is refused at the same depth.
TEST(WorkerPool, BackgroundTasksDoNotTakeTheInteractiveQueueRoom) {
  WorkerPool pool(1, 2);
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  std::promise<void> holding;
  ASSERT_TRUE(pool.try_submit([gate, &holding] {
    holding.set_value();
    gate.wait();
  }));
  holding.get_future().wait();
  ASSERT_TRUE(pool.try_submit([] {}, TaskPriority::kBackground));
  ASSERT_TRUE(pool.try_submit([] {}, TaskPriority::kBackground));
  EXPECT_FALSE(pool.try_submit([] {}, TaskPriority::kBackground));  // its own queue is full
  EXPECT_TRUE(pool.try_submit([] {}));
  EXPECT_TRUE(pool.try_submit([] {}));
  EXPECT_FALSE(pool.try_submit([] {}));  // the interactive queue holds 2: the 3rd is refused
  release.set_value();
}

// Regression: a std::system_error from starting a connection thread (e.g. under
// `ulimit -v`) left ConnectionPool::enqueue, then the HTTP library's accept loop, and ended the
// process. The connection goes to the refusing thread instead (its requests are answered 503).
TEST(ConnectionPool, AThreadTheSystemRefusesSendsTheConnectionToTheRefusingThread) {
  std::atomic<int> started{0};
  std::atomic<bool> refuse{false};
  ConnectionPool pool(4, [&](std::function<void()> body) {
    if (refuse)
      throw std::system_error(std::make_error_code(std::errc::resource_unavailable_try_again));
    ++started;
    return std::thread(std::move(body));
  });
  EXPECT_EQ(started, 1);  // the refusing thread
  // The system refuses the connection's thread: the refusing thread runs the connection.
  refuse = true;
  std::promise<bool> first;
  EXPECT_NO_THROW(pool.enqueue([&first] { first.set_value(ConnectionPool::refusing()); }));
  auto refused = first.get_future();
  ASSERT_EQ(refused.wait_for(10s), std::future_status::ready);
  EXPECT_TRUE(refused.get());
  EXPECT_EQ(pool.refused(), 1u);
  EXPECT_EQ(pool.threads(), 0u);
  // Threads can be started again: the next connection gets one of its own.
  refuse = false;
  std::promise<bool> second;
  pool.enqueue([&second] { second.set_value(ConnectionPool::refusing()); });
  auto served = second.get_future();
  ASSERT_EQ(served.wait_for(10s), std::future_status::ready);
  EXPECT_FALSE(served.get());
  EXPECT_EQ(pool.refused(), 1u);
  EXPECT_EQ(pool.threads(), 1u);
  EXPECT_EQ(started, 2);
  pool.shutdown();
}

// A pool whose refusing thread cannot be started does not start (the server reports it).
TEST(ConnectionPool, NoRefusingThreadMeansNoPool) {
  EXPECT_THROW(ConnectionPool(4,
                              [](std::function<void()>) -> std::thread {
                                throw std::system_error(std::make_error_code(
                                    std::errc::resource_unavailable_try_again));
                              }),
               std::system_error);
}

// Worker threads the system refuses (here: the address space limited to what the process maps
// plus 16 MiB, two thread stacks): the started ones are joined and the std::system_error
// propagates, where destroying their joinable std::thread objects ended the process.
// Starts 64 workers with the address space limited to what the process maps plus 16 MiB (two
// thread stacks); exits 3 when the pool reports the refusal, 0 when it starts them all.
[[noreturn]] void start_workers_in_a_tight_address_space() {
  std::ifstream status("/proc/self/status");
  std::string line;
  rlim_t mapped = 0;
  while (std::getline(status, line)) {
    if (line.rfind("VmSize:", 0) == 0) mapped = std::stoull(line.substr(7)) * 1024;
  }
  rlimit limit{};
  ::getrlimit(RLIMIT_AS, &limit);
  const rlimit tight{mapped + (rlim_t{16} << 20), limit.rlim_max};
  ::setrlimit(RLIMIT_AS, &tight);
  try {
    const WorkerPool pool(64, 4);
  } catch (const std::system_error&) {
    std::_Exit(3);
  }
  std::_Exit(0);
}

TEST(WorkerPoolDeathTest, AWorkerTheSystemRefusesIsAnErrorNotAnAbort) {
  // AddressSanitizer's own allocations (its fake stacks) abort in a tight address space before
  // the worker pool can refuse: the limit would test the sanitizer.
  SLOSH_SKIP_WHEN_SANITIZED(
      "an address-space limit under AddressSanitizer aborts in its allocator");
  EXPECT_EXIT(start_workers_in_a_tight_address_space(), ::testing::ExitedWithCode(3), "");
}

}  // namespace test_worker_pool
}  // namespace slosh::service
