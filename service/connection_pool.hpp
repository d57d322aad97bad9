#pragma once
// The HTTP connection threads: grown on demand up to a maximum, so idle keep-alive clients and
// slow senders each hold one thread without starving the others (the HTTP library serves one
// connection per thread for its whole life).

#include <httplib.h>

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace slosh::service {

class ConnectionPool : public httplib::TaskQueue {
 public:
  /// Up to `max_threads` (>= 1) threads, started as connections arrive and kept afterwards.
  explicit ConnectionPool(std::size_t max_threads);
  ~ConnectionPool() override;
  ConnectionPool(const ConnectionPool&) = delete;
  ConnectionPool& operator=(const ConnectionPool&) = delete;

  /// Runs `fn` (one connection) on an idle thread, a new one below the maximum, or queues it.
  void enqueue(std::function<void()> fn) override;
  /// Finishes the queued connections, then joins every thread.
  void shutdown() override;

  [[nodiscard]] std::size_t threads() const;

 private:
  void run();

  mutable std::mutex mutex_;
  std::condition_variable has_job_;
  std::deque<std::function<void()>> jobs_;
  std::vector<std::thread> threads_;
  std::size_t max_threads_;
  std::size_t idle_{0};
  bool shutdown_{false};
};

}  // namespace slosh::service
