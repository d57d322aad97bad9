#include "jobs/shared_job_queue.hpp"

#include <algorithm>
#include <cstdlib>
#include <utility>

#include "jobs/job_messages.hpp"
#include "jobs/replica_name.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/job_record.hpp"
#include "slosh/api/json_text.hpp"

namespace slosh::service {

namespace {

/// The consumer group of every job's stream.
constexpr const char* kWorkersGroup = "workers";

/// Items written to the stream in one round trip when a job is published.
constexpr std::size_t kPublishChunk = 500;

// Stores a row once by its index, counts it and acknowledges its item, in one step: a replica
// killed between two of these leaves either all done or none (the item is then taken over). The
// job's rows are bounded by its spec's max_bytes: the row that passes it is stored, then the job
// is closed ("over" in its counters) and its final record says failed.
// KEYS: spec, rows, counts, items, cancel, removed. ARGV: index, row, failed (0|1), replica,
// entry. Returns {1 new | 0 again | -1 closed, done}.
constexpr const char* kStoreScript = R"lua(
if redis.call('EXISTS', KEYS[1]) == 0 or redis.call('EXISTS', KEYS[5], KEYS[6]) > 0 or
   redis.call('HEXISTS', KEYS[3], 'over') == 1 then
  return {-1, tonumber(redis.call('HGET', KEYS[3], 'done') or '0')}
end
local new = redis.call('HSETNX', KEYS[2], ARGV[1], ARGV[2])
if new == 1 then
  redis.call('HINCRBY', KEYS[3], 'done', 1)
  if ARGV[3] == '1' then redis.call('HINCRBY', KEYS[3], 'failed', 1) end
  redis.call('HINCRBY', KEYS[3], 'r:' .. ARGV[4], 1)
  local bytes = redis.call('HINCRBY', KEYS[3], 'bytes', string.len(ARGV[2]))
  local max = tonumber(redis.call('HGET', KEYS[1], 'max_bytes') or '0')
  if max > 0 and bytes > max then redis.call('HSET', KEYS[3], 'over', '1') end
end
redis.call('XACK', KEYS[4], 'workers', ARGV[5])
return {new, tonumber(redis.call('HGET', KEYS[3], 'done') or '0')}
)lua";

// Writes a record unless the job was removed or already has its final record; a final record is
// written by the first replica only. KEYS: record, final, removed, alive. ARGV: text, final
// (0|1), ttl ms, alive ms.
constexpr const char* kRecordScript = R"lua(
if redis.call('EXISTS', KEYS[3]) == 1 then return 0 end
if ARGV[2] == '1' then
  if not redis.call('SET', KEYS[2], '1', 'NX', 'PX', ARGV[3]) then return 0 end
elseif redis.call('EXISTS', KEYS[2]) == 1 then
  return 0
end
redis.call('SET', KEYS[1], ARGV[1], 'PX', ARGV[3])
redis.call('SET', KEYS[4], ARGV[4], 'PX', ARGV[4])
return 1
)lua";

// The value of `field` in a flat field/value array reply (HGETALL, a stream entry's fields).
const std::string* field_of(const RedisReply& flat, const std::string& field) {
  for (std::size_t i = 0; i + 1 < flat.elements.size(); i += 2) {
    if (flat.elements[i].text == field) return &flat.elements[i + 1].text;
  }
  return nullptr;
}

std::size_t count_of(const RedisReply& flat, const std::string& field) {
  const std::string* v = field_of(flat, field);
  return v != nullptr ? static_cast<std::size_t>(std::strtoull(v->c_str(), nullptr, 10)) : 0;
}

}  // namespace

std::vector<std::string> SharedJobQueue::item_command(const std::string& stream,
                                                      const JobStatus& job, std::size_t index,
                                                      const RecipeRow& r) {
  std::vector<std::string> add{"XADD",
                               stream,
                               "*",
                               "i",
                               std::to_string(index),
                               "n",
                               std::to_string(r.row),
                               "rid",
                               r.recipe_id,
                               "req",
                               api::recipe_request_text(r.request),
                               "err",
                               api::recipe_error_text(r.error),
                               "csv",
                               r.csv ? "1" : "0",
                               "t",
                               std::to_string(job.total)};
  if (job.view) add.insert(add.end(), {"view", *job.view});
  return add;
}

SharedJobQueue::SharedJobQueue(std::shared_ptr<RedisClient> client, SharedQueueOptions options)
    : client_(std::move(client)), options_(std::move(options)) {}

std::string SharedJobQueue::key(const std::string& id, const char* part) const {
  return options_.prefix + id + ":" + part;
}

