#pragma once
// The per-recipe plan cache: an in-memory LRU tier in front of a persistent SQLite store, and
// optionally a Redis shared by several replicas behind both (SPEC §13).
//
// Values are opaque text (the rendered plan JSON, or a min-time answer) keyed by the request key
// (a hex string). An answer is a pure function of its request, so the value of a key never
// changes meaning: the cache never expires entries, only evicts them from memory (they stay on
// disk); values in Redis expire only when a TTL is configured.

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "cache/cache_level.hpp"
#include "config/version.hpp"
#include "storage/sqlite_db.hpp"

namespace slosh::service {

class RedisClient;
class RedisCache;

/// Layout of the store file (PRAGMA user_version): 2 = table `plans` of api::StoredPlan bodies
/// (without the per-reply `cached` member); 3 = the same with a digest per row, and table
/// `min_times` of stored min-time answers; 4 = the same with the slosh version that wrote each row
/// (column `version`, covered by the digest). Opening a file of layout 2 or 3 empties it: its
/// answers were made by a slosh that recorded no version (an older planner, whose answers are
/// never served) and their keys hold no version. A file of any other layout (older, or written by
/// a newer slosh) is emptied too (a cache: answers are computed again on demand).
constexpr int kStoreLayoutVersion = 4;

/// The tables of the store file: each cache instance reads and writes one of them, so a key of
/// one kind is never answered from the other.
enum class CacheTable {
  kPlans,    ///< `plans`: api::StoredPlan bodies by recipe key
  kMinTime,  ///< `min_times`: stored min-time answers (api::stored_min_time) by min-time key
};

/// Settings of the plan cache.
struct CacheConfig {
  /// SQLite file; empty = memory only. Default empty.
  std::string path;
  /// LRU capacity of the memory tier (entries); 0 = no memory tier. Default 10000.
  std::size_t memory_entries{10000};
  /// LRU capacity of the memory tier [bytes of keys, values and the renderings kept with them
  /// (CachedValue)]; the least recent plans are evicted beyond it, with their renderings (a plan
  /// larger than this is kept on disk only). Default 256 MiB.
  std::size_t memory_bytes{std::size_t{256} << 20};
  /// Largest size of the plans in the SQLite store [bytes of values]; beyond it the oldest plans
  /// are deleted down to 90 % of it (freed pages are reused, so the file stays near this size).
  /// 0 = unbounded. Default 1 GiB.
  std::size_t store_bytes{std::size_t{1} << 30};
  /// How long a write waits for a lock held by another connection to the file [ms]. Default 5000.
  int busy_timeout_ms{5000};
  /// The table of the store this cache uses (store_bytes bounds that table). Default plans.
  CacheTable table{CacheTable::kPlans};
  /// The slosh version whose answers this cache writes and serves: a row of another version is
  /// never served (it stays in the file for that version until pruned). Default slosh::kVersion.
  std::string version{kVersion};
  /// The shared level behind memory and SQLite (a Redis several replicas use); null = none.
  /// Default none.
  std::shared_ptr<RedisClient> redis{};
  /// Expiry of the values this cache writes to Redis [s]; 0 = none (an answer never goes stale:
  /// the version is part of its key). Default 0.
  std::chrono::seconds redis_ttl{0};
  /// Whether a value read from SQLite or Redis may be served (one an older build wrote that this
  /// build would not store, e.g. a plan that depended on its time budget, is a miss); null = every
  /// value. Values in memory were put by this process and are not checked again. Default null.
  std::function<bool(std::string_view)> servable{};
};

/// A value of the cache as its memory tier holds it, shared by the requests that read it (a hit
/// hands out a pointer, never a copy of the value), with what is rendered from it (a plan's views,
/// see rendered_plans.hpp): up to kRenderings texts, each made at its first use
/// (PlanCache::rendering) and kept while the value stays in memory, in the memory tier's bytes.
class CachedValue {
 public:
  /// Slots of renderings per value.
  static constexpr std::size_t kRenderings{4};

  CachedValue(std::string key, std::string value)
      : key_(std::move(key)), value_(std::move(value)) {}
  CachedValue(const CachedValue&) = delete;
  CachedValue& operator=(const CachedValue&) = delete;

  [[nodiscard]] const std::string& key() const { return key_; }
  [[nodiscard]] const std::string& value() const { return value_; }

