#include "worker_pool.hpp"

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

bool WorkerPool::try_submit(std::function<void()> task) {
  {
    std::lock_guard lock(mutex_);
    if (!accepting_ || queue_.size() >= capacity_) return false;
    if (queue_.empty() && busy_ == 0) last_progress_ = std::chrono::steady_clock::now();
    queue_.push_back(std::move(task));
  }
  has_task_.notify_one();
  return true;
}

bool WorkerPool::submit_wait(std::function<void()> task) {
  {
    std::unique_lock lock(mutex_);
    has_room_.wait(lock, [this] { return !accepting_ || queue_.size() < capacity_; });
    if (!accepting_) return false;
    if (queue_.empty() && busy_ == 0) last_progress_ = std::chrono::steady_clock::now();
    queue_.push_back(std::move(task));
  }
  has_task_.notify_one();
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
  return queue_.size();
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
      has_task_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping and drained
      task = std::move(queue_.front());
      queue_.pop_front();
      ++busy_;
    }
    has_room_.notify_one();
    bool failed = false;
    try {
      task();  // tasks catch their own exceptions; this keeps the worker alive if one does not
    } catch (...) {
      failed = true;
    }
    std::lock_guard lock(mutex_);
    --busy_;
    if (failed) ++task_errors_;
    last_progress_ = std::chrono::steady_clock::now();
  }
}

std::chrono::steady_clock::duration WorkerPool::stalled_for() const {
  std::lock_guard lock(mutex_);
  if (queue_.empty() && busy_ == 0) return std::chrono::steady_clock::duration::zero();
  return std::chrono::steady_clock::now() - last_progress_;
}

std::uint64_t WorkerPool::task_errors() const {
  std::lock_guard lock(mutex_);
  return task_errors_;
}

}  // namespace slosh::service
