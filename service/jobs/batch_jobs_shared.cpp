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
    // Nobody learns the id of a refused job, but its writes that timed out may land once Redis
    // answers again: its items would then be taken by every replica for a job no one owns. Its
    // removal mark (sent again at every heartbeat until Redis takes it) closes it for them all.
    (void)store_.remove(job.status.id);
    throw api::ApiError(api::ErrorCode::kUnavailable, "",
                        *refused + "; the job was not started: POST it again later");
  }
  return reply;
}

}  // namespace slosh::service
