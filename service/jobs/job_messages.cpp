#include "jobs/job_messages.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <random>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"

namespace slosh::service {

namespace {

// "12 s" (whole seconds from 10 s on), "0.4 s".
std::string seconds_text(double s) {
  return api::number_text(s >= 10.0 ? std::floor(s) : std::floor(s * 10.0) / 10.0) + " s";
}

std::string seconds_of_ms(std::int64_t ms) {
  return seconds_text(static_cast<double>(ms) / 1e3);
}

}  // namespace

std::string duplicate_replica_id_text(const std::string& replica) {
  return "another live replica uses the replica id '" + replica +
         "' on this Redis: their shares of batch jobs and their consumer names merge, and neither "
         "helps nor takes over the other's jobs; give each replica its own --replica-id";
}

std::string new_job_id() {
  static std::mutex m;
  static std::random_device device;
  static std::mt19937_64 bits(
      (static_cast<std::uint64_t>(device()) << 32U) ^ device() ^
      static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()));
  const std::lock_guard lock(m);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id;
  for (int word = 0; word < 2; ++word) {
    std::uint64_t v = bits();
    for (int i = 0; i < 16; ++i, v >>= 4U) id += kHex[v & 0xFU];
  }
  return id;
}

void refuse_missing_record(JobStore& store, const std::string& id,
                           const JobStore::RecordLookup& lookup, const JobKeepBounds& bounds) {
  const std::string shown = id.substr(0, 64);
  const auto unavailable = [&](const std::string& message) {
    throw api::ApiError(api::ErrorCode::kUnavailable, "id", message);
  };
  if (lookup.damaged) {
    unavailable("the stored state of batch job '" + shown +
                "' is damaged (its record in the shared job store, Redis, is not a job record): "
                "POST the job again");
  }
  if (!lookup.answered || !store.reachable()) {
    unavailable("batch job '" + shown +
                "' is not on this replica and the shared job store (Redis) cannot be reached now: "
                "retry later, or ask the replica that runs it");
  }
  if (store.recently_emptied()) {
    unavailable(
        "batch job '" + shown +
        "' is not on this replica and the shared job store (Redis) was emptied or "
        "restarted a moment ago: the replicas are publishing their jobs again, retry later");
  }
  const JobTraces traces = store.traces(id);
  if (traces == JobTraces::kRows) {
    // The record key alone is gone (evicted under maxmemory, or deleted) while the job's rows
    // are there: its owner publishes it again at its next heartbeat. A 404 would lose a DELETE.
    unavailable("batch job '" + shown +
                "' is not on this replica and its record is missing from the shared job store "
                "(Redis) although its results are there (evicted or deleted): the replica that "
                "runs it publishes it again, retry later");
  }
  if (traces == JobTraces::kLiveCancel) {
    // Only its cancel flag and its heartbeat: the replica running it beats it within
    // batch_job_stale_s and writes its record back at that heartbeat; once the heartbeat has
    // expired, nobody will, and the job is unknown (404) rather than a 503 without end.
    unavailable("batch job '" + shown +
                "' is not on this replica and its record is missing from the shared job store "
                "(Redis); its cancel is recorded there and the replica running it is alive: that "
                "replica writes the record again at its next heartbeat, retry later");
  }
  throw api::ApiError(
      api::ErrorCode::kNotFound, "id",
      "no batch job with id '" + shown +
          "' is known to this service: it never existed, was deleted, was lost with a restart of "
          "the replica that ran it (without a shared store), expired or was forgotten to make "
          "room (finished jobs are kept for batch_job_ttl_s = " +
          api::number_text(bounds.ttl_s) +
          " s, at most batch_jobs_kept = " + std::to_string(bounds.kept) +
          " of them within batch_jobs_bytes = " + std::to_string(bounds.bytes) + " bytes)");
}

std::string row_list(const std::vector<std::size_t>& rows) {
  std::string text = rows.size() == 1 ? "row " : "rows ";
  const std::size_t shown = std::min<std::size_t>(rows.size(), 10);
  for (std::size_t k = 0; k < shown; ++k) {
    if (k > 0) text += k + 1 == rows.size() ? " and " : ", ";
    text += std::to_string(rows[k]);
  }
  if (rows.size() > shown) text += " and " + std::to_string(rows.size() - shown) + " more";
  return text;
}

std::string rows_problem_text(const std::string& id, std::size_t readable, std::size_t first,
                              std::size_t last, const std::vector<std::size_t>& missing,
                              const std::vector<std::size_t>& damaged) {
  // "damaged" only for rows the store holds but that are not result rows; rows it lost are
  // missing (the owner may still hold them).
  const std::string what = missing.empty()   ? "damaged"
                           : damaged.empty() ? "incomplete"
                                             : "incomplete and damaged";
  std::string detail;
  if (!missing.empty()) detail += "; missing: " + row_list(missing);
  if (!damaged.empty()) detail += "; damaged: " + row_list(damaged);
  return "the stored results of batch job '" + id.substr(0, 64) + "' are " + what + " (" +
         std::to_string(readable) + " readable of rows " + std::to_string(first) + " to " +
         std::to_string(last) + detail + "): ask the replica that ran it, or POST the job again";
}

std::string lost_job_text(std::size_t recipes_lost, const std::vector<std::size_t>& rows_lost,
                          std::size_t kept, std::size_t total) {
  std::string lost;
  if (recipes_lost != 0) {
    lost =
        std::to_string(recipes_lost) + " of the " + std::to_string(total) + " recipes of its table";
  }
  if (!rows_lost.empty()) {
    lost += (lost.empty() ? "" : ", and ") + row_list(rows_lost) + " of its results";
  }
  return "its replica stopped answering, and the shared job store no longer holds " + lost +
         " (Redis was emptied, or evicted them, meanwhile): no replica can run it on; the first " +
         std::to_string(kept) + " of " + std::to_string(total) +
         " rows are kept; POST the job again (the finished plans are cached)";
}

