#include "redis_job_store.hpp"

#include <algorithm>
#include <limits>
#include <utility>

namespace slosh::service {

RedisJobStore::RedisJobStore(std::shared_ptr<RedisClient> client, std::chrono::seconds ttl,
                             std::string prefix)
    : client_(std::move(client)),
      ttl_(std::to_string(std::max<long long>(1, ttl.count()))),
      prefix_(std::move(prefix)) {}

bool RedisJobStore::write(const std::string& id, std::vector<std::vector<std::string>> commands) {
  commands.insert(commands.begin(), {"MULTI"});
  for (const char* part : {"record", "rows", "cancel"}) {
    commands.push_back({"EXPIRE", key(id, part), ttl_});
  }
  commands.push_back({"EXEC"});
  const auto replies = client_->pipeline(commands);
  if (!replies) return false;
  const RedisReply& exec = replies->back();
  if (exec.type != RedisReply::Type::kArray) return false;  // aborted (EXECABORT) or refused
  return std::none_of(exec.elements.begin(), exec.elements.end(),
                      [](const RedisReply& r) { return r.is_error(); });
}

bool RedisJobStore::put_record(const std::string& id, const std::string& record) {
  return write(id, {{"SET", key(id, "record"), record}});
}

std::optional<std::string> RedisJobStore::record(const std::string& id) {
  const auto reply = client_->command({"GET", key(id, "record")});
  if (!reply || reply->type != RedisReply::Type::kString) return std::nullopt;
  return reply->text;
}

bool RedisJobStore::append_rows(const std::string& id, const std::vector<std::string>& rows) {
  if (rows.empty()) return write(id, {});
  std::vector<std::string> push{"RPUSH", key(id, "rows")};
  push.insert(push.end(), rows.begin(), rows.end());
  return write(id, {std::move(push)});
}

std::optional<std::vector<std::string>> RedisJobStore::rows(const std::string& id,
                                                            std::size_t offset, std::size_t count) {
  constexpr auto kMax = static_cast<std::size_t>(std::numeric_limits<long long>::max() / 2);
  const std::size_t first = std::min(offset, kMax);
  // LRANGE's stop is inclusive, and -1 would mean "to the end": count 0 asks for nothing.
  const std::size_t last = count == 0 ? first : std::min(first + std::min(count, kMax) - 1, kMax);
  const auto replies =
      client_->pipeline({{"EXISTS", key(id, "record")},
                         {"LRANGE", key(id, "rows"), std::to_string(first), std::to_string(last)}});
  if (!replies || (*replies)[0].type != RedisReply::Type::kInteger || (*replies)[0].integer == 0 ||
      (*replies)[1].type != RedisReply::Type::kArray) {
    return std::nullopt;
  }
  std::vector<std::string> out;
  if (count == 0) return out;
  for (const RedisReply& r : (*replies)[1].elements) out.push_back(r.text);
  return out;
}

bool RedisJobStore::request_cancel(const std::string& id) {
  return write(id, {{"SET", key(id, "cancel"), "1"}});
}

bool RedisJobStore::cancel_requested(const std::string& id) {
  const auto reply = client_->command({"EXISTS", key(id, "cancel")});
  return reply && reply->type == RedisReply::Type::kInteger && reply->integer > 0;
}

void RedisJobStore::remove(const std::string& id) {
  (void)client_->command({"DEL", key(id, "record"), key(id, "rows"), key(id, "cancel")});
}

}  // namespace slosh::service
