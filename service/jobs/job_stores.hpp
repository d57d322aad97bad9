#pragma once
// Where the server's batch jobs keep their state: this replica's memory, and with a Redis plan
// cache the shared Redis too, so that any replica answers for any job (TieredJobStore: local
// first).

#include <memory>
#include <optional>

#include "config/server_config.hpp"
#include "jobs/memory_job_store.hpp"
#include "jobs/redis_job_store.hpp"
#include "jobs/tiered_job_store.hpp"
#include "storage/redis_client.hpp"

namespace slosh::service {

struct JobStores {
  MemoryJobStore local;
  std::optional<RedisJobStore> redis;
  std::optional<TieredJobStore> tiered;

  /// The stores of `config` (batch_job_ttl_s, batch_jobs_kept, batch_jobs_max, batch_jobs_bytes,
  /// batch_job_stale_s); `redis`: the shared cache's client, null without one.
  JobStores(const ServerConfig& config, const std::shared_ptr<RedisClient>& redis);
  JobStores(const JobStores&) = delete;
  JobStores& operator=(const JobStores&) = delete;
  /// The store the jobs use: the tiered one with Redis, else the local one.
  JobStore& store() { return tiered ? static_cast<JobStore&>(*tiered) : local; }
};

}  // namespace slosh::service
