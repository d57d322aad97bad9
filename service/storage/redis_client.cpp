#include "storage/redis_client.hpp"

#include <hiredis/hiredis.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <stdexcept>
#include <string_view>

namespace slosh::service {
namespace {

RedisReply convert(const redisReply& r) {
  RedisReply out;
  switch (r.type) {
    case REDIS_REPLY_STRING:
    case REDIS_REPLY_STATUS:
    case REDIS_REPLY_ERROR:
      out.type = r.type == REDIS_REPLY_STRING   ? RedisReply::Type::kString
                 : r.type == REDIS_REPLY_STATUS ? RedisReply::Type::kStatus
                                                : RedisReply::Type::kError;
      out.text.assign(r.str, r.len);
      break;
    case REDIS_REPLY_INTEGER:
      out.type = RedisReply::Type::kInteger;
      out.integer = r.integer;
      break;
    case REDIS_REPLY_ARRAY:
      out.type = RedisReply::Type::kArray;
      for (std::size_t i = 0; i < r.elements; ++i) out.elements.push_back(convert(*r.element[i]));
      break;
    default:
      out.type = RedisReply::Type::kNil;
  }
  return out;
}

timeval to_timeval(std::chrono::steady_clock::duration d) {
  const auto us =
      std::max<long long>(1000, std::chrono::duration_cast<std::chrono::microseconds>(d).count());
  return timeval{static_cast<time_t>(us / 1000000), static_cast<suseconds_t>(us % 1000000)};
}

/// The failure of context `c` in words ("no reply within 200 ms" for a socket timeout).
std::string context_error(const redisContext* c, std::chrono::milliseconds timeout) {
  if (c == nullptr) return "out of memory";
  const std::string text = c->errstr;
  if (c->err == REDIS_ERR_IO &&
      (text == std::strerror(EAGAIN) || text == std::strerror(EWOULDBLOCK) ||
       text.find("timed out") != std::string::npos)) {
    return "no reply within " + std::to_string(timeout.count()) + " ms";
  }
  if (c->err == REDIS_ERR_EOF) return "the server closed the connection";
  return text.empty() ? "connection error " + std::to_string(c->err) : text;
}

/// hiredis writes with write(2): a peer that closed makes it raise SIGPIPE, which would end the
/// process. The failure is handled as an error instead (EPIPE), so SIGPIPE is ignored unless the
/// program installed a handler of its own.
void ignore_sigpipe() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction current {};
    if (::sigaction(SIGPIPE, nullptr, &current) == 0 && current.sa_handler == SIG_DFL) {
      std::signal(SIGPIPE, SIG_IGN);
    }
  });
}

}  // namespace

struct RedisClient::Slot {
  std::timed_mutex mutex;
  redisContext* context{nullptr};
  std::uint64_t generation{0};  // failures_ when it connected
  ~Slot() {
    if (context != nullptr) redisFree(context);
  }
};

RedisClient::RedisClient(RedisOptions options) : options_(std::move(options)) {
  ignore_sigpipe();
  const std::size_t n = std::max<std::size_t>(1, options_.connections);
  for (std::size_t i = 0; i < n; ++i) slots_.push_back(std::make_unique<Slot>());
  (void)command({"PING"});  // logs the initial state
}

RedisClient::~RedisClient() = default;

bool RedisClient::may_try() {
  const std::lock_guard lock(state_mutex_);
  if (up_) return true;
  const auto now = Clock::now();
  if (now < retry_at_) return false;
  retry_at_ = now + options_.retry_interval;  // one probe; the others fail fast meanwhile
  return true;
}

void RedisClient::mark_up() {
  const std::lock_guard lock(state_mutex_);
  if (up_) return;
  if (known_) {
    spdlog::info("redis {} is up again; the shared cache level is back", options_.url.display());
  } else {
    spdlog::info("redis {} is up", options_.url.display());
  }
  up_ = true;
  known_ = true;
  error_.clear();
}

void RedisClient::mark_down(const std::string& error) {
  const std::lock_guard lock(state_mutex_);
  ++failures_;  // connections made before this failure are replaced on their next use
  last_failure_ = Clock::now();
  retry_at_ = last_failure_ + options_.retry_interval;
  error_ = error;
  if (!up_ && known_) return;
  spdlog::warn("redis {} is down ({}); answering from the local cache levels, retrying every {} ms",
               options_.url.display(), error, options_.retry_interval.count());
  up_ = false;
  known_ = true;
}

