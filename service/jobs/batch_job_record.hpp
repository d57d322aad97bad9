#pragma once
// The record of a batch job (POST /v1/batches, SPEC §13): what GET /v1/batches/{id} answers
// besides the results. The job manager renders it into the JobStore; any replica reads it back.
//
// {"id", "state": "queued"|"running"|"done"|"cancelled"|"failed", "format": "csv"|"jsonl",
//  "view": "full"|"compact"|null, "progress": {"done", "total", "failed", "rate_per_s", "eta_s"},
//  "created_at", "started_at", "finished_at", "updated_at" (ISO 8601 UTC, null until then),
//  "updated_unix_ms", "message" (why it failed or was cancelled; null), "note" (e.g. the replica
//  running it was paused and carried on; null), "cancel_requested",
//  "results_csv", "results_jsonl" (the download paths)}

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace slosh::service {

/// The state of a job as its owner knows it.
struct JobStatus {
  std::string id;
  std::string state{"queued"};
  std::string format{"csv"};
  std::optional<std::string> view;
  std::size_t total{0};
  std::size_t done{0};    ///< rows finished (planned or in error), stored in item order
  std::size_t failed{0};  ///< rows in error among them
  std::int64_t created_ms{0};
  std::optional<std::int64_t> started_ms;
  std::optional<std::int64_t> finished_ms;
  std::string message;
  /// What happened to the job besides its state (e.g. its replica was paused); empty when none.
  std::string note;
  bool cancel_requested{false};
};

/// Milliseconds since the Unix epoch, now.
[[nodiscard]] std::int64_t unix_ms_now();
/// "2026-11-24T23:55:01.250Z".
[[nodiscard]] std::string iso_time(std::int64_t unix_ms);

/// The record of `status` written at `now_ms` (rate and ETA from the time since it started).
[[nodiscard]] nlohmann::json job_record(const JobStatus& status, std::int64_t now_ms);

/// Whether `state` is final (done, cancelled or failed).
[[nodiscard]] bool is_final_state(const std::string& state);

/// A record read back: a queued or running job whose owner has not rewritten it for more than
/// `stale_s` reads as failed ("the replica running it stopped"). Returns whether it was stale.
bool mark_if_stale(nlohmann::json& record, std::int64_t now_ms, double stale_s);

}  // namespace slosh::service
