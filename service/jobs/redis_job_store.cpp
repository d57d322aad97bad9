#include "jobs/redis_job_store.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <random>
#include <utility>

#include "jobs/batch_job_record.hpp"

namespace slosh::service {

namespace {

// KEYS[1]: the job's owner mark; ARGV[1]: this replica; then each command as its argument count
// and its arguments. Writes nothing and answers {0, owner} when the mark names another replica;
// else runs the commands and answers {1}, or the first command's error (Redis refuses the first
// write when full, so a refusal writes nothing, as an aborted MULTI).
constexpr const char* kOwnedWrite = R"lua(
local mark = redis.call('GET', KEYS[1])
if mark and mark ~= ARGV[1] then return {0, mark} end
local i = 2
while i <= #ARGV do
  local n = tonumber(ARGV[i])
  local r = redis.pcall(unpack(ARGV, i + 1, i + n))
  if type(r) == 'table' and r.err then return r end
  i = i + n + 1
end
return {1}
)lua";

}  // namespace

RedisJobStore::RedisJobStore(std::shared_ptr<RedisClient> client, std::chrono::seconds ttl,
                             std::string prefix, std::chrono::milliseconds settle,
                             std::string owner)
    : client_(std::move(client)),
      ttl_(std::to_string(std::max<long long>(1, ttl.count()))),
      prefix_(std::move(prefix)),
      settle_ms_(settle.count()),
      owner_(std::move(owner)) {}

std::string RedisJobStore::write_failure(const std::string& id,
                                         std::vector<std::vector<std::string>> commands,
                                         bool owned) {
  {
    // The generation this write lands in is known before it is sent: an emptying right after it
    // (even before this replica's first heartbeat looked) is then seen as one, and what was
    // written (a DELETE's cancel, a job) is written again.
    const std::lock_guard lock(mutex_);
    if (seen_generation_.empty()) {
      if (auto mark = generation(0)) seen_generation_ = std::move(*mark);
    }
  }
  for (const char* part : {"record", "rows", "cancel", "removed"}) {
    commands.push_back({"EXPIRE", key(id, part), ttl_});
  }
  std::string failure;
  if (owned && !owner_.empty()) {
    bool taken = false;
    failure = owned_write(id, commands, taken);
    // Not the store's failure: another replica runs the job (the caller drops its copy).
    if (taken) return failure;
  } else {
    commands.insert(commands.begin(), {"MULTI"});
    commands.push_back({"EXEC"});
    failure = write_replies_failure(client_->pipeline(commands));
  }
  if (!failure.empty()) {
    const std::string store = "the shared job store (" + client_->options().url.display() + ") ";
    const std::string refused = "Redis refused the write: ";
    const std::lock_guard lock(failure_mutex_);
    last_failure_ = failure.starts_with(refused)
                        ? store + "refused the write: " + failure.substr(refused.size())
                        : store + "is unavailable: " + failure;
  }
  return failure;
}

std::string RedisJobStore::owned_write(const std::string& id,
                                       const std::vector<std::vector<std::string>>& commands,
                                       bool& taken) {
  std::vector<std::string> eval{"EVAL", kOwnedWrite, "1", key(id, "owner"), owner_};
  for (const auto& command : commands) {
    eval.push_back(std::to_string(command.size()));
    eval.insert(eval.end(), command.begin(), command.end());
  }
  const auto reply = client_->command(eval);
  if (!reply) {
    const std::string error = client_->state().error;
    return error.empty() ? "no reply" : error;
  }
  if (reply->is_error()) return "Redis refused the write: " + reply->text;
  if (reply->type != RedisReply::Type::kArray || reply->elements.empty() ||
      reply->elements[0].type != RedisReply::Type::kInteger) {
    return "Redis refused the write (the script answered no result)";
  }
  if (reply->elements[0].integer == 1) {
    const std::lock_guard lock(taken_mutex_);
    taken_.erase(id);
    return "";
  }
  taken = true;
  const std::string other = reply->elements.size() > 1 ? reply->elements[1].text : "";
  {
    const std::lock_guard lock(taken_mutex_);
    taken_[id] = other;
  }
  return "replica " + other + " took the job over (its owner mark names it)";
}

