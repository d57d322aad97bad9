#include "http/connection_pool.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <exception>
#include <utility>

namespace slosh::service {

namespace {

thread_local bool refusing_thread = false;

// Runs a connection; the library catches its own exceptions, and a connection never takes a
// thread down.
void run_job(const std::function<void()>& job) {
  try {
    job();
  } catch (...) {
  }
}

}  // namespace

ConnectionPool::ConnectionPool(std::size_t max_threads, ThreadStarter start_thread)
    : start_thread_(start_thread
                        ? std::move(start_thread)
                        : [](std::function<void()> body) { return std::thread(std::move(body)); }),
      max_threads_(std::max<std::size_t>(1, max_threads)) {
  threads_.reserve(max_threads_);  // adding a started thread never allocates
  refuser_ = start_thread_([this] { run_refusals(); });
}

ConnectionPool::~ConnectionPool() {
  shutdown();
}

void ConnectionPool::enqueue(std::function<void()> fn) {
  bool refused = false;
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(fn));
    if (idle_ < jobs_.size() && threads_.size() < max_threads_) {
      try {
        threads_.push_back(start_thread_([this] { run(); }));
      } catch (const std::exception& e) {  // std::system_error (or std::bad_alloc)
        // No thread for this connection: the refusing thread answers it (503).
        refusals_.push_back(std::move(jobs_.back()));
        jobs_.pop_back();
        ++refused_;
        refused = true;
        spdlog::error(
            "cannot start a connection thread ({} running): {}; the connection is "
            "answered 503",
            threads_.size(), e.what());
      }
    }
  }
  if (refused) {
    has_refusal_.notify_one();
  } else {
    has_job_.notify_one();
  }
}

void ConnectionPool::shutdown() {
  std::vector<std::thread> threads;
  {
    std::lock_guard lock(mutex_);
    shutdown_ = true;
    threads.swap(threads_);
  }
  has_job_.notify_all();
  has_refusal_.notify_all();
  for (std::thread& t : threads) t.join();
  if (refuser_.joinable()) refuser_.join();
}

std::size_t ConnectionPool::threads() const {
  std::lock_guard lock(mutex_);
  return threads_.size();
}

std::uint64_t ConnectionPool::refused() const {
  std::lock_guard lock(mutex_);
  return refused_;
}

bool ConnectionPool::refusing() {
  return refusing_thread;
}

void ConnectionPool::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    ++idle_;
    has_job_.wait(lock, [this] { return shutdown_ || !jobs_.empty(); });
    --idle_;
    if (jobs_.empty()) return;  // shutting down and drained
    std::function<void()> job = std::move(jobs_.front());
    jobs_.pop_front();
    lock.unlock();
    run_job(job);
    lock.lock();
  }
}

void ConnectionPool::run_refusals() {
  refusing_thread = true;
  std::unique_lock lock(mutex_);
  for (;;) {
    has_refusal_.wait(lock, [this] { return shutdown_ || !refusals_.empty(); });
    if (refusals_.empty()) return;  // shutting down and drained
    std::function<void()> job = std::move(refusals_.front());
    refusals_.pop_front();
    lock.unlock();
    run_job(job);
    lock.lock();
  }
}

}  // namespace slosh::service
