#include "cli/batch_interrupt.hpp"

#include <thread>

namespace slosh::service::batch_cli {

namespace {

volatile std::sig_atomic_t interrupted = 0;
extern "C" void on_interrupt(int) {
  interrupted = 1;
}

}  // namespace

bool interrupt_requested() {
  return interrupted != 0;
}

InterruptFlag::InterruptFlag() {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // a blocking HTTP call finishes; the flag is looked at after
  ::sigaction(SIGINT, &action, &previous_);
}

InterruptFlag::~InterruptFlag() {
  ::sigaction(SIGINT, &previous_, nullptr);
}

void sleep_unless_interrupted(std::chrono::milliseconds wait) {
  const auto until = std::chrono::steady_clock::now() + wait;
  while (!interrupted && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace slosh::service::batch_cli
