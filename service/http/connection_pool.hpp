#pragma once
// The HTTP connection threads: grown on demand up to a maximum, so idle keep-alive clients and
// slow senders each hold one thread without starving the others (the HTTP library serves one
// connection per thread for its whole life).
//
// When the system refuses a new thread (std::system_error, e.g. under `ulimit -v` or a thread
// limit), the connection is not lost and the process does not end (the exception
// escaped the accept loop and std::terminate aborted the server): it goes to the refusing thread,
// started with the pool, whose requests the service answers 503 with Retry-After (refusing()).

#include <httplib.h>

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace slosh::service {

class ConnectionPool : public httplib::TaskQueue {
 public:
  /// Starts a thread running `body` (the pool's threads); throws std::system_error when the
  /// system refuses one, as std::thread does.
  using ThreadStarter = std::function<std::thread(std::function<void()> body)>;

  /// Up to `max_threads` (>= 1) threads, started as connections arrive and kept afterwards, plus
  /// the refusing thread, started here (a std::system_error from it propagates: the server does
  /// not start). `start_thread` starts every thread (a test seam; default std::thread).
  explicit ConnectionPool(std::size_t max_threads, ThreadStarter start_thread = {});
  ~ConnectionPool() override;
  ConnectionPool(const ConnectionPool&) = delete;
  ConnectionPool& operator=(const ConnectionPool&) = delete;

  /// Runs `fn` (one connection) on an idle thread, a new one below the maximum, or queues it;
  /// when a new thread is needed and the system refuses it (any exception of `start_thread`), on
  /// the refusing thread. Never throws std::system_error.
  void enqueue(std::function<void()> fn) override;
  /// Finishes the queued connections, then joins every thread.
  void shutdown() override;

  [[nodiscard]] std::size_t threads() const;
  /// Connections handed to the refusing thread because a thread could not be started.
  [[nodiscard]] std::uint64_t refused() const;

  /// True on the refusing thread: the connection it serves could not get a thread of its own,
  /// and its requests are to be answered 503.
  [[nodiscard]] static bool refusing();

 private:
  void run();
  void run_refusals();

  mutable std::mutex mutex_;
  std::condition_variable has_job_;
  std::condition_variable has_refusal_;
  std::deque<std::function<void()>> jobs_;
  std::deque<std::function<void()>> refusals_;
  std::vector<std::thread> threads_;
  std::thread refuser_;
  ThreadStarter start_thread_;
  std::size_t max_threads_;
  std::size_t idle_{0};
  std::uint64_t refused_{0};
  bool shutdown_{false};
};

}  // namespace slosh::service
