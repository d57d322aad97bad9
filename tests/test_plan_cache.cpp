// The plan cache: memory LRU tier, SQLite persistence (WAL), failure handling and threads. Every
// test uses real SQLite files in a private temporary directory.

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cache/plan_cache.hpp"
#include "support/process.hpp"
#include "support/sqlite_query.hpp"

namespace slosh::service {
namespace test_plan_cache {

class PlanCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = ::testing::TempDir() + "slosh_plan_cache_XXXXXX";
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  [[nodiscard]] std::string file(const std::string& name) const { return (dir_ / name).string(); }

  std::filesystem::path dir_;
};

using test::query;

TEST_F(PlanCacheTest, HitAfterPutAndMissForUnknownKey) {
  PlanCache cache({.path = file("plans.sqlite")});
  EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
  EXPECT_EQ(cache.get("ab12"), std::nullopt);
  cache.put("ab12", R"({"plan": 1})");
  EXPECT_EQ(cache.get("ab12"), R"({"plan": 1})");
  EXPECT_EQ(cache.get("cd34"), std::nullopt);
  cache.put("ab12", R"({"plan": 2})");  // replaces
  EXPECT_EQ(cache.get("ab12"), R"({"plan": 2})");
  const PlanCache::Stats s = cache.stats();
  EXPECT_EQ(s.hits, 2U);
  EXPECT_EQ(s.misses, 2U);
  EXPECT_EQ(s.memory_entries, 1U);
  EXPECT_TRUE(s.persistent);
  EXPECT_TRUE(s.storage_error.empty());
}

TEST_F(PlanCacheTest, EntriesSurviveARestart) {
  const std::string path = file("plans.sqlite");
  {
    PlanCache first({.path = path});
    first.put("k1", "v1");
    first.put("k2", "v2");
  }
  PlanCache second({.path = path});
  EXPECT_FALSE(second.in_memory("k1"));
  EXPECT_EQ(second.get("k1"), "v1");  // from SQLite, then promoted
  EXPECT_TRUE(second.in_memory("k1"));
  EXPECT_EQ(second.get("k2"), "v2");
  EXPECT_EQ(second.get("k3"), std::nullopt);
  EXPECT_EQ(second.stats().hits, 2U);
  EXPECT_EQ(second.stats().misses, 1U);
  EXPECT_EQ(query(path, "SELECT count(*) FROM plans"), "2");
  EXPECT_EQ(query(path, "SELECT body FROM plans WHERE key = 'k2'"), "v2");
  // created_unix is a plausible Unix time (after 2020-01-01).
  EXPECT_GT(std::stoll(query(path, "SELECT min(created_unix) FROM plans")), 1577836800LL);
}

TEST_F(PlanCacheTest, EntriesSurviveAProcessThatDiesWithoutClosing) {
  const std::string path = file("plans.sqlite");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    auto* cache = new PlanCache({.path = path});  // never destroyed: no close, no checkpoint
    cache->put("crash", "survived");
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_TRUE(std::filesystem::exists(path + "-wal"));  // the entry lives in the WAL
  PlanCache cache({.path = path});
  EXPECT_EQ(cache.get("crash"), "survived");
}

TEST_F(PlanCacheTest, WalModeIsSet) {
  const std::string path = file("plans.sqlite");
  PlanCache cache({.path = path});
  cache.put("k", "v");
  EXPECT_EQ(query(path, "PRAGMA journal_mode"), "wal");
}

TEST_F(PlanCacheTest, LeastRecentlyUsedIsEvictedFirst) {
  PlanCache memory({.path = "", .memory_entries = 2});
  memory.put("a", "1");
  memory.put("b", "2");
  EXPECT_EQ(memory.get("a"), "1");  // a is now the most recent: b goes first
  memory.put("c", "3");
  EXPECT_EQ(memory.stats().memory_entries, 2U);
  EXPECT_EQ(memory.get("b"), std::nullopt);
  EXPECT_EQ(memory.get("a"), "1");
  EXPECT_EQ(memory.get("c"), "3");
  memory.put("d", "4");  // evicts a (c was read after a)
  EXPECT_EQ(memory.get("a"), std::nullopt);
  EXPECT_EQ(memory.get("c"), "3");
  EXPECT_EQ(memory.get("d"), "4");
}

TEST_F(PlanCacheTest, EvictedEntriesComeBackFromSqlite) {
  PlanCache cache({.path = file("plans.sqlite"), .memory_entries = 2});
  cache.put("a", "1");
  cache.put("b", "2");
  EXPECT_EQ(cache.get("a"), "1");
  cache.put("c", "3");
  EXPECT_TRUE(cache.in_memory("a"));
  EXPECT_FALSE(cache.in_memory("b"));
  EXPECT_TRUE(cache.in_memory("c"));
  EXPECT_EQ(cache.get("b"), "2");  // from SQLite, promoted; evicts a (least recent)
  EXPECT_TRUE(cache.in_memory("b"));
  EXPECT_FALSE(cache.in_memory("a"));
  EXPECT_TRUE(cache.in_memory("c"));
  EXPECT_EQ(cache.get("a"), "1");
  EXPECT_EQ(cache.stats().memory_entries, 2U);
  EXPECT_EQ(cache.stats().hits, 3U);
  EXPECT_EQ(cache.stats().misses, 0U);
}

TEST_F(PlanCacheTest, ZeroCapacityServesEverythingFromSqlite) {
  PlanCache cache({.path = file("plans.sqlite"), .memory_entries = 0});
  cache.put("a", "1");
  EXPECT_FALSE(cache.in_memory("a"));
  EXPECT_EQ(cache.get("a"), "1");
  EXPECT_EQ(cache.stats().memory_entries, 0U);
}

TEST_F(PlanCacheTest, MemoryOnlyModeNeverPersists) {
  {
    PlanCache cache(CacheConfig{});
    EXPECT_FALSE(cache.stats().persistent);
    EXPECT_TRUE(cache.storage_error().empty());
    cache.put("k", "v");
    EXPECT_EQ(cache.get("k"), "v");
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir_));
  PlanCache again(CacheConfig{});
  EXPECT_EQ(again.get("k"), std::nullopt);
}

