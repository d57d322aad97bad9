#include "cache/plan_cache.hpp"

#include <spdlog/spdlog.h>
#include <sqlite3.h>

#include "cache/redis_cache.hpp"
#include "slosh/api/plan.hpp"
#include "storage/sqlite_db.hpp"

#include <array>
#include <chrono>
#include <climits>
#include <string_view>

namespace slosh::service {
namespace {

/// Both tables of the layout, whichever cache opens the file first. `digest` is row_digest of the
/// key, the version and the body: SQLite checks its pages' structure, not their content, so a row
/// whose bytes changed on disk is only caught by its digest.
constexpr std::string_view kSchema =
    "CREATE TABLE IF NOT EXISTS plans(key TEXT PRIMARY KEY, body TEXT NOT NULL, "
    "created_unix INTEGER NOT NULL, digest TEXT NOT NULL DEFAULT '', "
    "version TEXT NOT NULL DEFAULT '');"
    "CREATE TABLE IF NOT EXISTS min_times(key TEXT PRIMARY KEY, body TEXT NOT NULL, "
    "created_unix INTEGER NOT NULL, digest TEXT NOT NULL DEFAULT '', "
    "version TEXT NOT NULL DEFAULT '')";
constexpr std::array<std::string_view, 2> kTables{"plans", "min_times"};
/// The columns that layouts before kStoreLayoutVersion lack (digest: layout 2; version: 2 and 3).
constexpr std::array<std::string_view, 2> kAddedColumns{"digest", "version"};

std::string table_name(CacheTable table) {
  return table == CacheTable::kMinTime ? "min_times" : "plans";
}

/// The digest of a row: of its key, its version and its body, so that none of them can change on
/// disk unnoticed.
std::string row_digest(std::string_view key, std::string_view version, std::string_view body) {
  std::string text;
  text.reserve(key.size() + version.size() + 2 + body.size());
  text.append(key).push_back('\n');
  text.append(version).push_back('\n');
  text.append(body);
  return api::sha256_key(text);
}

/// Brings the file to kStoreLayoutVersion in one write transaction (so two connections opening it
/// at once migrate it once): creates the tables and the columns they lack; a file of any other
/// layout is emptied (layouts 2 and 3 recorded no version: their answers are an older planner's).
/// Sets `error` on failure.
void migrate_layout(const SqliteDb& db, std::string& error) {
  db.execute("BEGIN IMMEDIATE", error);
  if (!error.empty()) return;
  db.execute(kSchema, error);
  const std::string current = std::to_string(kStoreLayoutVersion);
  std::string found = error.empty() ? db.query_text("PRAGMA user_version", error) : "";
  for (std::string_view table : kTables) {
    for (std::string_view column : kAddedColumns) {
      const std::string name(table);
      const std::string col(column);
      if (error.empty() && db.query_text("SELECT COUNT(*) FROM pragma_table_info('" + name +
                                             "') WHERE name = '" + col + "'",
                                         error) == "0") {
        db.execute("ALTER TABLE " + name + " ADD COLUMN " + col + " TEXT NOT NULL DEFAULT ''",
                   error);
        // A file that says this layout but lacks its columns is of no layout this slosh knows.
        if (found == current) found = "unknown";
      }
    }
  }
  if (error.empty() && found != current) {
    for (std::string_view table : kTables) {
      if (error.empty()) db.execute("DELETE FROM " + std::string(table), error);
    }
    if (error.empty()) db.execute("PRAGMA user_version = " + current, error);
  }
  if (error.empty()) db.execute("COMMIT", error);
  if (!error.empty()) {
    std::string ignored;  // the failure that caused the rollback is the one to report
    db.execute("ROLLBACK", ignored);
  }
}

std::int64_t now_unix() {
  return std::chrono::duration_cast<std::chrono::seconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

PlanCache::PlanCache(CacheConfig config)
    : config_(std::move(config)),
      table_(table_name(config_.table)),
      noun_(config_.table == CacheTable::kMinTime ? "a min-time answer" : "a plan") {
  if (!config_.path.empty()) open_store();
  if (config_.redis) {
    shared_ =
        std::make_unique<RedisCache>(config_.redis, config_.version, table_, config_.redis_ttl);
  }
}

PlanCache::~PlanCache() {
  close_store();
}

void PlanCache::open_store() {
  std::string error;
  if (db_.open(config_.path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
               error)) {
    db_.busy_timeout(config_.busy_timeout_ms);
    // A file of garbage opens fine; the first statement reports "file is not a database".
    const std::string mode = db_.query_text("PRAGMA journal_mode=WAL", error);
    if (error.empty() && mode != "wal") {
      error = "journal_mode is '" + mode + "', WAL could not be enabled";
    }
    if (error.empty()) db_.query_text("PRAGMA synchronous=NORMAL", error);
    if (error.empty() && db_.read_only()) error = "the file is read-only";
    if (error.empty()) migrate_layout(db_, error);
    if (error.empty()) {
      select_ =
          db_.prepare("SELECT body, digest, version FROM " + table_ + " WHERE key = ?1", true);
      upsert_ = db_.prepare("INSERT OR REPLACE INTO " + table_ +
                                "(key, body, created_unix, digest, version) "
                                "VALUES(?1, ?2, ?3, ?4, ?5)",
                            true);
      if (!select_ || !upsert_) error = db_.message();
    }
    if (error.empty()) {
      store_bytes_ = std::stoull(
          "0" + db_.query_text("SELECT SUM(LENGTH(CAST(body AS BLOB))) FROM " + table_, error));
    }
  }
  if (!error.empty()) {
    close_store();
    set_error("plan cache store '" + config_.path + "' is unavailable (" + error +
              "); serving from memory only");
    return;
  }
  const std::lock_guard lock(error_mutex_);
  persistent_ = true;
}

void PlanCache::close_store() {
  select_ = SqliteStatement();
  upsert_ = SqliteStatement();
  db_.close();
  const std::lock_guard lock(error_mutex_);
  persistent_ = false;
}

void PlanCache::set_error(std::string message) {
  const std::lock_guard lock(error_mutex_);
  if (message != storage_error_) spdlog::error("{}", message);  // once per distinct failure
  storage_error_ = std::move(message);
}

void PlanCache::clear_error() {
  const std::lock_guard lock(error_mutex_);
  if (!storage_error_.empty()) spdlog::info("plan cache store '{}' works again", config_.path);
  storage_error_.clear();
}

void PlanCache::remember_locked(const std::shared_ptr<const CachedValue>& entry) {
  const std::string& key = entry->key();
  const std::size_t bytes = key.size() + entry->value().size();
  if (const auto it = index_.find(key); it != index_.end()) {
    memory_bytes_ -= it->second->bytes;
    lru_.erase(it->second);
    index_.erase(it);
  }
  if (config_.memory_entries == 0 || bytes > config_.memory_bytes) return;
  lru_.push_front(Resident{entry, bytes});
  index_.emplace(key, lru_.begin());
  memory_bytes_ += bytes;
  evict_locked();
}

void PlanCache::evict_locked() {
  while (!lru_.empty() &&
         (lru_.size() > config_.memory_entries || memory_bytes_ > config_.memory_bytes)) {
    memory_bytes_ -= lru_.back().bytes;
    index_.erase(lru_.back().value->key());
    lru_.pop_back();
  }
}

void PlanCache::count_rendering(const std::shared_ptr<const CachedValue>& entry,
                                std::size_t bytes) {
  // Counted only while this very entry is resident: one replaced or evicted meanwhile is dropped
  // with its renderings when its last reader lets go.
  const std::lock_guard memory(memory_mutex_);
  if (const auto it = index_.find(entry->key()); it != index_.end() && it->second->value == entry) {
    it->second->bytes += bytes;
    memory_bytes_ += bytes;
    evict_locked();
  }
}

void PlanCache::drop_corrupt_locked(const std::string& key) {
  std::string error;
  SqliteStatement remove = db_.prepare("DELETE FROM " + table_ + " WHERE key = ?1");
  if (!remove || remove.bind_text(1, key, false) != SQLITE_OK || remove.step() != SQLITE_DONE) {
    error = db_.message();
  }
  set_error("plan cache store '" + config_.path + "': the stored bytes of " + noun_ + " (key '" +
            key.substr(0, 64) + "') do not match their digest" +
            (error.empty() ? "; the row was dropped and is computed again"
                           : "; dropping the row failed (" + error + ")"));
}

void PlanCache::prune_store_locked() {
  std::string error;
  const std::size_t target = config_.store_bytes / 10 * 9;
  while (error.empty() && store_bytes_ > target) {
    // The oldest tenth of the rows (at least one) per round, then the size as SQLite counts it.
    db_.query_text("DELETE FROM " + table_ + " WHERE rowid IN (SELECT rowid FROM " + table_ +
                       " ORDER BY created_unix, rowid LIMIT MAX(1, (SELECT COUNT(*) FROM " +
                       table_ + ") / 10))",
                   error);
    if (error.empty()) {
      store_bytes_ = std::stoull(
          "0" + db_.query_text("SELECT SUM(LENGTH(CAST(body AS BLOB))) FROM " + table_, error));
    }
  }
  if (!error.empty()) {
    set_error("plan cache store '" + config_.path + "': pruning old " +
              (config_.table == CacheTable::kMinTime ? "min-time answers" : "plans") + " failed (" +
              error + ")");
  }
}

std::optional<std::string> PlanCache::read_store(const std::string& key) {
  // Puts hold store_mutex_ across their memory and disk updates, so what is read here is the
  // latest value of the key.
  std::optional<std::string> value;
  bool corrupt = false;
  const std::lock_guard store(store_mutex_);
  if (db_) {
    if (select_.bind_text(1, key, false) != SQLITE_OK) {
      set_error("plan cache store '" + config_.path + "': reading " + noun_ + " failed (" +
                db_.message() + ")");
    } else {
      const int rc = select_.step();
      if (rc == SQLITE_ROW) {
        value.emplace(select_.column(0));
        const std::string_view digest = select_.column(1);
        const std::string_view row_version = select_.column(2);
        if (select_.column_is_null(1) || row_digest(key, row_version, *value) != digest) {
          value.reset();
          corrupt = true;
        } else if (row_version != config_.version) {
          value.reset();  // another slosh's answer: never served (its key is not ours either)
        } else if (config_.servable && !config_.servable(*value)) {
          value.reset();
        }
      } else if (rc != SQLITE_DONE) {
        set_error("plan cache store '" + config_.path + "': reading " + noun_ + " failed (" +
                  db_.message() + ")");
      }
    }
    select_.reset();
    if (corrupt) drop_corrupt_locked(key);
  }
  return value;
}

std::optional<std::string> PlanCache::get(const std::string& key, CacheLevel* level) {
  const auto entry = find(key, level);
  if (!entry) return std::nullopt;
  return entry->value();
}

std::shared_ptr<const CachedValue> PlanCache::find(const std::string& key, CacheLevel* level) {
  const auto hit = [&](CacheLevel where, std::uint64_t& counter) {
    ++counter;
    if (level != nullptr) *level = where;
  };
  {
    const std::lock_guard memory(memory_mutex_);
    if (const auto it = index_.find(key); it != index_.end()) {
      lru_.splice(lru_.begin(), lru_, it->second);
      hit(CacheLevel::kMemory, memory_hits_);
      return it->second->value;
    }
  }
  // Not in memory: ask the store, then the shared level (without holding a lock meanwhile).
  if (std::optional<std::string> value = read_store(key)) {
    auto entry = std::make_shared<const CachedValue>(key, std::move(*value));
    const std::lock_guard memory(memory_mutex_);
    remember_locked(entry);
    hit(CacheLevel::kLocal, local_hits_);
    return entry;
  }
  std::shared_ptr<const CachedValue> entry;
  if (shared_) {
    const std::optional<std::string> value = shared_->get(key);
    if (value && (!config_.servable || config_.servable(*value))) {
      entry = write_local(key, *value);  // promoted into SQLite and memory
    }
  }
  const std::lock_guard memory(memory_mutex_);
  if (entry) {
    hit(CacheLevel::kShared, shared_hits_);
  } else {
    ++misses_;
  }
  return entry;
}

std::shared_ptr<const CachedValue> PlanCache::put(const std::string& key,
                                                  const std::string& value) {
  auto entry = write_local(key, value);
  if (shared_) shared_->put(key, value);  // outside the locks: Redis may take its timeout
  return entry;
}

std::shared_ptr<const CachedValue> PlanCache::write_local(const std::string& key,
                                                          const std::string& value) {
  auto entry = std::make_shared<const CachedValue>(key, value);
  const std::lock_guard store(store_mutex_);
  {
    const std::lock_guard memory(memory_mutex_);
    remember_locked(entry);
  }
  if (!db_) return entry;
  const std::string digest = row_digest(key, config_.version, value);
  int rc = upsert_.bind_text(1, key, false);
  if (rc == SQLITE_OK) rc = upsert_.bind_text(2, value, false);
  if (rc == SQLITE_OK) rc = upsert_.bind_int64(3, now_unix());
  if (rc == SQLITE_OK) rc = upsert_.bind_text(4, digest, false);
  if (rc == SQLITE_OK) rc = upsert_.bind_text(5, config_.version, false);
  if (rc == SQLITE_OK) rc = upsert_.step();
  const std::string message = rc == SQLITE_TOOBIG ? std::string(sqlite3_errstr(rc)) : db_.message();
  upsert_.reset();
  if (rc == SQLITE_DONE) {
    clear_error();
    store_bytes_ += value.size();
    if (config_.store_bytes > 0 && store_bytes_ > config_.store_bytes) prune_store_locked();
  } else {
    set_error("plan cache store '" + config_.path + "': writing " + noun_ + " failed (" + message +
              "); it is kept in memory only");
  }
  return entry;
}

PlanCache::Stats PlanCache::stats() const {
  Stats s;
  {
    const std::lock_guard memory(memory_mutex_);
    s.memory_hits = memory_hits_;
    s.local_hits = local_hits_;
    s.shared_hits = shared_hits_;
    s.hits = memory_hits_ + local_hits_ + shared_hits_;
    s.misses = misses_;
    s.memory_entries = lru_.size();
    s.memory_bytes = memory_bytes_;
  }
  s.store_bytes = store_bytes_;
  if (shared_) s.shared_rejected = shared_->rejected();
  const std::lock_guard lock(error_mutex_);
  s.persistent = persistent_;
  s.storage_error = storage_error_;
  return s;
}

std::string PlanCache::storage_error() const {
  const std::lock_guard lock(error_mutex_);
  return storage_error_;
}

bool PlanCache::in_memory(const std::string& key) const {
  const std::lock_guard memory(memory_mutex_);
  return index_.contains(key);
}

}  // namespace slosh::service
