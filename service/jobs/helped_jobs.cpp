#include "jobs/helped_jobs.hpp"

#include <algorithm>
#include <cstdlib>
#include <utility>

#include "jobs/replica_name.hpp"

namespace slosh::service {

namespace {

/// The consumer group of the helpers.
constexpr const char* kHelpersGroup = "helpers";
/// Items written to the stream in one round trip.
constexpr std::size_t kChunk = 500;
/// Entries read back at a time when a job is adopted.
constexpr std::size_t kReadChunk = 1000;
/// note_helped(): KEYS help offer, helped, solved; ARGV the index, this replica, the TTL [ms].
/// Nothing once the offer is gone (the job ended: its owner has credited every row), so a plan
/// finished after the job's end is not credited nor counted.
constexpr const char* kNoteHelped = R"lua(
if redis.call('EXISTS', KEYS[1]) == 0 then return 0 end
local won = redis.call('HSETNX', KEYS[2], ARGV[1], ARGV[2])
redis.call('PEXPIRE', KEYS[2], ARGV[3])
redis.call('ZADD', KEYS[3], ARGV[1], ARGV[1])
redis.call('PEXPIRE', KEYS[3], ARGV[3])
return won
)lua";
/// close() by the owner: KEYS owner mark, helping set, items, help, helped, adopt, solved; ARGV
/// this replica, the job's id, the keys' TTL [ms]. Nothing when the mark names another replica.
constexpr const char* kCloseOwned = R"lua(
local mark = redis.call('GET', KEYS[1])
if mark and mark ~= ARGV[1] then return 0 end
redis.call('ZREM', KEYS[2], ARGV[2])
redis.call('DEL', KEYS[3], KEYS[4], KEYS[5], KEYS[6], KEYS[7])
redis.call('PEXPIRE', KEYS[1], ARGV[3])
return 1
)lua";

/// hand_over(): KEYS owner mark, heartbeat, helpers set, help offer, adoption lock; ARGV this
/// replica, the prefix of the replicas' name keys. Takes the heartbeat away when a helper other
/// than this replica holds its name (forgetting those that no longer do), and this replica's
/// adoption lock with it, so that the helper may take the job at once; 1 when it did.
constexpr const char* kHandOver = R"lua(
local mark = redis.call('GET', KEYS[1])
if mark and mark ~= ARGV[1] then return 0 end
if redis.call('EXISTS', KEYS[4]) == 0 then return 0 end
for _, r in ipairs(redis.call('SMEMBERS', KEYS[3])) do
  if r ~= ARGV[1] then
    if redis.call('EXISTS', ARGV[2] .. r) == 1 then
      redis.call('DEL', KEYS[2])
      if redis.call('GET', KEYS[5]) == ARGV[1] then redis.call('DEL', KEYS[5]) end
      return 1
    end
    redis.call('SREM', KEYS[3], r)
  end
end
return 0
)lua";

/// give_back(): KEYS owner mark, heartbeat, adoption lock; ARGV this replica. A takeover that did
/// not start here: its heartbeat and this replica's lock go, while the mark names this replica.
constexpr const char* kGiveBack = R"lua(
if redis.call('GET', KEYS[1]) ~= ARGV[1] then return 0 end
redis.call('DEL', KEYS[2])
if redis.call('GET', KEYS[3]) == ARGV[1] then redis.call('DEL', KEYS[3]) end
return 1
)lua";

bool any_error(const std::optional<std::vector<RedisReply>>& replies) {
  if (!replies) return true;
  return std::any_of(replies->begin(), replies->end(), [](const RedisReply& r) {
    return r.is_error() && r.text.rfind("BUSYGROUP", 0) != 0;
  });
}

}  // namespace

HelpedJobs::HelpedJobs(std::shared_ptr<RedisClient> client, std::string replica,
                       std::chrono::milliseconds ttl, std::string prefix)
    : client_(std::move(client)),
      replica_(std::move(replica)),
      ttl_ms_(std::to_string(ttl.count())),
      prefix_(std::move(prefix)) {}

