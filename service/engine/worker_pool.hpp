#pragma once
// A fixed set of worker threads behind a bounded queue: the service's solves run here, so a burst
// of requests waits in a queue of known size (or is refused) instead of spawning work unbounded.
//
// Two priorities: a worker takes an interactive task (a plan an HMI waits for) whenever one is
// queued, and a background task (an item of a batch job, POST /v1/batches) only when no
// interactive task waits. Each priority has its own queue of `queue_capacity` tasks, so queued
// background work never takes the room that answers interactive overload with 503.

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

/// Which queue a task waits in: interactive tasks always run before background ones.
enum class TaskPriority { kInteractive, kBackground };

class WorkerPool {
 public:
  /// Starts `workers` threads (>= 1) with room for `queue_capacity` waiting tasks (>= 1). Throws
  /// std::system_error when the system refuses a thread (the started ones are joined first).
  WorkerPool(std::size_t workers, std::size_t queue_capacity);
  /// Finishes every queued and running task, then joins the threads.
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Queues `task` unless its priority's queue is full or the pool is stopping; false then. The
  /// queue is full when `queue_capacity` tasks of that priority wait beyond the ones the idle
  /// workers are about to take (so an idle pool admits workers + queue_capacity tasks at once).
  [[nodiscard]] bool try_submit(std::function<void()> task,
                                TaskPriority priority = TaskPriority::kInteractive);
  /// Queues `task`, waiting for room in its priority's queue; false when the pool is stopping.
  [[nodiscard]] bool submit_wait(std::function<void()> task,
                                 TaskPriority priority = TaskPriority::kInteractive);
  /// Stops accepting tasks; queued and running ones still finish.
  void stop_accepting();

  [[nodiscard]] std::size_t queue_depth() const;  ///< tasks waiting (both priorities)
  /// Tasks of `priority` waiting.
  [[nodiscard]] std::size_t queue_depth(TaskPriority priority) const;
  /// Tasks of `priority` started since the pool began.
  [[nodiscard]] std::uint64_t started(TaskPriority priority) const;
  [[nodiscard]] std::size_t busy() const;  ///< tasks running
  /// How long the pool has had work (queued or running) without finishing a task; zero while it
  /// is idle or has just finished one. A pool that makes no progress shows a growing figure.
  [[nodiscard]] std::chrono::steady_clock::duration stalled_for() const;
  /// Tasks that threw (they are contained: the worker carries on).
  [[nodiscard]] std::uint64_t task_errors() const;
  [[nodiscard]] std::size_t workers() const { return threads_.size(); }
  [[nodiscard]] std::size_t capacity() const { return capacity_; }

 private:
  void run();
  // Whether a task of `priority` may be queued now (the lock held).
  [[nodiscard]] bool has_room_locked(TaskPriority priority) const;
  // Queues `task` (the lock held, room checked) and wakes a worker.
  void push(std::unique_lock<std::mutex>& lock, std::function<void()> task, TaskPriority priority);
  std::deque<std::function<void()>>& queue_of(TaskPriority priority) {
    return priority == TaskPriority::kInteractive ? interactive_ : background_;
  }
  [[nodiscard]] bool idle() const {
    return interactive_.empty() && background_.empty() && busy_ == 0;
  }
  // Stops accepting, finishes every queued and running task, joins the threads.
  void stop_and_join();

  mutable std::mutex mutex_;
  std::condition_variable has_task_;
  std::condition_variable has_room_;
  std::deque<std::function<void()>> interactive_;
  std::deque<std::function<void()>> background_;
  std::uint64_t started_interactive_{0};
  std::uint64_t started_background_{0};
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
