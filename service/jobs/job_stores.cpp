#include "jobs/job_stores.hpp"

#include <chrono>
#include <cmath>

namespace slosh::service {

JobStores::JobStores(const ServerConfig& config, const std::shared_ptr<RedisClient>& shared)
    : local(MemoryJobStoreLimits{.ttl_s = config.batch_job_ttl_s,
                                 .max_jobs = config.batch_jobs_kept + config.batch_jobs_max,
                                 .max_bytes = config.batch_jobs_bytes}) {
  if (!shared) return;
  redis.emplace(shared, std::chrono::seconds(std::llround(config.batch_job_ttl_s)), "slosh:jobs:",
                std::chrono::milliseconds(std::llround(config.batch_job_stale_s * 1000)),
                replica_name(config));
  tiered.emplace(local, *redis);
}

}  // namespace slosh::service