bool HelpedJobs::publish(const JobStatus& status, const std::vector<RecipeRow>& recipes,
                         std::size_t front) {
  const std::string& id = status.id;
  const std::string stream = key(id, "items");
  front = std::min(front, recipes.size());
  if (any_error(client_->pipeline(
          {{"DEL", stream},
           {"HSET", key(id, "help"), "owner", replica_, "front", std::to_string(front)},
           {"PEXPIRE", key(id, "help"), ttl_ms_},
           {"SET", key(id, "owner"), replica_, "PX", ttl_ms_},
           {"XGROUP", "CREATE", stream, kHelpersGroup, "0", "MKSTREAM"},
           {"PEXPIRE", stream, ttl_ms_}}))) {
    return false;
  }
  // From the end: the helpers work from the table's end while the owner works from its start.
  // Every item, also those below `front`: a replica that takes the job over reads its table
  // from them.
  for (std::size_t done = 0; done < recipes.size(); done += kChunk) {
    std::vector<std::vector<std::string>> adds;
    for (std::size_t k = done; k < std::min(recipes.size(), done + kChunk); ++k) {
      const std::size_t i = recipes.size() - 1 - k;
      adds.push_back(SharedJobQueue::item_command(stream, status, i, recipes[i]));
    }
    if (any_error(client_->pipeline(adds))) return false;
  }
  return !any_error(
      client_->pipeline({{"ZADD", prefix_ + "helping", std::to_string(status.created_ms), id}}));
}

std::optional<std::string> HelpedJobs::beat(const std::string& id, std::size_t front) {
  const auto replies = client_->pipeline({{"HGET", key(id, "help"), "owner"},
                                          {"HSET", key(id, "help"), "front", std::to_string(front)},
                                          {"PEXPIRE", key(id, "help"), ttl_ms_},
                                          {"PEXPIRE", key(id, "items"), ttl_ms_},
                                          {"PEXPIRE", key(id, "helped"), ttl_ms_},
                                          {"GET", key(id, "owner")},
                                          {"PEXPIRE", key(id, "solved"), ttl_ms_}});
  if (!replies) return std::nullopt;
  const RedisReply& owner = (*replies)[0];
  const RedisReply& last_owner = (*replies)[5];
  if (owner.type != RedisReply::Type::kString && last_owner.type == RedisReply::Type::kString &&
      last_owner.text != replica_) {
    // The help offer is gone because another replica took the job over and ended it (its
    // owner mark outlives the job's end): the job is no longer this replica's.
    (void)client_->command({"DEL", key(id, "help")});
    return last_owner.text;
  }
  if (owner.type != RedisReply::Type::kString) {
    // Emptied or expired: the key the HSET just made holds no owner, and nobody helps.
    (void)client_->command({"DEL", key(id, "help")});
    return std::string();
  }
  return owner.text;
}

std::optional<std::string> HelpedJobs::owner_of(const std::string& id) {
  const auto reply = client_->command({"GET", key(id, "owner")});
  if (!reply || reply->type == RedisReply::Type::kError) return std::nullopt;
  return reply->type == RedisReply::Type::kString ? reply->text : std::string();
}

