// POST /v1/batches with batch_job_spread = "replicas": the job is published in Redis, where
// every replica's SharedJobWorker takes its items; its record is the one every replica rewrites.

#include "jobs/batch_job_state.hpp"
#include "jobs/batch_jobs.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/job_record.hpp"

namespace slosh::service {

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
    throw api::ApiError(api::ErrorCode::kUnavailable, "",
                        *refused + "; the job was not started: POST it again later");
  }
  return reply;
}

}  // namespace slosh::service