/// get/put keep working from memory; storage_error names the path.
void expect_memory_fallback(PlanCache& cache, const std::string& path) {
  const std::string error = cache.storage_error();
  EXPECT_NE(error.find("'" + path + "'"), std::string::npos) << error;
  EXPECT_FALSE(cache.stats().persistent);
  EXPECT_EQ(cache.stats().storage_error, error);
  EXPECT_EQ(cache.get("k"), std::nullopt);
  cache.put("k", "v");
  EXPECT_EQ(cache.get("k"), "v");
  EXPECT_EQ(cache.storage_error(), error);
}

TEST_F(PlanCacheTest, CorruptFileFallsBackToMemory) {
  const std::string path = file("garbage.sqlite");
  {
    std::mt19937 random(42);
    std::ofstream out(path, std::ios::binary);
    for (int i = 0; i < 8192; ++i) out.put(static_cast<char>(random() & 0xFF));
  }
  PlanCache cache({.path = path});
  expect_memory_fallback(cache, path);
  EXPECT_NE(cache.storage_error().find("file is not a database"), std::string::npos)
      << cache.storage_error();
  EXPECT_EQ(std::filesystem::file_size(path), 8192U);  // left untouched
}

TEST_F(PlanCacheTest, UnwritablePathFallsBackToMemory) {
  const std::string missing_dir = file("no_such_dir") + "/x.sqlite";
  PlanCache in_missing_dir({.path = missing_dir});
  expect_memory_fallback(in_missing_dir, missing_dir);
  EXPECT_NE(in_missing_dir.storage_error().find("unable to open database file"), std::string::npos)
      << in_missing_dir.storage_error();

  PlanCache absolute({.path = "/nonexistent_dir/x.sqlite"});
  expect_memory_fallback(absolute, "/nonexistent_dir/x.sqlite");

  // A directory is not a file, whoever runs the test (root ignores permission bits).
  PlanCache on_directory({.path = dir_.string()});
  expect_memory_fallback(on_directory, dir_.string());
}