std::optional<std::string> RedisJobStore::taken_over_by(const std::string& id) {
  const std::lock_guard lock(taken_mutex_);
  const auto it = taken_.find(id);
  if (it == taken_.end()) return std::nullopt;
  return it->second;
}

std::string RedisJobStore::write_replies_failure(
    const std::optional<std::vector<RedisReply>>& replies) const {
  if (!replies) {
    const std::string error = client_->state().error;
    return error.empty() ? "no reply" : error;
  }
  const RedisReply& exec = replies->back();
  if (exec.type != RedisReply::Type::kArray) {  // aborted (EXECABORT) or refused
    // The reason is the first error of the queued commands (e.g. OOM under maxmemory), else
    // EXEC's own.
    for (const RedisReply& r : *replies) {
      if (r.is_error()) return "Redis refused the write: " + r.text;
    }
    return "Redis refused the write (EXEC answered no results)";
  }
  for (const RedisReply& r : exec.elements) {
    if (r.is_error()) return "Redis refused the write: " + r.text;
  }
  return "";
}

std::vector<std::string> RedisJobStore::alive_command(const std::string& id) const {
  const std::string ms = std::to_string(std::max<std::int64_t>(1, settle_ms_));
  return {"SET", key(id, "alive"), ms, "PX", ms};
}

bool RedisJobStore::put_record(const std::string& id, const std::string& record) {
  return write(id, {{"SET", key(id, "record"), record}, alive_command(id)}, true);
}

bool RedisJobStore::touch(const std::string& id) {
  const std::string ms = std::to_string(std::max<std::int64_t>(1, settle_ms_));
  const auto renewed = client_->command({"PEXPIRE", key(id, "alive"), ms});
  if (!renewed || renewed->type != RedisReply::Type::kInteger) return false;
  if (renewed->integer == 1) return true;
  // Expired (the owner was silent for `settle`): set again, which a full Redis refuses.
  const auto set = client_->command(alive_command(id));
  return set && set->type == RedisReply::Type::kStatus;
}

std::optional<std::int64_t> RedisJobStore::heartbeat_age_ms(const std::string& id) {
  const auto replies = client_->pipeline({{"GET", key(id, "alive")}, {"PTTL", key(id, "alive")}});
  if (!replies || (*replies)[0].type != RedisReply::Type::kString ||
      (*replies)[1].type != RedisReply::Type::kInteger || (*replies)[1].integer < 0) {
    return std::nullopt;
  }
  const std::int64_t given = std::atoll((*replies)[0].text.c_str());
  return std::max<std::int64_t>(0, given - (*replies)[1].integer);
}

std::string RedisJobStore::last_write_failure() {
  const std::lock_guard lock(failure_mutex_);
  return last_failure_;
}

std::string RedisJobStore::unanswered() const {
  const RedisClient::State state = client_->state();
  const std::string store = "the shared job store (" + client_->options().url.display() + ") ";
  if (state.up) {
    return store + "did not answer in time: every connection to it stayed busy for " +
           std::to_string(client_->options().timeout.count()) + " ms";
  }
  if (state.error.find("no reply within") != std::string::npos) {
    return store + "did not answer in time: " + state.error;
  }
  return store + "cannot be reached: " + (state.error.empty() ? "no reply" : state.error);
}

std::optional<std::string> RedisJobStore::create(const std::string& id, const std::string& record) {
  const std::string failure =
      write_failure(id, {{"SET", key(id, "record"), record}, alive_command(id)});
  if (failure.empty()) return std::nullopt;
  return "the shared job store (" + client_->options().url.display() +
         ") is unavailable: " + failure;
}