std::optional<std::vector<HelpedJobs::Credit>> HelpedJobs::credit(
    const std::string& id, const std::vector<std::size_t>& indexes) {
  std::vector<Credit> out(indexes.size());
  if (indexes.empty()) return out;
  // HSETNX: an item a helper noted first stays its own; the others become this replica's. Then
  // HGETs in the same round trip (not an HMGET: that is the job's row read, see jobs()).
  // In chunks (rows held while Redis did not answer may be thousands); a chunk sent again after
  // a failure credits the same replicas (HSETNX keeps the first).
  for (std::size_t first = 0; first < indexes.size(); first += kChunk) {
    const std::size_t n = std::min(kChunk, indexes.size() - first);
    std::vector<std::vector<std::string>> asks;
    for (std::size_t k = first; k < first + n; ++k) {
      asks.push_back({"HSETNX", key(id, "helped"), std::to_string(indexes[k]), replica_});
    }
    for (std::size_t k = first; k < first + n; ++k) {
      asks.push_back({"HGET", key(id, "helped"), std::to_string(indexes[k])});
    }
    asks.push_back({"PEXPIRE", key(id, "helped"), ttl_ms_});
    const auto replies = client_->pipeline(asks);
    if (!replies || replies->size() != asks.size()) return std::nullopt;
    for (std::size_t k = 0; k < n; ++k) {
      const RedisReply& noted = (*replies)[k];
      const RedisReply& name = (*replies)[n + k];
      if (name.type != RedisReply::Type::kString) return std::nullopt;
      out[first + k].solver = name.text;
      out[first + k].noted_now = noted.type == RedisReply::Type::kInteger && noted.integer == 1;
    }
  }
  return out;
}

std::optional<std::size_t> HelpedJobs::solved_from(const std::string& id, std::size_t done) {
  const auto reply = client_->command({"ZCOUNT", key(id, "solved"), std::to_string(done), "+inf"});
  if (!reply || reply->type != RedisReply::Type::kInteger) return std::nullopt;
  return static_cast<std::size_t>(std::max<long long>(0, reply->integer));
}

void HelpedJobs::close(const std::string& id, bool as_owner) {
  if (as_owner) {
    // Only while the owner mark still names this replica: a job another replica took over while
    // this one was cut off keeps its offer (this one's close may reach Redis late).
    (void)client_->command({"EVAL", kCloseOwned, "7", key(id, "owner"), prefix_ + "helping",
                            key(id, "items"), key(id, "help"), key(id, "helped"), key(id, "adopt"),
                            key(id, "solved"), replica_, id, ttl_ms_});
    return;
  }
  (void)client_->pipeline(
      {{"ZREM", prefix_ + "helping", id},
       {"DEL", key(id, "items"), key(id, "help"), key(id, "helped"), key(id, "adopt"),
        key(id, "solved")},
       // The owner mark stays as long as the record: a paused former owner reads it.
       {"PEXPIRE", key(id, "owner"), ttl_ms_}});
}

std::vector<HelpedJobs::Helped> HelpedJobs::jobs() {
  std::vector<Helped> out;
  const auto ids = client_->command({"ZRANGE", prefix_ + "helping", "0", "-1"});
  if (!ids || ids->type != RedisReply::Type::kArray) return out;
  // Two HGETs a job in one round trip rather than an HMGET: the job's rows are read with HMGET,
  // and a slow log or a proxy filtered on it then shows the row reads alone.
  std::vector<std::vector<std::string>> asks;
  for (const RedisReply& id : ids->elements) {
    asks.push_back({"HGET", key(id.text, "help"), "owner"});
    asks.push_back({"HGET", key(id.text, "help"), "front"});
  }
  if (asks.empty()) return out;
  const auto replies = client_->pipeline(asks);
  if (!replies) return out;
  for (std::size_t i = 0; i < ids->elements.size(); ++i) {
    const RedisReply& owner = (*replies)[2 * i];
    const RedisReply& front = (*replies)[2 * i + 1];
    if (owner.type != RedisReply::Type::kString) {
      // No owner any more (closed, emptied): no help.
      (void)client_->command({"ZREM", prefix_ + "helping", ids->elements[i].text});
      continue;
    }
    Helped h;
    h.id = ids->elements[i].text;
    h.owner = owner.text;
    h.front = static_cast<std::size_t>(std::strtoull(front.text.c_str(), nullptr, 10));
    out.push_back(std::move(h));
  }
  return out;
}

