#include "engine/worker_pool.hpp"

#include <algorithm>

namespace slosh::service {

WorkerPool::WorkerPool(std::size_t workers, std::size_t queue_capacity)
    : capacity_(std::max<std::size_t>(1, queue_capacity)) {
  workers = std::max<std::size_t>(1, workers);
  threads_.reserve(workers);
  try {
    for (std::size_t i = 0; i < workers; ++i) threads_.emplace_back([this] { run(); });
  } catch (...) {
    // The system refused a thread (std::system_error): the started ones end before the
    // exception leaves (a joinable std::thread destroyed would end the process).
    stop_and_join();
    throw;
  }
}

WorkerPool::~WorkerPool() {
  stop_and_join();
}

void WorkerPool::stop_and_join() {
  {
    std::lock_guard lock(mutex_);
    accepting_ = false;
    stopping_ = true;
  }
  has_task_.notify_all();
  has_room_.notify_all();
  for (std::thread& t : threads_) t.join();
  threads_.clear();
}

void WorkerPool::push(std::unique_lock<std::mutex>& lock, std::function<void()> task,
                      TaskPriority priority) {
  if (idle()) last_progress_ = std::chrono::steady_clock::now();
  queue_of(priority).push_back(std::move(task));
  lock.unlock();
  has_task_.notify_one();
}

bool WorkerPool::has_room_locked(TaskPriority priority) const {
  // A task an idle worker is about to take is not waiting: it does not count against the queue
  // (else a burst of exactly workers + queue tasks on an idle pool would see one refused before
  // the woken workers take theirs). Idle workers take interactive tasks first, so a background
  // task counts only the idle workers the interactive ones leave.
  const std::size_t idle = threads_.size() > busy_ ? threads_.size() - busy_ : 0;
  if (priority == TaskPriority::kInteractive) return interactive_.size() < capacity_ + idle;
  const std::size_t left = idle > interactive_.size() ? idle - interactive_.size() : 0;
  return background_.size() < capacity_ + left;
}

bool WorkerPool::try_submit(std::function<void()> task, TaskPriority priority) {
  std::unique_lock lock(mutex_);
  if (!accepting_ || !has_room_locked(priority)) return false;
  push(lock, std::move(task), priority);
  return true;
}

bool WorkerPool::submit_wait(std::function<void()> task, TaskPriority priority) {
  std::unique_lock lock(mutex_);
  has_room_.wait(lock, [&] { return !accepting_ || has_room_locked(priority); });
  if (!accepting_) return false;
  push(lock, std::move(task), priority);
  return true;
}

void WorkerPool::stop_accepting() {
  {
    std::lock_guard lock(mutex_);
    accepting_ = false;
  }
  has_room_.notify_all();
}

std::size_t WorkerPool::queue_depth() const {
  std::lock_guard lock(mutex_);
  return interactive_.size() + background_.size();
}

std::size_t WorkerPool::queue_depth(TaskPriority priority) const {
  std::lock_guard lock(mutex_);
  return priority == TaskPriority::kInteractive ? interactive_.size() : background_.size();
}

std::uint64_t WorkerPool::started(TaskPriority priority) const {
  std::lock_guard lock(mutex_);
  return priority == TaskPriority::kInteractive ? started_interactive_ : started_background_;
}

std::size_t WorkerPool::busy() const {
  std::lock_guard lock(mutex_);
  return busy_;
}

void WorkerPool::run() {
  for (;;) {
    std::function<void()> task;
    {
      std::unique_lock lock(mutex_);
      has_task_.wait(lock,
                     [this] { return stopping_ || !interactive_.empty() || !background_.empty(); });
      // Interactive first: a background task runs only when no interactive one waits.
      const bool interactive = !interactive_.empty();
      std::deque<std::function<void()>>& queue = interactive ? interactive_ : background_;
      if (queue.empty()) return;  // stopping and drained
      task = std::move(queue.front());
      queue.pop_front();
      ++(interactive ? started_interactive_ : started_background_);
      ++busy_;
    }
    has_room_.notify_all();  // waiters of either priority
    bool failed = false;
    try {
      task();  // tasks catch their own exceptions; this keeps the worker alive if one does not
    } catch (...) {
      failed = true;
    }
    {
      std::lock_guard lock(mutex_);
      --busy_;
      if (failed) ++task_errors_;
      last_progress_ = std::chrono::steady_clock::now();
    }
    has_room_.notify_all();  // an idle worker is room too (has_room_locked)
  }
}

std::chrono::steady_clock::duration WorkerPool::stalled_for() const {
  std::lock_guard lock(mutex_);
  if (idle()) return std::chrono::steady_clock::duration::zero();
  return std::chrono::steady_clock::now() - last_progress_;
}

std::uint64_t WorkerPool::task_errors() const {
  std::lock_guard lock(mutex_);
  return task_errors_;
}

}  // namespace slosh::service