std::optional<std::string> SharedJobQueue::publish(const JobStatus& status,
                                                   const std::vector<RecipeRow>& recipes) {
  const std::string& id = status.id;
  const std::string ttl = std::to_string(options_.ttl.count());
  const std::string unavailable =
      "the shared job store (" + client_->options().url.display() + ") is unavailable: ";
  auto failed = [&](const std::optional<std::vector<RedisReply>>& replies) -> bool {
    if (!replies) return true;
    return std::any_of(replies->begin(), replies->end(), [](const RedisReply& r) {
      return r.is_error() && r.text.rfind("BUSYGROUP", 0) != 0;
    });
  };
  std::vector<std::string> spec{"HSET",       key(id, "spec"),
                                "total",      std::to_string(status.total),
                                "format",     status.format,
                                "created_ms", std::to_string(status.created_ms),
                                "max_bytes",  std::to_string(options_.max_bytes)};
  if (status.view) spec.insert(spec.end(), {"view", *status.view});
  if (failed(
          client_->pipeline({{"DEL", key(id, "items"), key(id, "final")},
                             spec,
                             {"PEXPIRE", key(id, "spec"), ttl},
                             {"XGROUP", "CREATE", key(id, "items"), kWorkersGroup, "0", "MKSTREAM"},
                             {"PEXPIRE", key(id, "items"), ttl}}))) {
    return unavailable +
           (client_->state().error.empty() ? "it refused the job" : client_->state().error);
  }
  for (std::size_t first = 0; first < recipes.size(); first += kPublishChunk) {
    std::vector<std::vector<std::string>> adds;
    for (std::size_t i = first; i < std::min(recipes.size(), first + kPublishChunk); ++i) {
      adds.push_back(item_command(key(id, "items"), status, i, recipes[i]));
    }
    if (failed(client_->pipeline(adds))) return unavailable + "the job's items were not all taken";
  }
  if (!write_record(id, api::job_record_text(status, unix_ms_now()), false) ||
      failed(client_->pipeline(
          {{"ZADD", options_.prefix + "shared", std::to_string(status.created_ms), id}}))) {
    return unavailable + "the job's record was not taken";
  }
  return std::nullopt;
}

std::vector<std::string> SharedJobQueue::jobs() {
  std::vector<std::string> out;
  const auto reply = client_->command({"ZRANGE", options_.prefix + "shared", "0", "-1"});
  if (!reply || reply->type != RedisReply::Type::kArray) return out;
  for (const RedisReply& r : reply->elements) out.push_back(r.text);
  return out;
}

std::vector<SharedItem> SharedJobQueue::items_of(const RedisReply& entries) {
  std::vector<SharedItem> out;
  for (const RedisReply& e : entries.elements) {
    // [id, [field, value, ...]]; an entry deleted meanwhile has no fields.
    if (e.elements.size() != 2 || e.elements[1].type != RedisReply::Type::kArray) continue;
    const RedisReply& fields = e.elements[1];
    SharedItem item;
    item.entry = e.elements[0].text;
    item.index = count_of(fields, "i");
    item.recipe.row = count_of(fields, "n");
    if (const std::string* rid = field_of(fields, "rid")) item.recipe.recipe_id = *rid;
    const std::string* req = field_of(fields, "req");
    const std::string* err = field_of(fields, "err");
    item.recipe.request = req != nullptr ? api::recipe_request_of_text(*req) : api::RecipeRequest();
    item.recipe.error = err != nullptr ? api::recipe_error_of_text(*err) : std::nullopt;
    const std::string* csv = field_of(fields, "csv");
    item.recipe.csv = csv != nullptr && *csv == "1";
    item.total = count_of(fields, "t");
    if (const std::string* view = field_of(fields, "view")) item.view = *view;
    out.push_back(std::move(item));
  }
  return out;
}

std::vector<SharedItem> SharedJobQueue::take(const std::string& id, std::size_t n,
                                             const std::set<std::string>& held) {
  const std::string stream = key(id, "items");
  std::vector<SharedItem> out;
  if (lost_.count(id) != 0) out = take_lost(id, n, held);
  if (out.size() < n) {
    const auto claimed = client_->command({"XAUTOCLAIM", stream, kWorkersGroup, options_.replica,
                                           std::to_string(options_.claim_idle.count()), "0-0",
                                           "COUNT", std::to_string(n - out.size())});
    if (!claimed) lost_.insert(id);  // it may have claimed entries all the same
    if (claimed && claimed->type == RedisReply::Type::kArray && claimed->elements.size() >= 2) {
      std::vector<SharedItem> over = items_of(claimed->elements[1]);
      count_takes(id, over);
      for (SharedItem& item : over) out.push_back(std::move(item));
    }
  }
  if (out.size() < n) {
    const auto read =
        client_->command({"XREADGROUP", "GROUP", kWorkersGroup, options_.replica, "COUNT",
                          std::to_string(n - out.size()), "STREAMS", stream, ">"});
    if (!read) lost_.insert(id);  // Redis may have handed entries out with the lost reply
    // [[stream, [entries]]], nil when there are none.
    if (read && read->type == RedisReply::Type::kArray && !read->elements.empty() &&
        read->elements[0].elements.size() == 2) {
      for (SharedItem& item : items_of(read->elements[0].elements[1])) {
        out.push_back(std::move(item));
      }
    }
  }
  if (!out.empty()) {
    (void)client_->command(
        {"HSETNX", key(id, "counts"), "started_ms", std::to_string(unix_ms_now())});
  }
  return out;
}

