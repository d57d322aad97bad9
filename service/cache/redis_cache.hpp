#pragma once
// The shared level of the plan cache: plans (or min-time answers) on a Redis that several
// replicas use (SPEC §13), behind their memory and SQLite levels.
//
// Key: slosh:v<version>:<table>:<key> (table plans or min_times), so that another slosh version's
// answers and the other table's keys are never read. Value: "slosh1 <digest>\n<body>", where the
// digest is api::sha256_key of the Redis key and the body: a value that was changed, truncated,
// copied under another key or written by something else is never served (it is deleted and the
// answer computed again). The digest catches corruption and foreign writers, not an attacker who
// can write to Redis and recompute SHA-256: Redis must be on a network only the replicas reach.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "storage/redis_client.hpp"

namespace slosh::service {

class RedisCache {
 public:
  /// `table`: plans or min_times; `ttl`: expiry of each value written (0 = none).
  RedisCache(std::shared_ptr<RedisClient> client, const std::string& version,
             const std::string& table, std::chrono::seconds ttl);
  /// Stops renewing the locks held (they expire within kLockLease, as a dead replica's do).
  ~RedisCache();
  RedisCache(const RedisCache&) = delete;
  RedisCache& operator=(const RedisCache&) = delete;

  /// A lock taken by lock_or_wait is a lease of this long, renewed every kLockRenewal by a thread
  /// of this cache until unlock(): a replica that dies or is paused holding it delays the others
  /// by at most the lease, however long the solve's budget.
  static constexpr std::chrono::milliseconds kLockLease{3000};
  static constexpr std::chrono::milliseconds kLockRenewal{1000};

  /// The value of `key`; nullopt when absent, rejected (bad digest: deleted, logged) or when
  /// Redis is down or slow (the client's timeout bounds the wait).
  [[nodiscard]] std::optional<std::string> get(const std::string& key);
  /// Stores `value` (with the TTL); false when Redis is down or slow.
  bool put(const std::string& key, const std::string& value);

  /// Cross-replica single flight before a solve of `key`: takes the lock
  /// slosh:v<version>:lock:<table>:<key> (SET NX PX kLockLease, renewed while held: a lock whose
  /// replica died or was paused expires by itself). While another replica holds it, polls every
  /// 20 ms for the value it writes (then answers it) or for the lock to go (then takes it), for
  /// at most `hold`. Returns the value when another replica stored it; else nullopt, and `token`
  /// names the lock taken ("" when none was: Redis down, or still held after `hold`; the caller
  /// then solves without one).
  [[nodiscard]] std::optional<std::string> lock_or_wait(const std::string& key,
                                                        std::chrono::milliseconds hold,
                                                        std::string& token);
  /// Releases the lock of `key` if it is still `token`'s (never another replica's).
  void unlock(const std::string& key, const std::string& token);

  /// The Redis key of `key`.
  [[nodiscard]] std::string redis_key(const std::string& key) const { return prefix_ + key; }
  /// Values rejected for a digest that did not match (since start).
  [[nodiscard]] std::uint64_t rejected() const { return rejected_; }
  [[nodiscard]] RedisClient& client() const { return *client_; }

 private:
  const std::shared_ptr<RedisClient> client_;
  const std::string prefix_;
  const std::string lock_prefix_;
  const std::chrono::seconds ttl_;
  std::atomic<std::uint64_t> rejected_{0};

  // The locks this cache holds (lock key -> token) and the thread that renews them.
  void renew_leases();
  std::mutex leases_mutex_;
  std::condition_variable leases_wake_;
  std::map<std::string, std::string> leases_;
  bool stopping_{false};
  std::thread renewer_;  // last: started once the members above exist
};

/// The stored form of `body` under Redis key `redis_key` (exposed for the tests).
[[nodiscard]] std::string redis_cache_value(const std::string& redis_key, const std::string& body);

}  // namespace slosh::service
