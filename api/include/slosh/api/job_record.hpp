#pragma once
// The record of a batch job (POST /v1/batches, SPEC §13) on the server side: what the replica
// running it knows (JobStatus), rendered as the stored record, and a record read back from the
// job store (JobRecord), typed, with what an answer adds to it.
//
// {"id", "state": "queued"|"running"|"done"|"cancelled"|"failed", "format": "csv"|"jsonl",
//  "view": "full"|"compact"|null, "progress": {"done", "total", "failed", "rate_per_s", "eta_s"},
//  "created_at", "started_at", "finished_at", "updated_at" (ISO 8601 UTC, null until then),
//  "updated_unix_ms", "message" (why it failed or was cancelled; null), "note" (e.g. the replica
//  running it was paused and carried on; null), "cancel_requested",
//  "results_csv", "results_jsonl" (the download paths), and for a job shared out to the
//  replicas "shares": {"<replica>": rows it stored}}
// Records written by earlier versions have the same members and are read alike.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/batch_job_reply.hpp"
#include "slosh/api/plan_table_row.hpp"

namespace slosh::api {

/// The state of a job as its owner knows it.
struct JobStatus {
  std::string id;
  JobState state{JobState::kQueued};
  std::string format{"csv"};  ///< of the results download: "csv" or "jsonl"
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
  /// A job shared out to the replicas (batch_job_spread = "replicas"): the rows each replica
  /// stored, by replica name, rendered as "shares": {"<replica>": rows}; empty (no member) for a
  /// job one replica runs.
  std::vector<std::pair<std::string, std::size_t>> shares;
  /// A job helped by other replicas (batch_job_spread = "helpers"): items whose plans they solved
  /// ahead of the stored rows (`done`), counted in "solved", the rate and the ETA until stored.
  std::size_t solved_ahead{0};
};

/// The state named `name` ("queued", ...); nullopt for any other text.
[[nodiscard]] std::optional<JobState> job_state_named(std::string_view name);

/// "2026-11-24T23:55:01.250Z".
[[nodiscard]] std::string iso_time(std::int64_t unix_ms);

/// The record of `status` written at `now_ms` (rate and ETA from the time since it started), as
/// stored and answered (JSON text).
[[nodiscard]] std::string job_record_text(const JobStatus& status, std::int64_t now_ms);

/// A record read back from the job store: the members the service decides on, typed, and the
/// whole record, which only the functions below change and render.
struct JobRecord {
  JobState state{JobState::kQueued};
  std::size_t done{0};
  std::size_t total{0};
  /// When its owner wrote it [ms since the Unix epoch]; 0 when it says not.
  std::int64_t updated_unix_ms{0};
  bool cancel_requested{false};
  /// Why it failed or was cancelled; empty when the record says none.
  std::string message;
  /// Whether mark_unshared has said that the shared store is behind the owner, and why.
  bool unshared{false};
  std::string unshared_reason;
  nlohmann::json document;
};

/// The record in `text`; nullopt when it is not a job record (not a JSON object, no known
/// "state", no whole "progress.done" and "progress.total").
[[nodiscard]] std::optional<JobRecord> parse_job_record(std::string_view text);

/// Marks a queued or running record failed (its owner stopped rewriting it) with `message`: no
/// rate, no ETA.
void mark_failed(JobRecord& record, const std::string& message);
/// Adds "unshared": {"rows" (null when `rows` is not given), "reason"}: the shared store lacks
/// some of the job's rows or its latest record.
void mark_unshared(JobRecord& record, std::optional<std::size_t> rows, const std::string& reason);
/// Sets "cancel_requested": true.
void mark_cancel_requested(JobRecord& record);
/// Sets "note": what happened besides the job's state.
void add_note(JobRecord& record, const std::string& note);
/// Adds "cancel_note": when the owner will see a cancel asked through another replica.
void add_cancel_note(JobRecord& record, const std::string& note);
/// Adds "deleted": true (the answer of DELETE for a finished job).
void mark_deleted(JobRecord& record);
/// The status a record was written from (id, state, format, view, progress, times to the
/// millisecond, note, cancel_requested, shares): what a replica that takes over a running job
/// from its silent owner carries on from.
[[nodiscard]] JobStatus job_status_of(const JobRecord& record);
/// Adds "results": {"offset", "limit", "rows", "next_offset" (null after the last stored row),
/// "partial" (fewer rows stored than the job's total)}, `rows` being the page from `offset`.
void add_results(JobRecord& record, std::size_t offset, std::size_t limit,
                 const std::vector<PlanTableRow>& rows);
/// The record as answered (JSON text).
[[nodiscard]] std::string job_record_text(const JobRecord& record);

/// The stored result row `text` of the table's row `number` (1-based): an object naming its row
/// and its status, as the job runner writes it; nullopt when it is not one (damaged in the
/// shared store, e.g. "{}").
[[nodiscard]] std::optional<PlanTableRow> parse_result_row(std::string_view text,
                                                           std::size_t number);

}  // namespace slosh::api
