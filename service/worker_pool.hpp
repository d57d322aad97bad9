#pragma once
// A fixed set of worker threads behind a bounded queue: the service's solves run here, so a burst
// of requests waits in a queue of known size (or is refused) instead of spawning work unbounded.

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace slosh::service {

class WorkerPool {
 public:
  /// Starts `workers` threads (>= 1) with room for `queue_capacity` waiting tasks (>= 1). Throws
  /// std::system_error when the system refuses a thread (the started ones are joined first).
  WorkerPool(std::size_t workers, std::size_t queue_capacity);
  /// Finishes every queued and running task, then joins the threads.
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Queues `task` unless the queue is full or the pool is stopping; false then.
  [[nodiscard]] bool try_submit(std::function<void()> task);
  /// Queues `task`, waiting for room; false when the pool is stopping.
  [[nodiscard]] bool submit_wait(std::function<void()> task);
  /// Stops accepting tasks; queued and running ones still finish.
  void stop_accepting();

  [[nodiscard]] std::size_t queue_depth() const;  ///< tasks waiting
  [[nodiscard]] std::size_t busy() const;         ///< tasks running
  /// How long the pool has had work (queued or running) without finishing a task; zero while it
  /// is idle or has just finished one. A pool that makes no progress shows a growing figure.
  [[nodiscard]] std::chrono::steady_clock::duration stalled_for() const;
  /// Tasks that threw (they are contained: the worker carries on).
  [[nodiscard]] std::uint64_t task_errors() const;
  [[nodiscard]] std::size_t workers() const { return threads_.size(); }
  [[nodiscard]] std::size_t capacity() const { return capacity_; }

 private:
  void run();
  // Stops accepting, finishes every queued and running task, joins the threads.
  void stop_and_join();

  mutable std::mutex mutex_;
  std::condition_variable has_task_;
  std::condition_variable has_room_;
  std::deque<std::function<void()>> queue_;
  std::vector<std::thread> threads_;
  std::size_t capacity_;
  std::size_t busy_{0};
  std::uint64_t task_errors_{0};
  // Last time a task finished, or work arrived at an idle pool.
  std::chrono::steady_clock::time_point last_progress_{std::chrono::steady_clock::now()};
  bool accepting_{true};
  bool stopping_{false};
};

}  // namespace slosh::service
