#include "http/stop_signals.hpp"

#include <pthread.h>

#include <ctime>
#include <utility>

#include "http/malloc_tuning.hpp"

namespace slosh::service {

StopSignals::StopSignals() {
  sigemptyset(&signals_);
  sigaddset(&signals_, SIGINT);
  sigaddset(&signals_, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals_, nullptr);
}

void StopSignals::join() {
  if (!waiter_.joinable()) return;
  finished_ = true;
  pthread_kill(waiter_.native_handle(), SIGTERM);  // wakes the wait if no signal came
  waiter_.join();
}

void StopSignals::start(std::function<void(int)> on_stop) {
  waiter_ = std::thread([this, on_stop = std::move(on_stop)] {
    int signal_number = -1;
    while (signal_number < 0) {
      const timespec period{5, 0};
      signal_number = sigtimedwait(&signals_, nullptr, &period);
      if (signal_number < 0) trim_freed_memory();
    }
    if (!finished_) on_stop(signal_number);
  });
}

}  // namespace slosh::service