std::vector<SharedItem> SharedJobQueue::take_lost(const std::string& id, std::size_t n,
                                                  const std::set<std::string>& held) {
  // XPENDING of this consumer: [[entry, consumer, idle ms, deliveries], ...].
  const auto pending = client_->command(
      {"XPENDING", key(id, "items"), kWorkersGroup, "-", "+", "1000", options_.replica});
  if (!pending || pending->type != RedisReply::Type::kArray) return {};
  std::vector<std::string> claim{"XCLAIM", key(id, "items"), kWorkersGroup, options_.replica, "0"};
  for (const RedisReply& p : pending->elements) {
    if (claim.size() - 5 >= n) break;
    if (!p.elements.empty() && held.count(p.elements[0].text) == 0) {
      claim.push_back(p.elements[0].text);
    }
  }
  if (pending->elements.size() < 1000 && claim.size() == 5) lost_.erase(id);  // none lost
  if (claim.size() == 5) return {};
  // XCLAIM by this replica itself: the entries and their fields, counted as one more take.
  const auto claimed = client_->command(claim);
  if (!claimed || claimed->type != RedisReply::Type::kArray) return {};
  std::vector<SharedItem> out = items_of(*claimed);
  count_takes(id, out);
  return out;
}

void SharedJobQueue::count_takes(const std::string& id, std::vector<SharedItem>& items) {
  if (items.empty()) return;
  // XPENDING of one entry: [[id, consumer, idle ms, deliveries]]. XAUTOCLAIM counted this take.
  std::vector<std::vector<std::string>> asks;
  for (const SharedItem& item : items) {
    asks.push_back({"XPENDING", key(id, "items"), kWorkersGroup, item.entry, item.entry, "1"});
  }
  const auto replies = client_->pipeline(asks);
  if (!replies) return;
  for (std::size_t i = 0; i < items.size() && i < replies->size(); ++i) {
    const RedisReply& r = (*replies)[i];
    if (r.type != RedisReply::Type::kArray || r.elements.empty() ||
        r.elements[0].elements.size() < 4) {
      continue;
    }
    items[i].takes = static_cast<std::size_t>(std::max(1LL, r.elements[0].elements[3].integer));
  }
}

void SharedJobQueue::keep(const std::string& id, const std::vector<std::string>& entries) {
  if (entries.empty()) return;
  // XCLAIM by the holder itself resets the entries' idle time: nobody takes them over.
  std::vector<std::string> claim{"XCLAIM", key(id, "items"), kWorkersGroup, options_.replica, "0"};
  claim.insert(claim.end(), entries.begin(), entries.end());
  claim.emplace_back("JUSTID");
  (void)client_->command(claim);
}

SharedJobQueue::StoreResult SharedJobQueue::store(const std::string& id, const SharedItem& item,
                                                  const std::string& text, bool failed) {
  const auto reply = client_->command({"EVAL", kStoreScript, "6", key(id, "spec"), key(id, "rows"),
                                       key(id, "counts"), key(id, "items"), key(id, "cancel"),
                                       key(id, "removed"), std::to_string(item.index), text,
                                       failed ? "1" : "0", options_.replica, item.entry});
  if (!reply || reply->type != RedisReply::Type::kArray || reply->elements.size() != 2) {
    return {};
  }
  const long long what = reply->elements[0].integer;
  const auto done = static_cast<std::size_t>(std::max(0LL, reply->elements[1].integer));
  if (what < 0) return {Stored::kClosed, done};
  return {what == 1 ? Stored::kNew : Stored::kAgain, done};
}

bool SharedJobQueue::write_record(const std::string& id, const std::string& record, bool final) {
  const auto reply = client_->command(
      {"EVAL", kRecordScript, "4", key(id, "record"), key(id, "final"), key(id, "removed"),
       key(id, "alive"), record, final ? "1" : "0", std::to_string(options_.ttl.count()),
       std::to_string(std::max<std::int64_t>(1, options_.alive.count()))});
  return reply && reply->type == RedisReply::Type::kInteger;
}