TEST_F(PlanCacheTest, FailedWriteIsReportedAndLaterWritesRecover) {
  const std::string path = file("plans.sqlite");
  PlanCache cache({.path = path, .busy_timeout_ms = 20});
  cache.put("before", "1");
  // Another connection holds the write lock: the cache's write times out with SQLITE_BUSY.
  sqlite3* other = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK);
  cache.put("during", "2");
  const std::string error = cache.storage_error();
  EXPECT_NE(error.find("'" + path + "'"), std::string::npos) << error;
  EXPECT_NE(error.find("database is locked"), std::string::npos) << error;
  EXPECT_TRUE(cache.stats().persistent);
  EXPECT_EQ(cache.get("during"), "2");  // still served from memory
  ASSERT_EQ(sqlite3_exec(other, "COMMIT", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(other);
  cache.put("after", "3");
  EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
  EXPECT_EQ(query(path, "SELECT count(*) FROM plans"), "2");  // before, after
}

TEST_F(PlanCacheTest, ConcurrentPutAndGetLoseNothing) {
  const std::string path = file("plans.sqlite");
  constexpr int kThreads = 8;
  constexpr int kOps = 500;
  const auto key = [](int t, int i) { return std::to_string(t) + "-" + std::to_string(i); };
  const auto value = [](int t, int i) { return "plan " + std::to_string(t * 100000 + i); };
  {
    // A small memory tier so that gets also go to SQLite while others write.
    PlanCache cache({.path = path, .memory_entries = 64});
    std::vector<std::thread> threads;
    std::vector<int> wrong(kThreads, 0);
    for (int t = 0; t < kThreads; ++t) {
      threads.emplace_back([&, t] {
        for (int i = 0; i < kOps; ++i) {
          cache.put(key(t, i), value(t, i));
          if (cache.get(key(t, i)) != value(t, i)) ++wrong[t];
          const int j = i / 2;  // an older entry, likely evicted from memory
          if (cache.get(key(t, j)) != value(t, j)) ++wrong[t];
          (void)cache.get(key((t + 1) % kThreads, i));  // another thread's, maybe not there yet
        }
      });
    }
    for (auto& th : threads) th.join();
    for (int t = 0; t < kThreads; ++t) EXPECT_EQ(wrong[t], 0) << "thread " << t;
    EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
    const PlanCache::Stats s = cache.stats();
    EXPECT_EQ(s.hits + s.misses, 3U * kThreads * kOps);
    EXPECT_GE(s.hits, 2U * kThreads * kOps);
    EXPECT_LE(s.memory_entries, 64U);
  }
  EXPECT_EQ(query(path, "SELECT count(*) FROM plans"), std::to_string(kThreads * kOps));
  PlanCache reopened({.path = path});
  for (int t = 0; t < kThreads; ++t) {
    for (int i = 0; i < kOps; ++i) ASSERT_EQ(reopened.get(key(t, i)), value(t, i));
  }
}

TEST_F(PlanCacheTest, LargeTextRoundTripsExactly) {
  const std::string path = file("plans.sqlite");
  std::string big;
  const std::string piece =
      "{\"q\": \"it's \\\"quoted\\\"\", \"u\": \"ĥéłłø 水 🌊\", \"n\": \"a\\nb\"}\n";
  while (big.size() < (1U << 20)) big += piece;
  {
    PlanCache cache({.path = path});
    cache.put("big", big);
    EXPECT_EQ(cache.get("big"), big);
    EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
  }
  PlanCache reopened({.path = path});
  const std::optional<std::string> back = reopened.get("big");
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->size(), big.size());
  EXPECT_TRUE(*back == big);
}

/// The memory tier is bounded in bytes, not only in entries (40 series-laden plans
/// took 978 MiB); the least recent plans go first, and a plan larger than the bound stays on disk.
TEST_F(PlanCacheTest, MemoryTierIsBoundedInBytes) {
  CacheConfig config{.path = file("bytes.sqlite"), .memory_entries = 1000, .memory_bytes = 10000};
  PlanCache cache(config);
  const std::string value(1000 - 2, 'v');  // 2-character keys: 1000 bytes an entry
  for (int i = 0; i < 25; ++i) cache.put(std::to_string(10 + i), value);
  const PlanCache::Stats s = cache.stats();
  EXPECT_EQ(s.memory_entries, 10u);
  EXPECT_EQ(s.memory_bytes, 10000u);
  EXPECT_TRUE(cache.in_memory("34"));
  EXPECT_FALSE(cache.in_memory("24"));
  // Evicted plans are still answered from disk.
  EXPECT_EQ(cache.get("10"), value);
  // Too large for the memory tier: on disk only, and the rest of the tier is kept.
  cache.put("big", std::string(20000, 'b'));
  EXPECT_FALSE(cache.in_memory("big"));
  EXPECT_EQ(cache.get("big")->size(), 20000u);
  EXPECT_LE(cache.stats().memory_bytes, 10000u);
  // Replacing a value accounts for the old one.
  cache.put("10", "short");
  EXPECT_LE(cache.stats().memory_bytes, 10000u);
  EXPECT_EQ(cache.get("10"), "short");
}

