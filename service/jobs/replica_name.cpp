#include "jobs/replica_name.hpp"

#include <algorithm>
#include <cstdint>

namespace slosh::service {

bool hold_replica_name(RedisClient& client, const std::string& prefix, const std::string& replica,
                       const std::string& token, std::chrono::milliseconds alive,
                       std::vector<std::vector<std::string>> also) {
  also.insert(also.begin(), {"SET", prefix + "replicas:" + replica, token, "PX",
                             std::to_string(std::max<std::int64_t>(1, alive.count())), "GET"});
  const auto replies = client.pipeline(also);
  if (!replies || replies->empty()) return true;
  const RedisReply& held = replies->front();
  return held.type != RedisReply::Type::kString || held.text == token;
}

}  // namespace slosh::service
