#pragma once
// The client side of the batch jobs API (`slosh batch --server`): the body that starts a job, the
// job record it polls, read into typed values, and the rows of its results.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace slosh::api {

/// Where a batch job is: queued and running are on their way; done, cancelled and failed are
/// final (the record no longer changes and its rows can be read).
enum class JobState { kQueued, kRunning, kDone, kCancelled, kFailed };

/// "queued", "running", "done", "cancelled", "failed".
[[nodiscard]] std::string_view to_string(JobState state);

/// Whether `state` is final (done, cancelled or failed).
[[nodiscard]] bool is_final(JobState state);

/// What a client follows of a job record (GET /v1/batches/{id}, the 202 of POST and the answer of
/// DELETE): its state, the rows done of the total, the message of a failed or cancelled job
/// (empty when none) and whether a cancel was asked.
struct JobProgress {
  JobState state{JobState::kQueued};
  std::size_t done{0};
  std::size_t total{0};
  std::string message;
  bool cancel_requested{false};
};

/// The record in `text`; nullopt when it is not a job record (not JSON, no known "state", no
/// whole "progress.done").
[[nodiscard]] std::optional<JobProgress> parse_job_progress(std::string_view text);

/// The "id" of the job record in `text` (the 202 of POST /v1/batches); nullopt when it has none.
[[nodiscard]] std::optional<std::string> parse_job_id(std::string_view text);

/// The body of POST /v1/batches for a table's text as read (`table_format`: csv, jsonl or json),
/// its rows asked as JSON lines, with the plan added to each row in `view` (full, compact) if
/// given.
[[nodiscard]] std::string job_body_text(std::string_view table, std::string_view table_format,
                                        const std::optional<std::string>& view);

}  // namespace slosh::api