/// The SQLite table is bounded (40 series-laden plans took 600 MiB): beyond
/// store_bytes the oldest plans are deleted down to 90 % of it.
TEST_F(PlanCacheTest, StoreIsPrunedOldestFirst) {
  const std::string path = file("pruned.sqlite");
  {
    CacheConfig config{.path = path, .memory_entries = 0, .store_bytes = 100000};
    PlanCache cache(config);
    for (int i = 0; i < 50; ++i) cache.put("k" + std::to_string(100 + i), std::string(5000, 'p'));
    EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
    EXPECT_LE(cache.stats().store_bytes, 100000u);
  }
  // Measured by SQLite itself, in another connection.
  EXPECT_LE(std::stoll(query(path, "SELECT SUM(LENGTH(body)) FROM plans")), 100000);
  EXPECT_GE(std::stoll(query(path, "SELECT COUNT(*) FROM plans")), 10);
  EXPECT_EQ(query(path, "SELECT COUNT(*) FROM plans WHERE key = 'k149'"), "1");  // newest kept
  EXPECT_EQ(query(path, "SELECT COUNT(*) FROM plans WHERE key = 'k100'"), "0");  // oldest gone
  // A reopened store counts what it holds and keeps pruning.
  CacheConfig config{.path = path, .memory_entries = 0, .store_bytes = 100000};
  PlanCache reopened(config);
  EXPECT_GT(reopened.stats().store_bytes, 50000u);
  for (int i = 0; i < 20; ++i) reopened.put("n" + std::to_string(i), std::string(5000, 'q'));
  EXPECT_LE(std::stoll(query(path, "SELECT SUM(LENGTH(body)) FROM plans")), 100000);
}

using test::execute;

TEST_F(PlanCacheTest, RowsOfAnotherBodyLayoutAreDroppedWhenTheStoreOpens) {
  // A store written before the bodies lost their per-reply "cached" member (user_version 0).
  const std::string path = file("old.sqlite");
  execute(path,
          "CREATE TABLE plans(key TEXT PRIMARY KEY, body TEXT NOT NULL, created_unix INTEGER "
          "NOT NULL); INSERT INTO plans VALUES('old', '{\"cached\":false,\"key\":\"old\"}', 1)");
  {
    PlanCache cache({.path = path});
    EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
    EXPECT_EQ(cache.get("old"), std::nullopt);
    cache.put("new", "{\"key\":\"new\"}");
  }
  EXPECT_EQ(query(path, "PRAGMA user_version"), "4");
  PlanCache reopened({.path = path});  // the current layout is kept across restarts
  EXPECT_EQ(reopened.get("new"), "{\"key\":\"new\"}");
}

TEST_F(PlanCacheTest, PlansAndMinTimeAnswersLiveInTheirOwnTablesOfOneFile) {
  const std::string path = file("store.sqlite");
  {
    PlanCache plans({.path = path});
    PlanCache min_times({.path = path, .table = CacheTable::kMinTime});
    ASSERT_TRUE(plans.storage_error().empty()) << plans.storage_error();
    ASSERT_TRUE(min_times.storage_error().empty()) << min_times.storage_error();
    plans.put("plan-key", "{\"plan\":1}");
    min_times.put("min-time-key", "{\"min_time\":1}");
    EXPECT_EQ(plans.get("min-time-key"), std::nullopt);
    EXPECT_EQ(min_times.get("plan-key"), std::nullopt);
  }
  EXPECT_EQ(query(path, "SELECT key FROM plans"), "plan-key");
  EXPECT_EQ(query(path, "SELECT key FROM min_times"), "min-time-key");
  // Restarted with empty memory tiers: each answers its own keys from disk, and only those.
  PlanCache plans({.path = path});
  PlanCache min_times({.path = path, .table = CacheTable::kMinTime});
  EXPECT_EQ(plans.get("plan-key"), "{\"plan\":1}");
  EXPECT_EQ(min_times.get("min-time-key"), "{\"min_time\":1}");
  EXPECT_EQ(plans.get("min-time-key"), std::nullopt);
  EXPECT_EQ(min_times.get("plan-key"), std::nullopt);
}