void RedisClient::probe() {
  {
    const std::lock_guard lock(state_mutex_);
    const auto now = Clock::now();
    if (now < next_probe_ || (!up_ && now < retry_at_)) return;
    next_probe_ = now + options_.retry_interval;
  }
  (void)command({"PING"});
}

RedisClient::State RedisClient::state() const {
  const std::lock_guard lock(state_mutex_);
  return State{up_, error_, last_failure_};
}

redisContext* RedisClient::connect(Slot& slot, Clock::time_point deadline, std::string& error) {
  std::uint64_t generation = 0;
  {
    const std::lock_guard lock(state_mutex_);
    generation = failures_;
  }
  if (slot.context != nullptr && slot.generation == generation && slot.context->err == 0) {
    return slot.context;
  }
  if (slot.context != nullptr) redisFree(slot.context);
  slot.generation = generation;
  const timeval tv = to_timeval(deadline - Clock::now());
  slot.context = redisConnectWithTimeout(options_.url.host.c_str(), options_.url.port, tv);
  if (slot.context == nullptr || slot.context->err != 0) {
    error = "cannot connect: " + context_error(slot.context, options_.timeout);
    return nullptr;
  }
  std::vector<std::vector<std::string>> setup;
  if (!options_.url.password.empty()) setup.push_back({"AUTH", options_.url.password});
  if (options_.url.db != 0) setup.push_back({"SELECT", std::to_string(options_.url.db)});
  if (setup.empty()) return slot.context;
  const auto replies = run(slot, setup, deadline, error);
  if (!replies) return nullptr;
  for (const RedisReply& r : *replies) {
    if (r.is_error()) {
      error = (r.text.starts_with("WRONGPASS") || r.text.starts_with("NOAUTH") ||
                       r.text.find("password") != std::string::npos
                   ? "authentication failed: "
                   : "selecting the database failed: ") +
              r.text;
      return nullptr;
    }
  }
  return slot.context;
}

std::optional<std::vector<RedisReply>> RedisClient::run(
    Slot& slot, const std::vector<std::vector<std::string>>& commands, Clock::time_point deadline,
    std::string& error) {
  redisContext* c = slot.context;
  redisSetTimeout(c, to_timeval(deadline - Clock::now()));
  for (const auto& args : commands) {
    std::vector<const char*> argv;
    std::vector<std::size_t> lengths;
    for (const std::string& a : args) {
      argv.push_back(a.data());
      lengths.push_back(a.size());
    }
    redisAppendCommandArgv(c, static_cast<int>(argv.size()), argv.data(), lengths.data());
  }
  std::vector<RedisReply> replies;
  for (std::size_t i = 0; i < commands.size(); ++i) {
    void* raw = nullptr;
    if (redisGetReply(c, &raw) != REDIS_OK || raw == nullptr) {
      error = context_error(c, options_.timeout);
      redisFree(c);
      slot.context = nullptr;
      return std::nullopt;
    }
    replies.push_back(convert(*static_cast<redisReply*>(raw)));
    freeReplyObject(raw);
  }
  return replies;
}

std::optional<std::vector<RedisReply>> RedisClient::pipeline(
    const std::vector<std::vector<std::string>>& commands) {
  if (commands.empty() || !may_try()) return std::nullopt;
  const auto deadline = Clock::now() + options_.timeout;
  std::size_t start = 0;
  {
    const std::lock_guard lock(next_mutex_);
    start = next_++ % slots_.size();
  }
  // A free connection if there is one; else wait for one (until the deadline).
  Slot* slot = nullptr;
  for (std::size_t i = 0; i < slots_.size() && slot == nullptr; ++i) {
    Slot& candidate = *slots_[(start + i) % slots_.size()];
    if (candidate.mutex.try_lock()) slot = &candidate;
  }
  if (slot == nullptr) {
    if (!slots_[start]->mutex.try_lock_until(deadline)) return std::nullopt;  // busy, not down
    slot = slots_[start].get();
  }
  const std::lock_guard lock(slot->mutex, std::adopt_lock);
  std::string error;
  std::optional<std::vector<RedisReply>> replies;
  if (connect(*slot, deadline, error) != nullptr) replies = run(*slot, commands, deadline, error);
  if (!replies) {
    if (slot->context != nullptr) {
      redisFree(slot->context);
      slot->context = nullptr;
    }
    mark_down(error);
    return std::nullopt;
  }
  mark_up();
  return replies;
}

std::optional<RedisReply> RedisClient::command(const std::vector<std::string>& args) {
  auto replies = pipeline({args});
  if (!replies) return std::nullopt;
  return std::move(replies->front());
}

}  // namespace slosh::service
