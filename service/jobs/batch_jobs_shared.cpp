// POST /v1/batches with batch_job_spread = "replicas": the job is published in Redis, where
// every replica's SharedJobWorker takes its items; its record is the one every replica rewrites.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "jobs/batch_job_state.hpp"
#include "jobs/batch_jobs.hpp"
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

bool BatchJobs::adopt(const std::string& id) {
  const JobStore::RecordLookup lookup = store_.lookup_record(id);
  const auto record = lookup.text ? api::parse_job_record(*lookup.text) : std::nullopt;
  if (!record || api::is_final(record->state)) return false;
  JobStatus status = api::job_status_of(*record);
  status.id = id;
  auto table = helped_->table(id, status.total);
  if (!table) return false;
  // The rows its record counts are in the shared store (its owner stored rows before records).
  std::vector<std::string> rows;
  rows.reserve(status.done);
  for (std::size_t page = 0; page < status.done; page += kCopyPage) {
    const std::size_t n = std::min(kCopyPage, status.done - page);
    auto read = store_.read_slots(id, page, n);
    if (!read.slots || read.slots->size() != n) return false;
    for (auto& slot : *read.slots) {
      if (!slot) return false;
      rows.push_back(std::move(*slot));
    }
  }
  if (!store_.keep_copy(id, *lookup.text, rows)) return false;
  auto job = std::make_shared<Job>();
  job->status = std::move(status);
  job->rows = std::move(*table);
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

}  // namespace slosh::service
