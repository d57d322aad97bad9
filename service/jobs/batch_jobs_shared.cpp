// POST /v1/batches with batch_job_spread = "replicas": the job is published in Redis, where
// every replica's SharedJobWorker takes its items; its record is the one every replica rewrites.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "jobs/batch_job_state.hpp"
#include "jobs/batch_jobs.hpp"
#include "jobs/job_messages.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/job_record.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::service {

namespace {

/// Rows read from Redis at a time when a finished job is copied here (one HMGET each).
constexpr std::size_t kCopyPage = 500;

}  // namespace

Reply BatchJobs::post_shared(Job& job) {
  {
    const std::lock_guard lock(mutex_);
    check_capacity_locked();  // again: other jobs may have been posted meanwhile
  }
  Reply reply;
  reply.status = 202;
  reply.body = api::job_record_text(job.status, unix_ms_now());
  reply.headers.emplace_back("Location", "/v1/batches/" + job.status.id);
  // Accepted only once every replica can find it and take its items.
  if (auto refused = shared_->publish(job.status, std::move(job.rows))) {
    // Nobody learns the id of a refused job, but its writes that timed out may land once Redis
    // answers again: its items would then be taken by every replica for a job no one owns. Its
    // removal mark (sent again at every heartbeat until Redis takes it) closes it for them all.
    (void)store_.remove(job.status.id);
    throw api::ApiError(api::ErrorCode::kUnavailable, "",
                        *refused + "; the job was not started: POST it again later");
  }
  return reply;
}

void BatchJobs::keep_finished_shared(const std::string& id) {
  const JobStore::RecordLookup lookup = store_.lookup_record(id);
  const auto record = lookup.text ? api::parse_job_record(*lookup.text) : std::nullopt;
  if (!record || !api::is_final(record->state)) return;
  std::vector<std::string> rows;
  rows.reserve(record->done);
  bool whole = true;
  for (std::size_t page = 0; whole && page < record->done; page += kCopyPage) {
    const std::size_t n = std::min(kCopyPage, record->done - page);
    auto read = store_.read_slots(id, page, n);
    whole = read.slots && read.slots->size() == n;
    for (std::size_t i = 0; whole && i < n; ++i) {
      whole = (*read.slots)[i].has_value();
      if (whole) rows.push_back(std::move(*(*read.slots)[i]));
    }
  }
  // A cancelled job's rows have gaps (the replicas stored them in no particular order): the
  // local store keeps rows in order only, so such a job is not kept (docs/machines.md).
  if (!whole || !store_.keep_copy(id, *lookup.text, rows)) {
    spdlog::info("batch job {}: no local copy kept (its rows are not the table's first {})", id,
                 record->done);
  }
}

BatchJobs::DoneRows BatchJobs::read_done_rows(const std::string& id, std::size_t done) {
  DoneRows out;
  out.rows.reserve(done);
  for (std::size_t page = 0; page < done; page += kCopyPage) {
    const std::size_t n = std::min(kCopyPage, done - page);
    auto read = store_.read_slots(id, page, n);
    if (!read.slots) {
      out.answered = false;
      return out;
    }
    read.slots->resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      auto& slot = (*read.slots)[i];
      if (!slot) {
        out.lost.push_back(page + i + 1);
      } else if (out.lost.empty()) {
        out.rows.push_back(std::move(*slot));
      }
    }
  }
  return out;
}

bool BatchJobs::adopt(const std::string& id) {
  const JobStore::RecordLookup lookup = store_.lookup_record(id);
  const auto record = lookup.text ? api::parse_job_record(*lookup.text) : std::nullopt;
  if (!record || api::is_final(record->state)) return false;
  auto job = std::make_shared<Job>();
  job->status = api::job_status_of(*record);
  job->status.id = id;
  HelpedJobs::TableRead table = helped_->table(id, job->status.total);
  // The rows its record counts are in the shared store (its owner stored rows before records).
  DoneRows done = read_done_rows(id, job->status.done);
  // A store that did not answer may answer at the next look; one that answered without parts of
  // the job lost them (emptied, evicted): taking the job over again would find the same.
  if (!table.answered || !done.answered) return false;
  if (!table.recipes || !done.lost.empty()) {
    fail_lost_job(*job, table.missing, done);
    return true;
  }
  if (!store_.keep_copy(id, *lookup.text, done.rows)) return false;
  job->rows = std::move(*table.recipes);
  if (job->status.view) job->view = api::parse_plan_view(*job->status.view);
  job->cancel = job->status.cancel_requested;
  {
    const std::lock_guard lock(mutex_);
    if (stopping_) return false;
    active_[id] = job;
    queue_.push_back(job);
  }
  wake_.notify_all();
  return true;
}

void BatchJobs::fail_lost_job(Job& job, std::size_t recipes_lost, const DoneRows& done) {
  JobStatus& s = job.status;
  const std::string message = lost_job_text(recipes_lost, done.lost, done.rows.size(), s.total);
  // Its record counts the rows that are still the table's first, and the local copy holds them,
  // so that this replica serves them and publishes them again if Redis loses them.
  s.done = done.rows.size();
  s.state = JobState::kFailed;
  s.message = message;
  s.finished_ms = unix_ms_now();
  (void)store_.keep_copy(s.id, record_text(job), done.rows);
  write_record(job);
  helped_->close(s.id, true);
  spdlog::warn("batch job {} failed: {}", s.id, message);
}

}  // namespace slosh::service
