#pragma once
// Ctrl-C in `slosh batch --server`: a flag the run looks at between calls, so that a job the
// service accepted is cancelled in an orderly way rather than left running.

#include <chrono>
#include <csignal>

namespace slosh::service::batch_cli {

/// True once SIGINT arrived while an InterruptFlag lived; never cleared, so that a Ctrl-C at any
/// moment after the handler is in place is seen.
[[nodiscard]] bool interrupt_requested();

/// Notes Ctrl-C from now on (the flag of interrupt_requested()), keeping SIGINT's action at this
/// moment for restore_interrupts(). `slosh` calls it before anything else of its own runs, so
/// that `batch --server` sees an interrupt from the process's first instant.
void note_interrupts();

/// SIGINT's action back to what note_interrupts() found; an interrupt that came meanwhile is
/// raised again, so the process ends as that action would have ended it (nothing when SIGINT was
/// ignored).
void restore_interrupts();

/// SIGINT (Ctrl-C) sets the flag of interrupt_requested() while this lives; the previous action
/// comes back after. Installed first thing in server mode, before the table is read: an
/// interrupt from then on can only stop the run in an orderly way (a job the service accepted is
/// cancelled).
class InterruptFlag {
 public:
  InterruptFlag();
  ~InterruptFlag();
  InterruptFlag(const InterruptFlag&) = delete;
  InterruptFlag& operator=(const InterruptFlag&) = delete;

 private:
  struct sigaction previous_ {};
};

/// Sleeps `wait` in slices, so that Ctrl-C ends it at once.
void sleep_unless_interrupted(std::chrono::milliseconds wait);

}  // namespace slosh::service::batch_cli
