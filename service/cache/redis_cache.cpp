#include "cache/redis_cache.hpp"

#include <spdlog/spdlog.h>

#include <random>
#include <string_view>
#include <thread>
#include <vector>

#include "slosh/api/plan.hpp"

namespace slosh::service {
namespace {

constexpr std::string_view kMagic = "slosh1 ";

std::string digest_of(const std::string& redis_key, std::string_view body) {
  std::string text;
  text.reserve(redis_key.size() + 1 + body.size());
  text.append(redis_key).push_back('\n');
  text.append(body);
  return api::sha256_key(text);
}

}  // namespace

std::string redis_cache_value(const std::string& redis_key, const std::string& body) {
  std::string value(kMagic);
  value += digest_of(redis_key, body);
  value.push_back('\n');
  value += body;
  return value;
}

RedisCache::RedisCache(std::shared_ptr<RedisClient> client, const std::string& version,
                       const std::string& table, std::chrono::seconds ttl)
    : client_(std::move(client)),
      prefix_("slosh:v" + version + ":" + table + ":"),
      lock_prefix_("slosh:v" + version + ":lock:" + table + ":"),
      ttl_(ttl),
      renewer_([this] { renew_leases(); }) {}

RedisCache::~RedisCache() {
  {
    const std::lock_guard lock(leases_mutex_);
    stopping_ = true;
  }
  leases_wake_.notify_all();
  renewer_.join();
}

void RedisCache::renew_leases() {
  const std::string lease = std::to_string(kLockLease.count());
  std::unique_lock lock(leases_mutex_);
  while (!leases_wake_.wait_for(lock, kLockRenewal, [this] { return stopping_; })) {
    if (leases_.empty()) continue;
    std::vector<std::vector<std::string>> renewals;
    for (const auto& [name, token] : leases_) {
      renewals.push_back({"EVAL",
                          "if redis.call('GET', KEYS[1]) == ARGV[1] then "
                          "return redis.call('PEXPIRE', KEYS[1], ARGV[2]) end return 0",
                          "1", name, token, lease});
    }
    lock.unlock();
    (void)client_->pipeline(renewals);  // a lock Redis does not renew expires: others solve
    lock.lock();
  }
}

std::optional<std::string> RedisCache::get(const std::string& key) {
  const std::string name = redis_key(key);
  const auto reply = client_->command({"GET", name});
  if (!reply || reply->type != RedisReply::Type::kString) return std::nullopt;
  const std::string& value = reply->text;
  const std::size_t newline = value.find('\n');
  if (value.starts_with(kMagic) && newline != std::string::npos) {
    const std::string_view digest =
        std::string_view(value).substr(kMagic.size(), newline - kMagic.size());
    const std::string_view body = std::string_view(value).substr(newline + 1);
    if (digest == digest_of(name, body)) return std::string(body);
  }
  ++rejected_;
  spdlog::warn(
      "redis {}: the value of '{}' does not match its digest (changed, or not written by this "
      "slosh); it was deleted and is computed again",
      client_->options().url.display(), name.substr(0, 120));
  (void)client_->command({"DEL", name});
  return std::nullopt;
}

bool RedisCache::put(const std::string& key, const std::string& value) {
  const std::string name = redis_key(key);
  std::vector<std::string> args{"SET", name, redis_cache_value(name, value)};
  if (ttl_.count() > 0) {
    args.emplace_back("EX");
    args.push_back(std::to_string(ttl_.count()));
  }
  const auto reply = client_->command(args);
  return reply && !reply->is_error();
}

std::optional<std::string> RedisCache::lock_or_wait(const std::string& key,
                                                    std::chrono::milliseconds hold,
                                                    std::string& token) {
  thread_local std::mt19937_64 random{std::random_device{}()};
  const std::string candidate = std::to_string(random());
  const std::string lock = lock_prefix_ + key;
  const auto deadline = std::chrono::steady_clock::now() + hold;
  token.clear();
  while (true) {
    const auto taken =
        client_->command({"SET", lock, candidate, "NX", "PX", std::to_string(kLockLease.count())});
    if (!taken || taken->is_error()) return std::nullopt;  // Redis down: solve without a lock
    if (taken->type == RedisReply::Type::kStatus) {
      token = candidate;
      {
        const std::lock_guard held(leases_mutex_);
        leases_[lock] = token;
      }
      // The holder before may have stored the value and released the lock since our lookup.
      auto value = get(key);
      if (value) unlock(key, token);
      return value;
    }
    if (auto value = get(key)) return value;  // stored by the replica that holds the lock
    // Every slosh lock expires (PX): one without an expiry was not set by a replica and is not
    // waited for (a planted lock held every request of its recipe for 11 s).
    const auto ttl = client_->command({"PTTL", lock});
    if (!ttl || ttl->type != RedisReply::Type::kInteger || ttl->integer == -1) return std::nullopt;
    if (std::chrono::steady_clock::now() > deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

void RedisCache::unlock(const std::string& key, const std::string& token) {
  if (token.empty()) return;
  {
    const std::lock_guard held(leases_mutex_);
    if (auto it = leases_.find(lock_prefix_ + key); it != leases_.end() && it->second == token) {
      leases_.erase(it);
    }
  }
  (void)client_->command({"EVAL",
                          "if redis.call('GET', KEYS[1]) == ARGV[1] then "
                          "return redis.call('DEL', KEYS[1]) end return 0",
                          "1", lock_prefix_ + key, token});
}

}  // namespace slosh::service