TEST_F(PlanCacheTest, ALayoutTwoStoreIsEmptiedAndGainsTheVersionedTables) {
  // A store of an older slosh (user_version 2: plans only, no versions), plus a min_times table
  // left by a rollback from a later slosh: none of its rows says which planner made it.
  const std::string path = file("v2.sqlite");
  execute(path,
          "CREATE TABLE plans(key TEXT PRIMARY KEY, body TEXT NOT NULL, created_unix INTEGER "
          "NOT NULL); INSERT INTO plans VALUES('old', '{\"key\":\"old\"}', 1);"
          "CREATE TABLE min_times(key TEXT PRIMARY KEY, body TEXT NOT NULL, created_unix INTEGER "
          "NOT NULL); INSERT INTO min_times VALUES('stray', '{}', 1); PRAGMA user_version = 2");
  {
    PlanCache min_times({.path = path, .table = CacheTable::kMinTime});  // opens it first
    EXPECT_TRUE(min_times.storage_error().empty()) << min_times.storage_error();
    EXPECT_EQ(min_times.get("stray"), std::nullopt);
    min_times.put("answer", "{\"key\":\"answer\"}");
    PlanCache plans({.path = path});
    EXPECT_EQ(plans.get("old"), std::nullopt);
  }
  EXPECT_EQ(query(path, "PRAGMA user_version"), "4");
  EXPECT_EQ(query(path, "SELECT count(*) FROM plans"), "0");
  EXPECT_EQ(query(path, "SELECT version FROM min_times WHERE key = 'answer'"), kVersion);
  PlanCache reopened({.path = path, .table = CacheTable::kMinTime});  // layout 4 is kept
  EXPECT_EQ(reopened.get("answer"), "{\"key\":\"answer\"}");
}

TEST_F(PlanCacheTest, AStoreOfAnUnknownLayoutIsEmptiedInBothTables) {
  // Written by a later slosh (user_version 5): neither table's rows can be read with confidence.
  const std::string path = file("v5.sqlite");
  execute(path,
          "CREATE TABLE plans(key TEXT PRIMARY KEY, body TEXT NOT NULL, created_unix INTEGER "
          "NOT NULL); INSERT INTO plans VALUES('p', '{}', 1);"
          "CREATE TABLE min_times(key TEXT PRIMARY KEY, body TEXT NOT NULL, created_unix INTEGER "
          "NOT NULL); INSERT INTO min_times VALUES('m', '{}', 1); PRAGMA user_version = 5");
  PlanCache plans({.path = path});
  EXPECT_TRUE(plans.storage_error().empty()) << plans.storage_error();
  EXPECT_EQ(plans.get("p"), std::nullopt);
  EXPECT_EQ(query(path, "SELECT count(*) FROM min_times"), "0");
  EXPECT_EQ(query(path, "PRAGMA user_version"), "4");
}

TEST_F(PlanCacheTest, TheMinTimeTableIsPrunedWithinItsOwnBound) {
  const std::string path = file("bounded.sqlite");
  PlanCache plans({.path = path, .store_bytes = 0});
  PlanCache min_times({.path = path, .store_bytes = 10000, .table = CacheTable::kMinTime});
  const std::string body(1000, 'x');
  for (int i = 0; i < 5; ++i) plans.put("plan" + std::to_string(i), body);
  for (int i = 0; i < 30; ++i) min_times.put("answer" + std::to_string(i), body);
  EXPECT_TRUE(min_times.storage_error().empty()) << min_times.storage_error();
  const long long kept = std::stoll(query(path, "SELECT SUM(LENGTH(body)) FROM min_times"));
  EXPECT_LE(kept, 10000);
  EXPECT_GE(kept, 5000);
  EXPECT_LE(min_times.stats().store_bytes, 10000u);
  EXPECT_EQ(query(path, "SELECT count(*) FROM plans"), "5");  // the other table is untouched
  EXPECT_EQ(query(path, "SELECT count(*) FROM min_times WHERE key = 'answer29'"), "1");
  EXPECT_EQ(query(path, "SELECT count(*) FROM min_times WHERE key = 'answer0'"), "0");
}

}  // namespace test_plan_cache
}  // namespace slosh::service

