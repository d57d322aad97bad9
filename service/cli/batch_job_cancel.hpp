#pragma once
// What `slosh batch --server` does with its job when the run stops (Ctrl-C, a failed job): cancel
// it unless it has finished, and keep the rows the service finished, within a few seconds even
// when the replica that runs it does not answer.

#include <chrono>
#include <string>

#include "cli/batch_job_calls.hpp"
#include "cli/batch_row_sink.hpp"
#include "cli/http_client.hpp"

namespace slosh::service::batch_cli {

/// Deadline of each call of the stop (reading the record, the DELETE, the rows): a replica that
/// is paused costs this much per call, not the progress polls' longer deadline.
constexpr std::chrono::seconds kStopCallTimeout{2};
/// How long the stop tries to have the job's DELETE accepted and to see the job end (calls that
/// get no answer, or 503/502/504, are repeated until then). The rows of a job seen ending are
/// then fetched within kStopCallTimeout more per try, for at most as long again.
constexpr std::chrono::seconds kStopBudget{5};

/// How a stop ended, for the message after "batch job <id> ".
struct StopOutcome {
  /// "had finished (N rows written)", "cancelled (N rows written)", "failed ...", or what is known
  /// when the cancel could not be seen through (refused, or asked with no answer: the job id to
  /// check and the call to send).
  std::string text;
  /// Whether the job is known to have ended (done, cancelled or failed).
  bool ended{false};
};

/// After a stop: cancels `job` unless its record says it has finished (a DELETE would forget the
/// rows of a finished job), waits up to kStopBudget for it to end, and writes the rows it finished
/// to `sink` (results.jsonl; a service that keeps the rows of a cancelled job for `?partial=1`
/// only is asked again with it). A record the service answers but cannot give (503 throughout,
/// 404) sends no DELETE; a service that does not answer at all (a paused replica) gets the DELETE
/// anyway. Never throws for the service's answers; the rows written so far stay.
[[nodiscard]] StopOutcome stop_job(HttpClient& client, const RemoteJob& job, RowSink& sink);

}  // namespace slosh::service::batch_cli
