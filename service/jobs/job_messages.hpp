#pragma once
// The job manager's words (BatchJobs): new job ids and the sentences its answers and records
// carry when a job's results are incomplete, the shared store is behind or slow, a cancel waits
// for an owner that does not answer, or the owner was paused. Kept apart from the JSON handling so
// that each sentence is written once and read in one place.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "jobs/job_store.hpp"

namespace slosh::service {

/// How long and how many finished jobs a replica keeps (config batch_job_ttl_s, batch_jobs_kept,
/// batch_jobs_bytes), named by the 404 of a job it does not know.
struct JobKeepBounds {
  double ttl_s{};
  std::size_t kept{};
  std::size_t bytes{};
};

/// Throws the answer for job `id` whose record `lookup` did not yield (damaged or missing):
/// 503 (unavailable) when its stored state is damaged, the store cannot be reached, was emptied a
/// moment ago or still holds the job's other keys (its owner publishes it again); else 404
/// naming `bounds`.
[[noreturn]] void refuse_missing_record(JobStore& store, const std::string& id,
                                        const JobStore::RecordLookup& lookup,
                                        const JobKeepBounds& bounds);

/// A job id: 128 random bits as 32 hex digits (not guessable from another job's id).
[[nodiscard]] std::string new_job_id();

/// The warning of a replica whose --replica-id another live replica uses on the same Redis.
[[nodiscard]] std::string duplicate_replica_id_text(const std::string& replica);

/// "row 5", "rows 5, 6 and 9" (at most 10 named, then how many more).
[[nodiscard]] std::string row_list(const std::vector<std::size_t>& rows);

/// The 503 of a table whose rows [first, last] (1-based) the store holds `readable` of: which are
/// missing (lost) and which damaged (not a result row of their index).
[[nodiscard]] std::string rows_problem_text(const std::string& id, std::size_t readable,
                                            std::size_t first, std::size_t last,
                                            const std::vector<std::size_t>& missing,
                                            const std::vector<std::size_t>& damaged);

/// The failure of a job taken over from its silent owner when the shared store (Redis) answered
/// without parts of it (emptied or evicted meanwhile): `recipes_lost` recipes of its table and
/// the rows `rows_lost` (1-based) its record counted; the first `kept` rows of `total` stay.
[[nodiscard]] std::string lost_job_text(std::size_t recipes_lost,
                                        const std::vector<std::size_t>& rows_lost, std::size_t kept,
                                        std::size_t total);

/// The 503 of a read of rows [first, last] (1-based) that the store did not answer (`failure`
/// names the store and why, e.g. its timeout).
[[nodiscard]] std::string rows_unread_text(const std::string& id, std::size_t first,
                                           std::size_t last, const std::string& failure);

/// The 409 of results.csv / .jsonl of a job that ended `state` (cancelled, failed; `message` its
/// reason, may be empty) with `done` of `total` rows: the table is incomplete, and how to ask
/// for the done rows (`path`: the download path).
[[nodiscard]] std::string incomplete_results_text(const std::string& id, const std::string& state,
                                                  std::size_t done, std::size_t total,
                                                  const std::string& message,
                                                  const std::string& path);

/// Why another replica's job whose record in the shared store is `record_age_ms` old is alive
/// all the same: its owner renewed its heartbeat `heartbeat_age_ms` ago, but its record and rows
/// since are held on that replica (the shared store refuses or fails its writes).
[[nodiscard]] std::string store_behind_text(std::int64_t record_age_ms,
                                            std::int64_t heartbeat_age_ms);
/// The same for a job shared out to the replicas (batch_job_spread = "replicas"): no replica
/// holds rows of it; the items whose rows the store refused are solved again once it takes them.
[[nodiscard]] std::string shared_behind_text(std::int64_t record_age_ms,
                                             std::int64_t heartbeat_age_ms);

/// Why the record of a shared job answered by the replica that accepted it is its last view:
/// the shared store cannot be asked now.
[[nodiscard]] std::string owner_view_text();

/// The 503 of the results of such a job: its rows are not all in the shared store.
[[nodiscard]] std::string results_behind_text(const std::string& id, const std::string& why);

/// The note of a job that was done when its cancel was read: `note` (its note so far, may be
/// empty) with the late cancel said after it.
[[nodiscard]] std::string late_cancel_note(const std::string& note);
/// The note of another replica's job whose record has not been rewritten for `record_age_ms`,
/// past batch_job_stale_s = `stale_s`, which this replica reads as failed in `left` unless the
/// owner writes again (or, `taken_over`, a helper takes the job over) first.
[[nodiscard]] std::string silent_owner_text(std::int64_t record_age_ms, double stale_s,
                                            std::chrono::milliseconds left, bool taken_over);

/// What a DELETE accepted for another replica's job says about when it takes effect: the owner's
/// record is `record_age_ms` old; `heartbeat_age_ms` < 0 when its heartbeat is unknown or old;
/// `taken_over`: a silent owner's job is taken over by another replica at stale_s / 2
/// (batch_job_spread = "helpers") rather than read as failed at stale_s.
[[nodiscard]] std::string remote_cancel_text(std::int64_t record_age_ms,
                                             std::int64_t heartbeat_age_ms, double stale_s,
                                             bool taken_over);

/// The message of a job that stopped failed because its rows passed `max_bytes`
/// (batch_jobs_bytes) after `done` of `total` recipes.
[[nodiscard]] std::string too_large_text(std::size_t max_bytes, std::size_t done,
                                         std::size_t total);

/// The error of a shared job's item that `takes` replicas took and none stored (each stopped,
/// crashed or was cut off while solving it): recorded failed, naming batch_job_max_takes.
[[nodiscard]] std::string dead_item_text(std::size_t takes, std::size_t max_takes);

/// The note of a job whose replica did not run for `gap_s` (paused or starved) and carried on.
[[nodiscard]] std::string resumed_note(double gap_s, double stale_s);

}  // namespace slosh::service