namespace slosh::service {
namespace test_plan_cache {

// Regression: bytes changed inside the file (its header intact) were served as a cached
// answer. SQLite checks the pages' structure, not their content: the digest of each row does.
TEST_F(PlanCacheTest, ARowWhoseBytesChangedOnDiskIsDroppedNotServed) {
  const std::string body = "{\"marker\":\"" + std::string(200, 'm') + "\"}";
  for (CacheTable table : {CacheTable::kPlans, CacheTable::kMinTime}) {
    SCOPED_TRACE(table == CacheTable::kPlans ? "plans" : "min_times");
    const std::string path = file(table == CacheTable::kPlans ? "p.sqlite" : "m.sqlite");
    {
      PlanCache cache({.path = path, .table = table});
      cache.put("k", body);
      cache.put("intact", "{\"other\":1}");
    }  // closed: the WAL is checkpointed into the file
    std::string bytes = test::read_file(path);
    const auto at = bytes.find(std::string(200, 'm'));
    ASSERT_NE(at, std::string::npos);
    bytes[at + 100] = 'X';  // same length: only the digest can tell
    test::write_file(path, bytes);
    PlanCache cache({.path = path, .table = table});
    EXPECT_EQ(cache.get("k"), std::nullopt);
    EXPECT_NE(cache.storage_error().find("do not match their digest; the row was dropped"),
              std::string::npos)
        << cache.storage_error();
    EXPECT_EQ(cache.get("intact"), "{\"other\":1}");
    EXPECT_EQ(
        query(path, std::string("SELECT count(*) FROM ") +
                        (table == CacheTable::kPlans ? "plans" : "min_times") + " WHERE key = 'k'"),
        "0");
    cache.put("k", body);  // computed again: stored and served, and the store is well again
    EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
    EXPECT_EQ(cache.get("k"), body);
  }
}

}  // namespace test_plan_cache
}  // namespace slosh::service

namespace slosh::service {
namespace test_plan_cache {

// Hostile re-test: the digest covered the body only, so a row whose key bytes changed answered
// another recipe; a layout-2 file's damaged rows got digests; a layout-3 file without digests
// left the store unusable.
TEST_F(PlanCacheTest, ARowWhoseKeyChangedOnDiskAnswersNoOtherKey) {
  const std::string path = file("store.sqlite");
  {
    PlanCache cache({.path = path});
    cache.put("k12", "{\"key\":\"k12\",\"T\":1.2}");
  }
  execute(path, "UPDATE plans SET key = 'k13' WHERE key = 'k12'");
  PlanCache cache({.path = path});
  EXPECT_EQ(cache.get("k13"), std::nullopt);
  EXPECT_NE(cache.storage_error().find("(key 'k13') do not match their digest"), std::string::npos)
      << cache.storage_error();
  EXPECT_EQ(query(path, "SELECT count(*) FROM plans"), "0");
}

TEST_F(PlanCacheTest, ALayoutThreeFileWithoutDigestsIsEmptiedAndUsable) {
  const std::string path = file("v3.sqlite");
  execute(path,
          "CREATE TABLE plans(key TEXT PRIMARY KEY, body TEXT NOT NULL, created_unix INTEGER "
          "NOT NULL); INSERT INTO plans VALUES('old', '{\"key\":\"old\"}', 1);"
          "PRAGMA user_version = 3");
  {
    PlanCache cache({.path = path});
    EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
    EXPECT_EQ(cache.get("old"), std::nullopt);
    cache.put("new", "{\"key\":\"new\"}");
    EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
  }
  PlanCache reopened({.path = path, .memory_entries = 0});
  EXPECT_EQ(reopened.get("new"), "{\"key\":\"new\"}");
}

}  // namespace test_plan_cache
}  // namespace slosh::service
