#pragma once
// A small, thread-safe Redis client (hiredis underneath) for the shared plan cache and the job
// store of several replicas (SPEC §13).
//
// It never throws to its callers and never blocks one longer than its timeout: a Redis that is
// down or slow makes a command answer nullopt, marks the client down (logged once per change of
// state) and, for the next retry_interval, fails every command at once without touching the
// network; then one command probes again, and a success marks it up (logged). Callers keep
// answering from their local levels meanwhile.

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "storage/redis_url.hpp"

struct redisContext;

namespace slosh::service {

/// One reply of Redis (a command's reply; an error reply is a reply too, not a failure).
struct RedisReply {
  enum class Type { kNil, kString, kStatus, kInteger, kArray, kError };
  Type type{Type::kNil};
  std::string text;  ///< kString, kStatus, kError
  long long integer{};
  std::vector<RedisReply> elements;  ///< kArray
  [[nodiscard]] bool is_error() const { return type == Type::kError; }
};

/// Settings of a RedisClient.
struct RedisOptions {
  RedisUrl url;
  /// Longest a command (with its connection set-up and its wait for a free connection) may take
  /// [ms]. Default 200.
  std::chrono::milliseconds timeout{200};
  /// While down, commands fail at once for this long before one probes Redis again [ms].
  /// Default 1000.
  std::chrono::milliseconds retry_interval{1000};
  /// Connections kept open (commands of more threads at once wait for one). Default 4.
  std::size_t connections{4};
};

class RedisClient {
 public:
  /// Connects once (bounded by the timeout) so that state() is known at start; never throws on
  /// a connection failure (the client starts down and retries).
  explicit RedisClient(RedisOptions options);
  ~RedisClient();
  RedisClient(const RedisClient&) = delete;
  RedisClient& operator=(const RedisClient&) = delete;

  /// Runs one command (binary-safe arguments); nullopt when Redis is down, slow or backing off.
  [[nodiscard]] std::optional<RedisReply> command(const std::vector<std::string>& args);
  /// Sends the commands in one round trip on one connection and returns their replies in order
  /// (MULTI ... EXEC in it makes them atomic); nullopt as command().
  [[nodiscard]] std::optional<std::vector<RedisReply>> pipeline(
      const std::vector<std::vector<std::string>>& commands);

  /// Asks Redis (PING, bounded by the timeout) at most once per retry interval and not while
  /// backing off, so that the state follows Redis without traffic (/readyz calls it).
  void probe();

  struct State {
    bool up{false};
    std::string error;  ///< the last failure while down; empty while up
    /// When a command last failed (epoch when none has).
    std::chrono::steady_clock::time_point last_failure{};
  };
  [[nodiscard]] State state() const;
  [[nodiscard]] const RedisOptions& options() const { return options_; }

 private:
  struct Slot;
  using Clock = std::chrono::steady_clock;
  // Whether a command may use the network now: up, or down and the retry interval has passed
  // (then the others keep failing fast until this probe's outcome).
  bool may_try();
  void mark_up();
  void mark_down(const std::string& error);
  // A connected context for `slot` within `deadline`; sets `error` and returns null on failure.
  redisContext* connect(Slot& slot, Clock::time_point deadline, std::string& error);
  std::optional<std::vector<RedisReply>> run(Slot& slot,
                                             const std::vector<std::vector<std::string>>& commands,
                                             Clock::time_point deadline, std::string& error);

  const RedisOptions options_;
  std::vector<std::unique_ptr<Slot>> slots_;
  std::mutex next_mutex_;
  std::size_t next_{0};

  mutable std::mutex state_mutex_;
  bool up_{false};
  bool known_{false};  // a state has been logged once
  std::string error_;
  Clock::time_point retry_at_{};
  Clock::time_point last_failure_{};
  Clock::time_point next_probe_{};
  std::uint64_t failures_{0};  // counts failures: connections older than the last are replaced
};

}  // namespace slosh::service