 private:
  friend class PlanCache;
  const std::string key_;
  const std::string value_;
  // Each slot is written once, under its flag, and only read after it.
  mutable std::array<std::once_flag, kRenderings> once_;
  mutable std::array<std::string, kRenderings> renderings_;
};

/// In-memory LRU in front of a persistent SQLite store (WAL mode, one file), and optionally a
/// shared Redis level behind both (config.redis, see RedisCache). Thread-safe. Values are opaque
/// text (the rendered plan JSON), keyed by the recipe key (hex string).
///
/// Levels: get() asks memory, then SQLite, then Redis, and promotes a hit into the faster levels
/// (a SQLite hit into memory; a Redis hit into SQLite and memory). put() writes through to all
/// of them. Redis down or slow costs a get or put at most the client's timeout once, then nothing
/// while the client backs off: the cache keeps answering from its local levels.
///
/// The store file holds two tables of the same shape, `plans` and `min_times` (key TEXT PRIMARY
/// KEY, body TEXT NOT NULL, created_unix INTEGER NOT NULL, digest TEXT NOT NULL: the
/// api::sha256_key of the key, the version and the body, version TEXT NOT NULL: the slosh version
/// that wrote the row); a cache uses the one of `config.table` (two caches on one file are two
/// connections). A row whose key, version or body no longer matches its digest (bytes changed on
/// disk) is never served: get() answers absent, deletes the row and records the failure. A row of
/// another version than `config.version` is never served either (get() answers absent). The file
/// is opened in WAL mode with synchronous=NORMAL: committed entries survive a restart and a process
/// crash (a power loss may drop the last few). Its layout is versioned (PRAGMA user_version,
/// kStoreLayoutVersion). Every put is written through at once (one transaction each). A store that
/// cannot be opened or written never makes the cache throw: the failure is recorded in
/// storage_error() and the cache keeps answering from memory.
///
/// Locking: the LRU tier has its own short lock (no I/O under it); SQLite I/O runs under a second
/// lock, so readers of memory-resident entries never wait for the disk.
class PlanCache {
 public:
  /// Opens (creating when missing) the store at `config.path`, unless the path is empty. Never
  /// throws on a storage failure: see storage_error().
  explicit PlanCache(CacheConfig config);
  /// Closes the store (the WAL is checkpointed into the file by SQLite).
  ~PlanCache();
  PlanCache(const PlanCache&) = delete;
  PlanCache& operator=(const PlanCache&) = delete;

  /// The value of `key`: from memory, else from SQLite (then promoted into memory), else from
  /// Redis (then promoted into SQLite and memory); nullopt when absent. A read failure of the store
  /// counts as absent and is recorded in storage_error(). `level` (optional) receives the level
  /// of a hit.
  [[nodiscard]] std::optional<std::string> get(const std::string& key, CacheLevel* level = nullptr);
  /// As get, without copying the value: the memory tier's entry of `key`, or for a value the
  /// memory tier does not keep (none configured, or larger than its bytes) one made for this
  /// caller alone (its renderings are then dropped with it); null when absent.
  [[nodiscard]] std::shared_ptr<const CachedValue> find(const std::string& key,
                                                        CacheLevel* level = nullptr);
  /// Stores in memory and (write-through) in SQLite and Redis, replacing any previous value. Never
  /// throws on a storage failure: records it in storage_error() (cleared again by a later
  /// successful write); a Redis failure is the client's state. Returns the value's entry (as
  /// find would).
  std::shared_ptr<const CachedValue> put(const std::string& key, const std::string& value);
  /// Rendering `slot` (< CachedValue::kRenderings) of `entry`: made by `render(entry.value())` at
  /// its first use (concurrent callers wait for that one; an exception leaves the slot empty for
  /// the next caller) and kept with the entry. While the entry is in the memory tier its rendering
  /// counts in memory_bytes, and the least recent entries are evicted beyond the bounds.
  template <typename Render>
  const std::string& rendering(const std::shared_ptr<const CachedValue>& entry, std::size_t slot,
                               Render&& render) {
    bool made = false;
    std::call_once(entry->once_.at(slot), [&] {
      entry->renderings_[slot] = render(entry->value());
      made = true;
    });
    const std::string& text = entry->renderings_[slot];
    if (made) count_rendering(entry, text.size());
    return text;
  }
  /// Stores in memory and SQLite only (a value that came from the shared level).
  std::shared_ptr<const CachedValue> put_local(const std::string& key, const std::string& value) {
    return write_local(key, value);
  }

