#include "redis_client.hpp"

#include <hiredis/hiredis.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <stdexcept>
#include <string_view>

namespace slosh::service {
namespace {

constexpr std::string_view kScheme = "redis://";
constexpr int kMaxDb = 15;  // Redis' default number of databases is 16

bool all_digits(std::string_view text) {
  return !text.empty() && text.size() <= 9 &&
         std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// `text` with the password of its user part replaced by "***" (for messages and logs).
std::string masked(const std::string& text) {
  if (!text.starts_with(kScheme)) return text;
  const std::size_t at = text.rfind('@');
  if (at == std::string::npos) return text;
  const std::string user = text.substr(kScheme.size(), at - kScheme.size());
  const std::size_t colon = user.find(':');
  return std::string(kScheme) +
         (colon == std::string::npos ? "***" : user.substr(0, colon) + ":***") + text.substr(at);
}

[[noreturn]] void refuse(const std::string& text, const std::string& reason) {
  throw std::invalid_argument(masked(text) + " is not a Redis URL: " + reason +
                              " (expected redis://host:port/db or "
                              "redis://:password@host:port/db)");
}

/// Splits "host[:port]" or "[v6]:port" into `url`.
void parse_host_port(const std::string& text, std::string_view hostport, RedisUrl& url) {
  std::string_view port_text;
  if (hostport.starts_with('[')) {
    const std::size_t close = hostport.find(']');
    if (close == std::string_view::npos) refuse(text, "the IPv6 address lacks its ']'");
    url.host = std::string(hostport.substr(1, close - 1));
    const std::string_view rest = hostport.substr(close + 1);
    if (!rest.empty() && !rest.starts_with(':')) refuse(text, "':port' must follow ']'");
    if (!rest.empty()) port_text = rest.substr(1);
    if (rest == ":") port_text = ":";  // an empty port is an error below
  } else {
    const std::size_t colon = hostport.find(':');
    url.host = std::string(hostport.substr(0, colon));
    if (colon != std::string_view::npos) {
      port_text = hostport.substr(colon + 1);
      if (port_text.empty()) port_text = ":";
    }
  }
  if (url.host.empty()) refuse(text, "the host is empty");
  if (port_text.empty()) return;
  const bool number = all_digits(port_text);
  const long port = number ? std::stol(std::string(port_text)) : 0;
  if (!number || port < 1 || port > 65535) {
    refuse(text, "the port '" + std::string(port_text == ":" ? "" : port_text) +
                     "' is not a number from 1 to 65535");
  }
  url.port = static_cast<int>(port);
}

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

std::string RedisUrl::display() const {
  const bool v6 = host.find(':') != std::string::npos;
  return std::string(kScheme) + (password.empty() ? "" : ":***@") + (v6 ? "[" + host + "]" : host) +
         ":" + std::to_string(port) + "/" + std::to_string(db);
}

bool is_redis_url(const std::string& text) {
  return text.starts_with(kScheme);
}

RedisUrl parse_redis_url(const std::string& text) {
  if (!is_redis_url(text)) refuse(text, "it does not start with redis://");
  RedisUrl url;
  std::string_view rest = std::string_view(text).substr(kScheme.size());
  if (rest.find_first_of("?#") != std::string_view::npos) {
    refuse(text, "query parameters and fragments are not supported");
  }
  if (const std::size_t at = rest.rfind('@'); at != std::string_view::npos) {
    const std::string_view user = rest.substr(0, at);
    if (!user.starts_with(':')) {
      refuse(text, "a user name is not supported (write the password as ':password@')");
    }
    url.password = std::string(user.substr(1));
    if (url.password.empty()) refuse(text, "the password after ':' is empty");
    rest = rest.substr(at + 1);
  }
  const std::size_t slash = rest.find('/');
  parse_host_port(text, rest.substr(0, slash), url);
  if (slash != std::string_view::npos && slash + 1 < rest.size()) {
    const std::string_view db = rest.substr(slash + 1);
    const bool number = all_digits(db);
    const long value = number ? std::stol(std::string(db)) : -1;
    if (!number || value > kMaxDb) {
      refuse(text, "the database '" + std::string(db) + "' is not a number from 0 to " +
                       std::to_string(kMaxDb));
    }
    url.db = static_cast<int>(value);
  }
  return url;
}

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
  retry_at_ = Clock::now() + options_.retry_interval;
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
  return State{up_, error_};
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