std::optional<JobStatus> SharedJobQueue::compose(const std::string& id, const RedisReply& spec,
                                                 const RedisReply& counts, bool cancel) const {
  if (spec.type != RedisReply::Type::kArray || spec.elements.empty()) return std::nullopt;
  JobStatus s;
  s.id = id;
  s.total = count_of(spec, "total");
  if (const std::string* format = field_of(spec, "format")) s.format = *format;
  if (const std::string* view = field_of(spec, "view")) s.view = *view;
  s.created_ms = static_cast<std::int64_t>(count_of(spec, "created_ms"));
  s.done = count_of(counts, "done");
  s.failed = count_of(counts, "failed");
  if (field_of(counts, "started_ms") != nullptr) {
    s.started_ms = static_cast<std::int64_t>(count_of(counts, "started_ms"));
    s.state = JobState::kRunning;
  }
  for (std::size_t i = 0; i + 1 < counts.elements.size(); i += 2) {
    const std::string& name = counts.elements[i].text;
    if (name.rfind("r:", 0) == 0) s.shares.emplace_back(name.substr(2), count_of(counts, name));
  }
  std::sort(s.shares.begin(), s.shares.end());
  s.cancel_requested = cancel;
  return s;
}

SharedJobQueue::Snapshot SharedJobQueue::read(const std::string& id, bool renew) {
  const std::string ttl = std::to_string(options_.ttl.count());
  // The cancel flag is read before the counters: the store script takes no row once it is set,
  // so the final record of a cancelled job counts every row stored.
  std::vector<std::vector<std::string>> asks{{"EXISTS", key(id, "cancel"), key(id, "removed")},
                                             {"HGETALL", key(id, "spec")},
                                             {"HGETALL", key(id, "counts")},
                                             {"EXISTS", key(id, "final"), key(id, "removed")}};
  if (renew) {
    for (const char* part : {"spec", "counts", "rows", "items"}) {
      asks.push_back({"PEXPIRE", key(id, part), ttl});
    }
  }
  const auto replies = client_->pipeline(asks);
  Snapshot out;
  if (!replies || (*replies)[1].is_error() || (*replies)[2].is_error()) return out;
  out.answered = true;
  out.over = (*replies)[3].integer > 0;
  out.status = compose(id, (*replies)[1], (*replies)[2], (*replies)[0].integer > 0);
  out.too_large = field_of((*replies)[2], "over") != nullptr;
  out.max_bytes = count_of((*replies)[1], "max_bytes");
  return out;
}

bool SharedJobQueue::hold_name(const std::string& token) {
  return hold_replica_name(*client_, options_.prefix, options_.replica, token, options_.alive);
}

bool SharedJobQueue::request_cancel(const std::string& id) {
  const auto reply =
      client_->command({"SET", key(id, "cancel"), "1", "PX", std::to_string(options_.ttl.count())});
  return reply && reply->type == RedisReply::Type::kStatus;
}

std::optional<std::string> SharedJobQueue::live_record(const std::string& id) {
  const Snapshot now = read(id, false);
  if (!now.answered || now.over || !now.status) return std::nullopt;
  return api::job_record_text(*now.status, unix_ms_now());
}

SharedJobQueue::Fate SharedJobQueue::beat(const std::string& id) {
  Snapshot now = read(id, true);
  if (!now.answered) return Fate::kUnknown;
  const auto leave = [&](Fate fate) {
    (void)client_->pipeline({{"ZREM", options_.prefix + "shared", id}});
    return fate;
  };
  // A job removed (DELETE of a finished job) is over too, not lost: its owner must not publish
  // it again.
  if (now.over) return leave(Fate::kFinished);
  if (!now.status) return leave(Fate::kGone);
  JobStatus& s = *now.status;
  const bool cancel = s.cancel_requested;
  if (!cancel && !now.too_large && s.done < s.total) {
    if (write_record(id, api::job_record_text(s, unix_ms_now()), false)) return Fate::kRunning;
    // A full Redis (maxmemory, noeviction) refuses the record but takes the heartbeat's
    // PEXPIRE: the other replicas then read the job as alive and behind, not as stopped.
    (void)client_->command({"PEXPIRE", key(id, "alive"),
                            std::to_string(std::max<std::int64_t>(1, options_.alive.count()))});
    return Fate::kUnknown;
  }
  s.finished_ms = unix_ms_now();
  s.state = cancel ? JobState::kCancelled : JobState::kDone;
  if (cancel) {
    s.message =
        "cancelled after " + std::to_string(s.done) + " of " + std::to_string(s.total) + " recipes";
  } else if (now.too_large) {
    s.state = JobState::kFailed;
    s.message = too_large_text(now.max_bytes, s.done, s.total);
  }
  if (!write_record(id, api::job_record_text(s, unix_ms_now()), true)) return Fate::kUnknown;
  (void)client_->pipeline({{"DEL", key(id, "items")}});
  return leave(Fate::kFinished);
}

}  // namespace slosh::service