std::vector<SharedItem> HelpedJobs::take(const std::string& id, std::size_t n) {
  // NOACK: an item a helper took and never solved costs nothing (the owner solves every item).
  const auto read =
      client_->command({"XREADGROUP", "GROUP", kHelpersGroup, replica_, "COUNT", std::to_string(n),
                        "NOACK", "STREAMS", key(id, "items"), ">"});
  if (!read || read->type != RedisReply::Type::kArray || read->elements.empty() ||
      read->elements[0].elements.size() != 2) {
    return {};
  }
  return SharedJobQueue::items_of(read->elements[0].elements[1]);
}

bool HelpedJobs::note_helped(const std::string& id, std::size_t index) {
  const auto reply =
      client_->command({"EVAL", kNoteHelped, "3", key(id, "help"), key(id, "helped"),
                        key(id, "solved"), std::to_string(index), replica_, ttl_ms_});
  return reply && reply->type == RedisReply::Type::kInteger && reply->integer == 1;
}

bool HelpedJobs::hold_name(const std::string& token, std::chrono::milliseconds alive) {
  // The key of the replicas spread's workers too (SharedJobQueue::hold_name): a duplicate is seen
  // whichever spread each of the two runs.
  return hold_replica_name(*client_, prefix_, replica_, token, alive,
                           {{"SADD", prefix_ + "helpers", replica_}});
}

bool HelpedJobs::hand_over(const std::string& id) {
  const auto reply = client_->command({"EVAL", kHandOver, "5", key(id, "owner"), key(id, "alive"),
                                       prefix_ + "helpers", key(id, "help"), key(id, "adopt"),
                                       replica_, prefix_ + "replicas:"});
  return reply && reply->type == RedisReply::Type::kInteger && reply->integer == 1;
}

void HelpedJobs::give_back(const std::string& id) {
  (void)client_->command(
      {"EVAL", kGiveBack, "3", key(id, "owner"), key(id, "alive"), key(id, "adopt"), replica_});
}

bool HelpedJobs::adopt(const std::string& id, std::chrono::milliseconds lock,
                       std::chrono::milliseconds alive) {
  const auto replies = client_->pipeline(
      {{"SET", key(id, "adopt"), replica_, "NX", "PX", std::to_string(lock.count())}});
  if (!replies || (*replies)[0].type != RedisReply::Type::kStatus) return false;
  // The heartbeat as the job store writes it (RedisJobStore::alive_command).
  const std::string beat = std::to_string(std::max<std::int64_t>(1, alive.count()));
  return !any_error(client_->pipeline({{"HSET", key(id, "help"), "owner", replica_},
                                       {"SET", key(id, "owner"), replica_, "PX", ttl_ms_},
                                       {"SET", key(id, "alive"), beat, "PX", beat}}));
}

HelpedJobs::TableRead HelpedJobs::table(const std::string& id, std::size_t total) {
  std::vector<std::optional<RecipeRow>> slots(total);
  std::string from = "-";
  for (;;) {
    const auto read = client_->command(
        {"XRANGE", key(id, "items"), from, "+", "COUNT", std::to_string(kReadChunk)});
    if (!read || read->type != RedisReply::Type::kArray) return {std::nullopt, false, 0};
    std::vector<SharedItem> items = SharedJobQueue::items_of(*read);
    for (SharedItem& item : items) {
      if (item.index < total) slots[item.index] = std::move(item.recipe);
    }
    if (read->elements.size() < kReadChunk) break;
    from = "(" + read->elements.back().elements[0].text;
  }
  TableRead out;
  out.missing = static_cast<std::size_t>(
      std::count_if(slots.begin(), slots.end(), [](const auto& s) { return !s.has_value(); }));
  if (out.missing != 0) return out;
  out.recipes.emplace();
  out.recipes->reserve(total);
  for (auto& slot : slots) out.recipes->push_back(std::move(*slot));
  return out;
}

}  // namespace slosh::service