JobStore::RecordLookup RedisJobStore::lookup_record(const std::string& id) {
  const auto replies =
      client_->pipeline({{"GET", key(id, "record")}, {"EXISTS", key(id, "removed")}});
  if (!replies) return {std::nullopt, false};
  const RedisReply& record = (*replies)[0];
  const RedisReply& removed = (*replies)[1];
  // Only a nil is "no such record"; any other reply (an error such as WRONGTYPE or LOADING, a
  // status, an integer, an array) is no answer: reading it as missing would answer 404 for a job
  // that exists.
  const bool known =
      record.type == RedisReply::Type::kString || record.type == RedisReply::Type::kNil;
  if (record.is_error() && record.text.rfind("WRONGTYPE", 0) == 0 &&
      removed.type == RedisReply::Type::kInteger) {
    // Redis answered: the key exists but is not a string. The job's state is damaged, and
    // reading it as "Redis cannot be reached" would send the user to wait for nothing.
    if (removed.integer > 0) return {std::nullopt, true};
    spdlog::warn("batch job {}: its record key in Redis is not a string ({})", id, record.text);
    return {std::nullopt, true, true};
  }
  if (!known || removed.type != RedisReply::Type::kInteger) {
    spdlog::warn(
        "batch job {}: Redis answered the record read with an unexpected reply ({}{}): "
        "answered as unavailable",
        id, record.is_error() || removed.is_error() ? "error " : "type ",
        record.is_error()    ? record.text
        : removed.is_error() ? removed.text
                             : "");
    return {std::nullopt, false};
  }
  if (removed.integer > 0 || record.type == RedisReply::Type::kNil) return {std::nullopt, true};
  return {record.text, true};
}

bool RedisJobStore::put_rows(const std::string& id, std::size_t first,
                             const std::vector<std::string>& rows) {
  if (rows.empty()) return write(id, {});
  std::vector<std::string> set{"HSET", key(id, "rows")};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    set.push_back(std::to_string(first + i));
    set.push_back(rows[i]);
  }
  return write(id, {std::move(set)}, true);
}

std::optional<std::vector<std::string>> RedisJobStore::rows(const std::string& id,
                                                            std::size_t offset, std::size_t count) {
  // The fields asked for are bounded by the rows the hash holds (HLEN, asked first), so a huge
  // count costs no more than the job's rows.
  const auto head = client_->pipeline({{"EXISTS", key(id, "record")}, {"HLEN", key(id, "rows")}});
  if (!head || (*head)[0].type != RedisReply::Type::kInteger || (*head)[0].integer == 0 ||
      (*head)[1].type != RedisReply::Type::kInteger) {
    return std::nullopt;
  }
  const auto held = static_cast<std::size_t>(std::max<long long>(0, (*head)[1].integer));
  std::vector<std::string> out;
  if (count == 0 || offset >= held) return out;
  // Rows at indexes >= held cannot all be present when one below is missing; asking up to `held`
  // past the offset is enough to find every row there is.
  const std::size_t n = std::min(count, held);
  std::vector<std::string> get{"HMGET", key(id, "rows")};
  for (std::size_t i = 0; i < n; ++i) get.push_back(std::to_string(offset + i));
  const auto reply = client_->command(get);
  if (!reply || reply->type != RedisReply::Type::kArray) return std::nullopt;
  for (const RedisReply& r : reply->elements) {
    if (r.type != RedisReply::Type::kString) break;  // a missing index ends what is readable
    out.push_back(r.text);
  }
  return out;
}

JobStore::SlotsRead RedisJobStore::read_slots(const std::string& id, std::size_t offset,
                                              std::size_t count) {
  const auto head = client_->pipeline({{"EXISTS", key(id, "record")}, {"HLEN", key(id, "rows")}});
  if (!head) return {std::nullopt, unanswered()};
  if ((*head)[0].type != RedisReply::Type::kInteger || (*head)[0].integer == 0 ||
      (*head)[1].type != RedisReply::Type::kInteger) {
    return {};
  }
  std::vector<std::optional<std::string>> out(count);
  if (count == 0 || (*head)[1].integer <= 0) return {std::move(out), {}};
  std::vector<std::string> get{"HMGET", key(id, "rows")};
  for (std::size_t i = 0; i < count; ++i) get.push_back(std::to_string(offset + i));
  const auto reply = client_->command(get);
  if (!reply) return {std::nullopt, unanswered()};
  if (reply->type != RedisReply::Type::kArray || reply->elements.size() != count) return {};
  for (std::size_t i = 0; i < count; ++i) {
    if (reply->elements[i].type == RedisReply::Type::kString) out[i] = reply->elements[i].text;
  }
  return {std::move(out), {}};
}

