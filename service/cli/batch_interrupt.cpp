#include "cli/batch_interrupt.hpp"

#include <thread>

namespace slosh::service::batch_cli {

namespace {

volatile std::sig_atomic_t interrupted = 0;
extern "C" void on_interrupt(int) {
  interrupted = 1;
}

// SIGINT's action when note_interrupts() replaced it.
struct sigaction found_action {};

void install(struct sigaction* previous) {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // a blocking HTTP call finishes; the flag is looked at after
  ::sigaction(SIGINT, &action, previous);
}

}  // namespace

bool interrupt_requested() {
  return interrupted != 0;
}

void note_interrupts() {
  install(&found_action);
}

void restore_interrupts() {
  ::sigaction(SIGINT, &found_action, nullptr);
  if (interrupted != 0) std::raise(SIGINT);
}

InterruptFlag::InterruptFlag() {
  install(&previous_);
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
