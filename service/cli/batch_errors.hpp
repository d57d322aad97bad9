#pragma once
// The ways a `slosh batch` run stops (the caller prints the message and exits kExitFailure, or
// kExitInterrupted after Ctrl-C).

#include <stdexcept>

namespace slosh::service::batch_cli {

/// Stops the run (server unreachable, output not writable): exit kExitFailure.
struct BatchAbort : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The service did not answer a call at all (refused, timed out), as opposed to answering an
/// error: a started job's poll waits and asks again rather than stopping the run.
struct ServiceUnreachable : BatchAbort {
  using BatchAbort::BatchAbort;
};

/// Thrown by wait_for_job on Ctrl-C: the job is stopped and its finished rows saved by the caller.
struct BatchInterrupted : BatchAbort {
  using BatchAbort::BatchAbort;
};

/// Thrown by wait_for_job when the service stopped answering for kJobUnreachableLimit: the job
/// is left alone (it may still finish; a DELETE could not reach it anyway).
struct JobUnreachable : BatchAbort {
  using BatchAbort::BatchAbort;
};

}  // namespace slosh::service::batch_cli
