#pragma once
// SIGINT and SIGTERM for the server, taken by one thread outside any signal handler.

#include <signal.h>

#include <atomic>
#include <functional>
#include <thread>

namespace slosh::service {

/// SIGINT / SIGTERM, blocked in every thread from construction on (so first, before any thread is
/// started: the worker pool inherits the mask) and taken synchronously by one waiter thread, which
/// runs `on_stop` outside any signal handler. While it waits, the waiter trims freed memory every
/// few seconds (trim_freed_memory). The destructor wakes and joins the waiter.
class StopSignals {
 public:
  StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  ~StopSignals() { join(); }

  /// Starts the waiter; `on_stop` receives the signal's number.
  void start(std::function<void(int)> on_stop);
  /// Ends the waiter (idempotent): after this no stop runs.
  void join();
  [[nodiscard]] bool finished() const { return finished_; }

 private:
  sigset_t signals_{};
  std::atomic<bool> finished_{false};
  std::thread waiter_;
};

}  // namespace slosh::service