JobTraces RedisJobStore::traces(const std::string& id) {
  const auto replies = client_->pipeline({{"EXISTS", key(id, "rows")},
                                          {"EXISTS", key(id, "cancel")},
                                          {"EXISTS", key(id, "removed")},
                                          {"EXISTS", key(id, "alive")}});
  if (!replies) return JobTraces::kNone;
  const auto exists = [&](std::size_t i) {
    return (*replies)[i].type == RedisReply::Type::kInteger && (*replies)[i].integer > 0;
  };
  if (exists(2)) return JobTraces::kNone;  // removed: deleted on purpose
  if (exists(0)) return JobTraces::kRows;
  return exists(1) && exists(3) ? JobTraces::kLiveCancel : JobTraces::kNone;
}

std::vector<std::string> RedisJobStore::records_missing_among(const std::vector<std::string>& ids) {
  std::vector<std::string> out;
  if (ids.empty()) return out;
  std::vector<std::vector<std::string>> asks;
  asks.reserve(ids.size());
  for (const std::string& id : ids)
    asks.push_back({"EXISTS", key(id, "record"), key(id, "removed")});
  const auto replies = client_->pipeline(asks);
  if (!replies) return out;  // unreachable: nothing is known missing
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const RedisReply& r = (*replies)[i];
    if (r.type == RedisReply::Type::kInteger && r.integer == 0) out.push_back(ids[i]);
  }
  return out;
}

bool RedisJobStore::request_cancel(const std::string& id) {
  return write(id, {{"SET", key(id, "cancel"), "1"}});
}

bool RedisJobStore::cancel_requested(const std::string& id) {
  // A job removed through another replica (its record read as stale there) is cancelled too.
  const auto reply = client_->command({"EXISTS", key(id, "cancel"), key(id, "removed")});
  return reply && reply->type == RedisReply::Type::kInteger && reply->integer > 0;
}

std::optional<std::string> RedisJobStore::generation(std::int64_t set_ms) {
  const std::string key = prefix_ + "generation";
  const auto current = client_->command({"GET", key});
  if (!current) return std::nullopt;
  if (current->type == RedisReply::Type::kString) return current->text;
  static thread_local std::mt19937_64 bits{std::random_device{}()};
  const std::string mark = std::to_string(bits()) + ":" + std::to_string(set_ms);
  // NX: when two replicas find it missing at once, both then read the one that was set first.
  const auto replies = client_->pipeline({{"SET", key, mark, "NX"}, {"GET", key}});
  if (!replies || (*replies)[1].type != RedisReply::Type::kString) return std::nullopt;
  return (*replies)[1].text;
}

bool RedisJobStore::emptied_since_last_check() {
  const std::lock_guard lock(mutex_);
  const bool first = seen_generation_.empty();
  const auto mark = generation(first ? 0 : unix_ms_now());
  if (!mark) return false;
  const bool changed = !first && *mark != seen_generation_;
  seen_generation_ = *mark;
  return changed;
}

bool RedisJobStore::recently_emptied() {
  const auto reply = client_->command({"GET", prefix_ + "generation"});
  if (!reply) return false;  // unreachable: answered as such elsewhere
  if (reply->type != RedisReply::Type::kString) return true;
  const std::size_t colon = reply->text.rfind(':');
  const std::int64_t set_ms =
      colon == std::string::npos ? 0 : std::atoll(reply->text.c_str() + colon + 1);
  return set_ms > 0 && unix_ms_now() - set_ms < settle_ms_;
}

bool RedisJobStore::remove(const std::string& id) {
  // The mark outlives the job's other keys by the TTL: the owner sees it at its next heartbeat
  // and drops its own copy instead of publishing it again.
  return write(id, {{"DEL", key(id, "record"), key(id, "rows"), key(id, "cancel"), key(id, "alive"),
                     key(id, "spec"), key(id, "counts"), key(id, "items"), key(id, "final")},
                    {"SET", key(id, "removed"), "1"}});
}

std::vector<std::string> RedisJobStore::removed_among(const std::vector<std::string>& ids) {
  std::vector<std::string> out;
  if (ids.empty()) return out;
  std::vector<std::vector<std::string>> asks;
  asks.reserve(ids.size());
  for (const std::string& id : ids) asks.push_back({"EXISTS", key(id, "removed")});
  const auto replies = client_->pipeline(asks);
  if (!replies) return out;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const RedisReply& r = (*replies)[i];
    if (r.type == RedisReply::Type::kInteger && r.integer > 0) out.push_back(ids[i]);
  }
  return out;
}

}  // namespace slosh::service
