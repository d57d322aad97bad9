// Job stores (issue 21): MemoryJobStore's bounds (age and count, least recently written first)
// and TieredJobStore's semantics with two MemoryJobStores standing in for the local store and a
// shared one (Redis) that goes down and comes back.

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "memory_job_store.hpp"

namespace slosh::service {
namespace {

using Rows = std::vector<std::string>;
using namespace std::chrono_literals;

// A clock the test moves by hand.
struct FakeClock {
  MemoryJobStore::Clock::time_point now{};
  std::function<MemoryJobStore::Clock::time_point()> fn() {
    return [this] { return now; };
  }
};

TEST(MemoryJobStore, KeepsRecordsRowsInOrderAndTheCancelFlag) {
  MemoryJobStore store;
  EXPECT_EQ(store.record("a"), std::nullopt);
  EXPECT_EQ(store.rows("a", 0, 10), std::nullopt);
  EXPECT_FALSE(store.put_rows("a", 0, {"r"}));  // rows follow a record
  EXPECT_FALSE(store.request_cancel("a"));
  ASSERT_TRUE(store.put_record("a", "{1}"));
  ASSERT_TRUE(store.put_record("a", "{2}"));
  EXPECT_EQ(store.record("a"), "{2}");
  ASSERT_TRUE(store.put_rows("a", 0, {"r0", "r1"}));
  ASSERT_TRUE(store.put_rows("a", 2, {"r2"}));
  EXPECT_EQ(store.rows("a", 0, 10), (Rows{"r0", "r1", "r2"}));
  EXPECT_EQ(store.rows("a", 1, 1), (Rows{"r1"}));
  EXPECT_EQ(store.rows("a", 2, 5), (Rows{"r2"}));
  EXPECT_EQ(store.rows("a", 7, 5), Rows{});
  EXPECT_FALSE(store.cancel_requested("a"));
  EXPECT_TRUE(store.request_cancel("a"));
  EXPECT_TRUE(store.cancel_requested("a"));
  store.remove("a");
  EXPECT_EQ(store.record("a"), std::nullopt);
  EXPECT_FALSE(store.cancel_requested("a"));
  store.remove("a");  // idempotent
}

TEST(MemoryJobStore, AJobNotWrittenForTheTtlIsForgottenAWrittenOneStays) {
  FakeClock clock;
  MemoryJobStore store({.ttl_s = 60, .max_jobs = 10}, clock.fn());
  store.put_record("old", "o");
  store.put_record("alive", "a");
  clock.now += 50s;
  store.put_record("alive", "a2");  // a running job's heartbeat
  clock.now += 11s;                 // old: 61 s since its write; alive: 11 s
  EXPECT_EQ(store.record("old"), std::nullopt);
  EXPECT_EQ(store.record("alive"), "a2");
  ASSERT_TRUE(store.put_rows("alive", 0, {"r"}));  // appending rows is a write too
  clock.now += 59s;
  EXPECT_EQ(store.rows("alive", 0, 1), (Rows{"r"}));
  clock.now += 2s;
  EXPECT_EQ(store.record("alive"), std::nullopt);
  EXPECT_EQ(store.size(), 0u);
}

TEST(MemoryJobStore, BeyondTheCountTheLeastRecentlyWrittenGoFirst) {
  FakeClock clock;
  MemoryJobStore store({.ttl_s = 3600, .max_jobs = 3}, clock.fn());
  for (const char* id : {"j1", "j2", "j3"}) {
    store.put_record(id, id);
    clock.now += 1s;
  }
  store.put_record("j1", "j1 again");  // j1 is now the most recently written
  clock.now += 1s;
  store.put_record("j4", "j4");  // 4 jobs: j2 (the least recently written) goes
  EXPECT_EQ(store.record("j2"), std::nullopt);
  EXPECT_EQ(store.record("j1"), "j1 again");
  EXPECT_EQ(store.record("j3"), "j3");
  EXPECT_EQ(store.record("j4"), "j4");
  EXPECT_EQ(store.size(), 3u);
}

// Beyond max_bytes (records and rows, counted by their lengths) the least recently written jobs go
// first, but never the job being written, even when it alone passes the budget.
TEST(MemoryJobStore, BeyondTheByteBudgetTheLeastRecentlyWrittenGoFirstNeverTheOneWritten) {
  FakeClock clock;
  MemoryJobStore store({.ttl_s = 3600, .max_jobs = 100, .max_bytes = 100}, clock.fn());
  const std::string row(30, 'x');
  for (const char* id : {"j1", "j2", "j3"}) {  // 2 + 30 bytes each: 96 in all
    store.put_record(id, id);
    ASSERT_TRUE(store.put_rows(id, 0, {row}));
    clock.now += 1s;
  }
  EXPECT_EQ(store.size(), 3u);
  store.put_record("j1", "j1");                  // j1 is now the most recently written
  EXPECT_FALSE(store.put_rows("j4", 0, {row}));  // rows follow a record
  store.put_record("j4", "j4 record");  // 96 + 9 = 105 > 100: j2 (least recently written) goes
  EXPECT_EQ(store.record("j2"), std::nullopt);
  EXPECT_EQ(store.record("j3"), "j3");
  EXPECT_EQ(store.size(), 3u);  // 73 bytes
  // A row rewritten at its index replaces its bytes rather than adding to them.
  ASSERT_TRUE(store.put_rows("j3", 0, {std::string(31, 'y')}));
  EXPECT_EQ(store.size(), 3u);  // 74 bytes
  // One job alone past the budget keeps its rows; every other job is forgotten for it.
  ASSERT_TRUE(store.put_rows("j4", 0, {std::string(200, 'z')}));
  EXPECT_EQ(store.size(), 1u);
  EXPECT_EQ(store.rows("j4", 0, 1), (Rows{std::string(200, 'z')}));
  // Removing it frees its bytes: two small jobs fit again.
  store.remove("j4");
  store.put_record("a", std::string(40, 'a'));
  store.put_record("b", std::string(40, 'b'));
  EXPECT_EQ(store.size(), 2u);
}

// A store that can be "down": every call fails as a Redis store's does (false / nullopt).
class SwitchableStore final : public JobStore {
 public:
  bool down{false};
  MemoryJobStore inner;
  bool put_record(const std::string& id, const std::string& r) override {
    return !down && inner.put_record(id, r);
  }
  std::optional<std::string> record(const std::string& id) override {
    return down ? std::nullopt : inner.record(id);
  }
  bool put_rows(const std::string& id, std::size_t first, const Rows& rows) override {
    return !down && inner.put_rows(id, first, rows);
  }
  std::optional<Rows> rows(const std::string& id, std::size_t offset, std::size_t count) override {
    return down ? std::nullopt : inner.rows(id, offset, count);
  }
  bool request_cancel(const std::string& id) override { return !down && inner.request_cancel(id); }
  bool cancel_requested(const std::string& id) override {
    return !down && inner.cancel_requested(id);
  }
  void remove(const std::string& id) override {
    if (!down) inner.remove(id);
  }
};

TEST(TieredJobStore, WritesBothReadsLocalFirstThenShared) {
  MemoryJobStore local_a;
  MemoryJobStore local_b;
  SwitchableStore shared;
  TieredJobStore a(local_a, shared);  // replica A
  TieredJobStore b(local_b, shared);  // replica B
  ASSERT_TRUE(a.put_record("job", "running"));
  ASSERT_TRUE(a.put_rows("job", 0, {"r0", "r1"}));
  // B has no local copy: it reads A's job from the shared store.
  EXPECT_EQ(b.record("job"), "running");
  EXPECT_EQ(b.rows("job", 0, 10), (Rows{"r0", "r1"}));
  EXPECT_EQ(local_b.record("job"), std::nullopt);
  // A DELETE on B sets the shared flag, which A (the owner) sees.
  EXPECT_TRUE(b.request_cancel("job"));
  EXPECT_TRUE(a.cancel_requested("job"));
  // Local first: a record only the local store has wins over the shared one.
  local_a.put_record("job", "local view");
  EXPECT_EQ(a.record("job"), "local view");
  EXPECT_EQ(b.record("job"), "running");
}

TEST(TieredJobStore, AReplicaKeepsItsJobWhileTheSharedStoreIsDownAndCatchesItUpAfter) {
  MemoryJobStore local;
  SwitchableStore shared;
  TieredJobStore owner(local, shared);
  ASSERT_TRUE(owner.put_record("job", "v1"));
  ASSERT_TRUE(owner.put_rows("job", 0, {"r0"}));
  shared.down = true;
  // Writes still succeed (the local store took them) and reads answer from it.
  EXPECT_TRUE(owner.put_record("job", "v2"));
  EXPECT_TRUE(owner.put_rows("job", 1, {"r1", "r2"}));
  EXPECT_EQ(owner.record("job"), "v2");
  EXPECT_EQ(owner.rows("job", 0, 10), (Rows{"r0", "r1", "r2"}));
  EXPECT_TRUE(owner.request_cancel("job"));
  EXPECT_TRUE(owner.cancel_requested("job"));
  shared.down = false;
  EXPECT_EQ(shared.inner.rows("job", 0, 10), (Rows{"r0"}));  // it missed r1, r2
  // The next rows carry the missed ones first: the shared copy has no gap.
  ASSERT_TRUE(owner.put_rows("job", 3, {"r3"}));
  EXPECT_EQ(shared.inner.rows("job", 0, 10), (Rows{"r0", "r1", "r2", "r3"}));
  ASSERT_TRUE(owner.put_record("job", "v3"));
  EXPECT_EQ(shared.inner.record("job"), "v3");
  owner.remove("job");
  EXPECT_EQ(owner.record("job"), std::nullopt);
  EXPECT_EQ(shared.inner.record("job"), std::nullopt);
}

// A shared store whose writes land but answer failure (Redis paused past the client's timeout,
// then continued): the tiered store sends those rows again with the next ones, and the shared copy
// holds each row once, in order.
class LandsButFailsStore final : public JobStore {
 public:
  bool lie{false};
  MemoryJobStore inner;
  bool put_record(const std::string& id, const std::string& r) override {
    return inner.put_record(id, r) && !lie;
  }
  std::optional<std::string> record(const std::string& id) override { return inner.record(id); }
  bool put_rows(const std::string& id, std::size_t first, const Rows& rows) override {
    return inner.put_rows(id, first, rows) && !lie;
  }
  std::optional<Rows> rows(const std::string& id, std::size_t offset, std::size_t count) override {
    return inner.rows(id, offset, count);
  }
  bool request_cancel(const std::string& id) override { return inner.request_cancel(id); }
  bool cancel_requested(const std::string& id) override { return inner.cancel_requested(id); }
  void remove(const std::string& id) override { inner.remove(id); }
};

TEST(TieredJobStore, AWriteThatLandedButReportedFailureIsNotDuplicatedWhenSentAgain) {
  MemoryJobStore local;
  LandsButFailsStore shared;
  TieredJobStore owner(local, shared);
  ASSERT_TRUE(owner.put_record("job", "v1"));
  ASSERT_TRUE(owner.put_rows("job", 0, {"r0"}));
  shared.lie = true;
  ASSERT_TRUE(owner.put_rows("job", 1, {"r1", "r2"}));
  shared.lie = false;
  ASSERT_TRUE(owner.put_rows("job", 3, {"r3"}));
  EXPECT_EQ(shared.inner.rows("job", 0, 10), (Rows{"r0", "r1", "r2", "r3"}));
  EXPECT_EQ(owner.rows("job", 0, 10), (Rows{"r0", "r1", "r2", "r3"}));
}

TEST(MemoryJobStore, RowsAreKeyedByIndexAndAGapIsRefused) {
  MemoryJobStore store;
  ASSERT_TRUE(store.put_record("a", "x"));
  ASSERT_TRUE(store.put_rows("a", 0, {"r0", "r1"}));
  ASSERT_TRUE(store.put_rows("a", 1, {"r1", "r2"}));
  EXPECT_EQ(store.rows("a", 0, 10), (Rows{"r0", "r1", "r2"}));
  EXPECT_FALSE(store.put_rows("a", 4, {"r4"}));  // row 3 missing
  EXPECT_EQ(store.rows("a", 0, 10), (Rows{"r0", "r1", "r2"}));
}

TEST(TieredJobStore, WithBothStoresDownWritesFailAndReadsFindNothing) {
  SwitchableStore local;
  SwitchableStore shared;
  TieredJobStore store(local, shared);
  local.down = true;
  shared.down = true;
  EXPECT_FALSE(store.put_record("job", "x"));
  EXPECT_FALSE(store.put_rows("job", 0, {"r"}));
  EXPECT_EQ(store.record("job"), std::nullopt);
  EXPECT_EQ(store.rows("job", 0, 1), std::nullopt);
  EXPECT_FALSE(store.request_cancel("job"));
}

}  // namespace
}  // namespace slosh::service