  /// Counters and state of the cache.
  struct Stats {
    std::uint64_t hits{};             ///< gets answered from any level
    std::uint64_t memory_hits{};      ///< ... from memory
    std::uint64_t local_hits{};       ///< ... from SQLite
    std::uint64_t shared_hits{};      ///< ... from Redis
    std::uint64_t misses{};           ///< gets answered nullopt
    std::uint64_t shared_rejected{};  ///< Redis values dropped for a bad digest
    std::size_t memory_entries{};     ///< entries in the memory tier now
    std::size_t memory_bytes{};  ///< bytes of keys, values and renderings in the memory tier now
    std::size_t store_bytes{};   ///< bytes of plans in the store (approximate between prunes)
    bool persistent{};           ///< a SQLite store is open (false: memory only)
    std::string storage_error;   ///< as storage_error()
  };
  [[nodiscard]] Stats stats() const;

  /// Empty while the persistent store works (or none is configured); else a sentence naming the
  /// file and the SQLite error (the cache then keeps answering from memory).
  [[nodiscard]] std::string storage_error() const;

  /// Whether `key` is in the memory tier, without touching its recency (diagnostics and tests).
  [[nodiscard]] bool in_memory(const std::string& key) const;

  [[nodiscard]] const CacheConfig& config() const { return config_; }
  /// The shared level; null without Redis.
  [[nodiscard]] RedisCache* shared() const { return shared_.get(); }

 private:
  // An entry of the memory tier and the bytes it is counted for (its key, value and renderings).
  struct Resident {
    std::shared_ptr<const CachedValue> value;
    std::size_t bytes{};
  };

  void open_store();
  void close_store();
  void set_error(std::string message);
  // Deletes the oldest plans of the store until they hold at most 90 % of store_bytes (under
  // store_mutex_).
  void prune_store_locked();
  // Deletes the row of `key`, whose body does not match its digest, and records the failure
  // (under store_mutex_): the caller answers a miss, so the answer is computed and stored again.
  void drop_corrupt_locked(const std::string& key);
  void clear_error();
  // The value of `key` in SQLite (takes store_mutex_); drops a corrupt row.
  std::optional<std::string> read_store(const std::string& key);
  // Stores in memory and SQLite (takes store_mutex_); the value's entry.
  std::shared_ptr<const CachedValue> write_local(const std::string& key, const std::string& value);
  /// Inserts or refreshes `entry` as most recent, evicting the least recent beyond capacity.
  void remember_locked(const std::shared_ptr<const CachedValue>& entry);
  /// Evicts the least recent entries while the memory tier is beyond its bounds.
  void evict_locked();
  /// Adds `bytes` of a new rendering of `entry` to the memory tier while that entry is resident.
  void count_rendering(const std::shared_ptr<const CachedValue>& entry, std::size_t bytes);

  const CacheConfig config_;
  const std::string table_;  // "plans" or "min_times"
  const std::string noun_;   // "a plan" or "a min-time answer" (messages)

  // Memory tier: most recent first.
  mutable std::mutex memory_mutex_;
  std::list<Resident> lru_;
  std::unordered_map<std::string, std::list<Resident>::iterator> index_;
  std::size_t memory_bytes_{};
  std::uint64_t memory_hits_{};
  std::uint64_t local_hits_{};
  std::uint64_t shared_hits_{};
  std::uint64_t misses_{};

  // Persistent tier. Lock order: store_mutex_ before memory_mutex_ (never the reverse).
  std::mutex store_mutex_;
  SqliteDb db_;
  SqliteStatement select_;
  SqliteStatement upsert_;
  // SUM of the plans' sizes, counted up by puts between prunes (written under store_mutex_).
  std::atomic<std::size_t> store_bytes_{0};

  // Shared level; null when none is configured.
  std::unique_ptr<RedisCache> shared_;

  // State reported by stats() and storage_error(), readable while the store is busy.
  mutable std::mutex error_mutex_;
  std::string storage_error_;
  bool persistent_{false};
};

}  // namespace slosh::service
