#pragma once
// A replica's name held in Redis by the process that runs it, so that two live processes started
// with one --replica-id find out (in either batch_job_spread that shares jobs).

#include <chrono>
#include <string>
#include <vector>

#include "storage/redis_client.hpp"

namespace slosh::service {

/// Sets `<prefix>replicas:<replica>` to this process's `token` for `alive` and sends `also` in the
/// same round trip; false when another process's token was there (a duplicate --replica-id).
/// True when Redis does not answer.
bool hold_replica_name(RedisClient& client, const std::string& prefix, const std::string& replica,
                       const std::string& token, std::chrono::milliseconds alive,
                       std::vector<std::vector<std::string>> also = {});

}  // namespace slosh::service