std::string rows_unread_text(const std::string& id, std::size_t first, std::size_t last,
                             const std::string& failure) {
  return "the results of batch job '" + id.substr(0, 64) + "' could not be read: " + failure +
         " (reading rows " + std::to_string(first) + " to " + std::to_string(last) +
         "); nothing is lost, retry later";
}

std::string incomplete_results_text(const std::string& id, const std::string& state,
                                    std::size_t done, std::size_t total, const std::string& message,
                                    const std::string& path) {
  return "batch job " + id + " is " + state + " with " + std::to_string(done) + " of " +
         std::to_string(total) + " recipes done" + (message.empty() ? "" : " (" + message + ")") +
         ": its table is incomplete; GET " + path + "?partial=1 for the " + std::to_string(done) +
         " done rows, marked partial (X-Slosh-Partial: true), or POST the job again";
}

std::string store_behind_text(std::int64_t record_age_ms, std::int64_t heartbeat_age_ms) {
  return "the replica running it is alive (its heartbeat in the shared job store is " +
         seconds_of_ms(heartbeat_age_ms) + " old) but could not update its record there for " +
         seconds_of_ms(record_age_ms) +
         ": its progress and rows since are kept on that replica until the shared store takes "
         "them (it refuses or fails the writes; that replica's /readyz says why)";
}

std::string shared_behind_text(std::int64_t record_age_ms, std::int64_t heartbeat_age_ms) {
  return "the replicas working on it are alive (its heartbeat in the shared job store is " +
         seconds_of_ms(heartbeat_age_ms) + " old) but could not update its record there for " +
         seconds_of_ms(record_age_ms) +
         ": the shared store refuses or fails their writes (their /readyz says why); each "
         "replica keeps the rows it refused and stores them once it takes writes";
}

std::string owner_view_text() {
  return "the shared job store (Redis) cannot be reached now: this is the job's progress over "
         "all replicas as the replica that accepted it last read it; its items wait until the "
         "store answers again";
}

std::string results_behind_text(const std::string& id, const std::string& why) {
  return "the rows of batch job '" + id.substr(0, 64) +
         "' are not all in the shared job store (Redis): " + why +
         "; retry later, or ask the replica that runs it";
}

std::string late_cancel_note(const std::string& note) {
  const std::string late =
      "a cancel was asked as its last row was stored: the job had finished, its table is whole";
  return note.empty() ? late : note + "; " + late;
}

std::string silent_owner_text(std::int64_t record_age_ms, double stale_s,
                              std::chrono::milliseconds left, bool taken_over) {
  return "the replica running it has not updated it for " + seconds_of_ms(record_age_ms) +
         ", past batch_job_stale_s = " + api::number_text(stale_s) +
         " s (paused, stalled or cut off from the shared store)" +
         (taken_over ? ": another replica takes it over, or it " : ": it ") +
         "reads as failed if still silent in " + seconds_of_ms(left.count());
}

std::string remote_cancel_text(std::int64_t record_age_ms, std::int64_t heartbeat_age_ms,
                               double stale_s, bool taken_over) {
  const std::string recorded = "the cancel is recorded in the shared job store; ";
  if (heartbeat_age_ms >= 0 && heartbeat_age_ms <= 2000) {
    return recorded +
           "the replica running the job is alive and stops it when it next reads the "
           "store (its record there is " +
           seconds_of_ms(record_age_ms) + " old: the store refuses or fails its writes)";
  }
  // The owner rewrites its record every 0.5 s: one older than two of those has missed a beat, and
  // a stop at its next read is no longer promised.
  if (record_age_ms <= 1000) {
    return recorded +
           "the replica running the job stops it when it next reads the store (every "
           "0.5 s)";
  }
  return recorded + "the replica running the job has not answered for " +
         seconds_of_ms(record_age_ms) +
         " (paused, stalled or cut off from the store): it stops the job when it next reads the "
         "store, " +
         (taken_over
              // A helper takes a silent owner's job over at half of stale_s and, reading the
              // cancel flag at once, stops it there: the job never reads as failed.
              ? "or another replica takes the job over once it has been silent for half of "
                "batch_job_stale_s = " +
                    api::number_text(stale_s) + " s (" + api::number_text(stale_s / 2) +
                    " s) and stops it then"
              : "and the job reads as failed once it has been silent for batch_job_stale_s = " +
                    api::number_text(stale_s) + " s");
}

std::string resumed_note(double gap_s, double stale_s) {
  return "this job's replica did not run for " + seconds_text(gap_s) +
         " (its process was paused or starved) and carried on with the job" +
         (gap_s > stale_s ? "; other replicas read it as failed meanwhile (batch_job_stale_s = " +
                                api::number_text(stale_s) + " s) until its next record"
                          : "");
}

std::string too_large_text(std::size_t max_bytes, std::size_t done, std::size_t total) {
  return "its results passed the memory kept for batch jobs, batch_jobs_bytes = " +
         std::to_string(max_bytes) + " bytes, after " + std::to_string(done) + " of " +
         std::to_string(total) +
         " recipes: split the table into smaller jobs, ask for a smaller view, or raise "
         "batch_jobs_bytes";
}

std::string dead_item_text(std::size_t takes, std::size_t max_takes) {
  return "this recipe was taken " + std::to_string(takes - 1) +
         " times by replicas that never stored its row (each stopped, crashed or was cut off "
         "from Redis while solving it): it is not handed out again past batch_job_max_takes = " +
         std::to_string(max_takes) + "; plan it alone (POST /v1/plans) to see what it does";
}

}  // namespace slosh::service
