// Job stores: MemoryJobStore's bounds (age and count, least recently written first)
// and TieredJobStore's semantics with two MemoryJobStores standing in for the local store and a
// shared one (Redis) that goes down and comes back.

#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <future>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "jobs/job_messages.hpp"
#include "jobs/memory_job_store.hpp"
#include "jobs/tiered_job_store.hpp"

namespace slosh::service {
namespace test_job_store {

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

// A store that can be "down": every call fails as a Redis store's does when Redis does not
// answer (false, nullopt, and a record lookup that says it was not answered, as
// RedisJobStore::lookup_record does on a timeout).
class SwitchableStore final : public JobStore {
 public:
  bool down{false};
  MemoryJobStore inner;
  bool put_record(const std::string& id, const std::string& r) override {
    return !down && inner.put_record(id, r);
  }
  RecordLookup lookup_record(const std::string& id) override {
    if (down) return {std::nullopt, false};
    return inner.lookup_record(id);
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
  bool remove(const std::string& id) override { return !down && inner.remove(id); }
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
  // Behind on this job, the shared store gets the next rows and record only with what it missed
  // (at the heartbeat's resync), in order: its copy has no gap, and no row is sent twice.
  ASSERT_TRUE(owner.put_rows("job", 3, {"r3"}));
  EXPECT_EQ(shared.inner.rows("job", 0, 10), (Rows{"r0"}));
  EXPECT_EQ(shared.inner.record("job"), "v1");
  owner.resync();
  EXPECT_EQ(shared.inner.rows("job", 0, 10), (Rows{"r0", "r1", "r2", "r3"}));
  EXPECT_EQ(shared.inner.record("job"), "v2");
  EXPECT_TRUE(shared.inner.cancel_requested("job"));
  // In step again: written through at once.
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
  RecordLookup lookup_record(const std::string& id) override { return inner.lookup_record(id); }
  bool put_rows(const std::string& id, std::size_t first, const Rows& rows) override {
    return inner.put_rows(id, first, rows) && !lie;
  }
  std::optional<Rows> rows(const std::string& id, std::size_t offset, std::size_t count) override {
    return inner.rows(id, offset, count);
  }
  bool request_cancel(const std::string& id) override { return inner.request_cancel(id); }
  bool cancel_requested(const std::string& id) override { return inner.cancel_requested(id); }
  bool remove(const std::string& id) override { return inner.remove(id) && !lie; }
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
  owner.resync();
  EXPECT_EQ(shared.inner.rows("job", 0, 10), (Rows{"r0", "r1", "r2", "r3"}));
  EXPECT_EQ(owner.rows("job", 0, 10), (Rows{"r0", "r1", "r2", "r3"}));
}

// A job is created only once the shared store took its first record: while it is down the job
// is refused and kept nowhere (another replica would not find it), and created once it is up.
TEST(TieredJobStore, AJobTheSharedStoreCannotTakeIsNotCreatedAnywhere) {
  MemoryJobStore local;
  SwitchableStore shared;
  TieredJobStore owner(local, shared);
  shared.down = true;
  EXPECT_EQ(owner.create("job", "v1"), "the job store did not take the job's record");
  EXPECT_EQ(local.record("job"), std::nullopt);
  EXPECT_TRUE(local.ids().empty());
  shared.down = false;
  owner.resync();
  EXPECT_EQ(shared.inner.record("job"), std::nullopt);  // nothing published later either
  EXPECT_EQ(owner.create("job2", "v1"), std::nullopt);
  EXPECT_EQ(local.record("job2"), "v1");
  EXPECT_EQ(shared.inner.record("job2"), "v1");
}

// The first record's write timed out but landed (Redis stalled, then continued): the refused
// job is removed from the shared store at the next resync, not left there as a queued job that
// never runs.
TEST(TieredJobStore, ARefusedCreateThatLandedIsRemovedFromTheSharedStoreAtTheNextResync) {
  MemoryJobStore local;
  LandsButFailsStore shared;
  TieredJobStore owner(local, shared);
  shared.lie = true;
  ASSERT_TRUE(owner.create("job", "v1"));
  EXPECT_EQ(shared.inner.record("job"), "v1");  // landed
  EXPECT_EQ(local.record("job"), std::nullopt);
  shared.lie = false;
  owner.resync();
  EXPECT_EQ(shared.inner.record("job"), std::nullopt);
  EXPECT_TRUE(local.ids().empty());
}

// What a shared store (Redis) holds, seen by several replicas' RecordingStores.
struct SharedState {
  MemoryJobStore inner;
  std::set<std::string> removed;
  int generation{0};                                            // counts emptyings (FLUSHALL)
  std::vector<std::pair<std::string, std::size_t>> row_writes;  // (id, rows in the write)
  std::vector<std::string> records;                             // every record written
  std::mutex log_mutex;
  std::atomic<bool> hold{false};  // row writes of job "big" stall while set (a slow Redis)
  std::atomic<bool> holding{false};
  void empty() {
    for (const std::string& id : inner.ids()) inner.remove(id);
    removed.clear();
    ++generation;
  }
};

// One replica's view of a SharedState: it records what it is sent and, as Redis does, takes rows
// and cancel flags of a job it holds no record of.
class RecordingStore final : public JobStore {
 public:
  explicit RecordingStore(SharedState& state) : s_(state) {}
  bool put_record(const std::string& id, const std::string& r) override {
    {
      const std::lock_guard lock(s_.log_mutex);
      s_.records.push_back(id + "=" + r);
    }
    return s_.inner.put_record(id, r);
  }
  RecordLookup lookup_record(const std::string& id) override {
    if (s_.removed.count(id) != 0) return {std::nullopt, true};
    return s_.inner.lookup_record(id);
  }
  bool put_rows(const std::string& id, std::size_t first, const Rows& rows) override {
    while (s_.hold && id == "big") {
      s_.holding = true;
      std::this_thread::sleep_for(1ms);
    }
    {
      const std::lock_guard lock(s_.log_mutex);
      s_.row_writes.emplace_back(id, rows.size());
    }
    if (!s_.inner.record(id)) s_.inner.put_record(id, "");
    return s_.inner.put_rows(id, first, rows);
  }
  std::optional<Rows> rows(const std::string& id, std::size_t offset, std::size_t count) override {
    return s_.inner.rows(id, offset, count);
  }
  bool request_cancel(const std::string& id) override {
    if (!s_.inner.record(id)) s_.inner.put_record(id, "");
    return s_.inner.request_cancel(id);
  }
  bool cancel_requested(const std::string& id) override {
    return s_.inner.cancel_requested(id) || s_.removed.count(id) != 0;
  }
  bool remove(const std::string& id) override {
    s_.removed.insert(id);
    return s_.inner.remove(id);
  }
  std::vector<std::string> removed_among(const std::vector<std::string>& ids) override {
    std::vector<std::string> out;
    for (const std::string& id : ids) {
      if (s_.removed.count(id) != 0) out.push_back(id);
    }
    return out;
  }
  bool emptied_since_last_check() override {
    const bool changed = seen_ != s_.generation;
    seen_ = s_.generation;
    return changed;
  }

 private:
  SharedState& s_;
  int seen_{0};
};

// Rows a failed write left behind go to the shared store once, with the next resync, before the
// record that counts them; the rows written meanwhile are not sent on their own as well.
TEST(TieredJobStore, RowsTheSharedStoreMissedAreSentOnceThenTheRecord) {
  MemoryJobStore local;
  SwitchableStore flaky;
  TieredJobStore owner(local, flaky);
  ASSERT_TRUE(owner.put_record("job", "v1"));
  flaky.down = true;
  ASSERT_TRUE(owner.put_rows("job", 0, {"r0", "r1"}));
  flaky.down = false;
  ASSERT_TRUE(owner.put_rows("job", 2, {"r2"}));
  ASSERT_TRUE(owner.put_record("job", "v2"));
  // Nothing reached the shared store out of order: no rows 2.. before rows 0, 1, no record v2
  // that counts rows it does not hold.
  EXPECT_EQ(flaky.inner.rows("job", 0, 10), Rows{});
  EXPECT_EQ(flaky.inner.record("job"), "v1");
  owner.resync();
  EXPECT_EQ(flaky.inner.rows("job", 0, 10), (Rows{"r0", "r1", "r2"}));
  EXPECT_EQ(flaky.inner.record("job"), "v2");

  // Counted on a recording store: after an emptying, each row is sent once, in chunks of at
  // most kPublishChunk, and the record once, after them.
  MemoryJobStore local2;
  SharedState state;
  RecordingStore shared(state);
  TieredJobStore replica(local2, shared);
  const std::size_t n = 2 * TieredJobStore::kPublishChunk + 7;
  ASSERT_TRUE(replica.put_record("big", "v1"));
  ASSERT_TRUE(replica.put_rows("big", 0, Rows(n, "r")));
  ASSERT_TRUE(replica.put_record("big", "done"));
  state.empty();
  state.row_writes.clear();
  state.records.clear();
  replica.resync();
  std::vector<std::size_t> sizes;
  for (const auto& [id, rows] : state.row_writes) sizes.push_back(rows);
  EXPECT_EQ(sizes, (std::vector<std::size_t>{TieredJobStore::kPublishChunk,
                                             TieredJobStore::kPublishChunk, 7}));
  EXPECT_EQ(state.records, std::vector<std::string>{"big=done"});
  EXPECT_EQ(state.inner.rows("big", 0, n + 5)->size(), n);
  replica.resync();  // in step: nothing is sent again
  EXPECT_EQ(state.row_writes.size(), 3u);
  EXPECT_EQ(state.records.size(), 1u);
}

// Publishing a large job again does not hold the store's lock across the shared store's writes:
// the other jobs' writes go on meanwhile.
TEST(TieredJobStore, RepublishingALargeJobDoesNotBlockOtherWrites) {
  MemoryJobStore local;
  SharedState state;
  RecordingStore shared(state);
  TieredJobStore replica(local, shared);
  ASSERT_TRUE(replica.put_record("big", "v1"));
  ASSERT_TRUE(replica.put_rows("big", 0, Rows(10, "r")));
  ASSERT_TRUE(replica.put_record("other", "v1"));
  state.empty();
  state.hold = true;  // the shared store stalls on the republished rows
  std::thread heartbeat([&] { replica.resync(); });
  while (!state.holding) std::this_thread::sleep_for(1ms);
  auto written = std::async(std::launch::async, [&] {
    return replica.put_rows("other", 0, {"o0"}) && replica.put_record("other", "v2");
  });
  const auto status = written.wait_for(5s);
  state.hold = false;
  heartbeat.join();
  ASSERT_EQ(status, std::future_status::ready) << "a write waited for the republishing";
  EXPECT_TRUE(written.get());
  EXPECT_EQ(state.inner.rows("big", 0, 20)->size(), 10u);
}

// A removal (DELETE of a finished job) and a cancel (DELETE of a running one) accepted by one
// replica survive an emptying of the shared store: that replica sends them again, before the
// owner's republishing can bring the job back, and the owner then forgets its own copy (removed)
// or sees the cancel.
TEST(TieredJobStore, ARemovalOrCancelAcceptedElsewhereSurvivesAnEmptyingAndTheOwnersRepublishing) {
  MemoryJobStore local_a;
  MemoryJobStore local_b;
  SharedState state;
  RecordingStore shared_a(state);
  RecordingStore shared_b(state);
  TieredJobStore a(local_a, shared_a);  // the owner
  TieredJobStore b(local_b, shared_b);  // where the DELETEs arrive
  ASSERT_TRUE(a.put_record("finished", "done"));
  ASSERT_TRUE(a.put_rows("finished", 0, {"r0"}));
  ASSERT_TRUE(a.put_record("running", "running"));
  ASSERT_TRUE(b.remove("finished"));
  ASSERT_TRUE(b.request_cancel("running"));
  state.empty();  // FLUSHALL while the owner is paused: the removal and the cancel are lost
  b.resync();     // B's heartbeat comes first (A is paused)
  a.resync();     // A resumes and republishes what it owns
  EXPECT_EQ(a.record("finished"), std::nullopt);
  EXPECT_EQ(b.record("finished"), std::nullopt);
  EXPECT_EQ(local_a.record("finished"), std::nullopt);
  EXPECT_TRUE(a.cancel_requested("running"));
  EXPECT_EQ(b.record("running"), "running");
  // The other order: A republishes first, then B's heartbeat.
  ASSERT_TRUE(a.put_record("finished2", "done"));
  ASSERT_TRUE(b.remove("finished2"));
  state.empty();
  a.resync();
  b.resync();
  a.resync();
  EXPECT_EQ(b.record("finished2"), std::nullopt);
  EXPECT_EQ(a.record("finished2"), std::nullopt);
}

// A local store whose row writes first run `on_rows` (a reader on another thread, in effect).
class HookedStore final : public JobStore {
 public:
  MemoryJobStore inner;
  std::function<void()> on_rows;
  bool put_record(const std::string& id, const std::string& r) override {
    return inner.put_record(id, r);
  }
  RecordLookup lookup_record(const std::string& id) override { return inner.lookup_record(id); }
  bool put_rows(const std::string& id, std::size_t first, const Rows& rows) override {
    if (on_rows) on_rows();
    return inner.put_rows(id, first, rows);
  }
  std::optional<Rows> rows(const std::string& id, std::size_t offset, std::size_t count) override {
    return inner.rows(id, offset, count);
  }
  bool request_cancel(const std::string& id) override { return inner.request_cancel(id); }
  bool cancel_requested(const std::string& id) override { return inner.cancel_requested(id); }
  bool remove(const std::string& id) override { return inner.remove(id); }
};

// A copy of a finished job kept here is read only once it is whole: while its rows are being
// copied, a reader gets the shared store's record and every row, never the copy's final record
// with rows missing (which a GET answers 503).
TEST(TieredJobStore, AJobBeingCopiedHereIsReadFromTheSharedStoreUntilTheCopyIsWhole) {
  HookedStore local;
  SwitchableStore shared;
  TieredJobStore replica(local, shared);
  const Rows rows{"r0", "r1", "r2"};
  ASSERT_TRUE(shared.inner.put_record("job", "done"));
  ASSERT_TRUE(shared.inner.put_rows("job", 0, rows));
  std::optional<std::vector<std::optional<std::string>>> seen;
  std::optional<std::string> record;
  local.on_rows = [&] {
    record = replica.record("job");
    seen = replica.read_slots("job", 0, 3).slots;
  };
  ASSERT_TRUE(replica.keep_copy("job", "done", rows));
  EXPECT_EQ(record, "done");
  EXPECT_EQ(seen, (std::vector<std::optional<std::string>>{"r0", "r1", "r2"}));
  local.on_rows = nullptr;
  shared.down = true;  // the copy answers alone now
  EXPECT_EQ(replica.rows("job", 0, 3), rows);
}

// A shared store that refuses every write of job "job" once `taken` because its owner mark names
// "line-2" (and fails every write while `down`).
class TakenOverStore final : public JobStore {
 public:
  MemoryJobStore inner;
  bool taken{false};
  bool down{false};
  bool put_record(const std::string& id, const std::string& r) override {
    return !taken && !down && inner.put_record(id, r);
  }
  RecordLookup lookup_record(const std::string& id) override { return inner.lookup_record(id); }
  bool put_rows(const std::string& id, std::size_t first, const Rows& rows) override {
    return !taken && !down && inner.put_rows(id, first, rows);
  }
  std::optional<Rows> rows(const std::string& id, std::size_t offset, std::size_t count) override {
    return inner.rows(id, offset, count);
  }
  std::optional<std::string> taken_over_by(const std::string& id) override {
    return taken && !down && id == "job" ? std::optional<std::string>("line-2") : std::nullopt;
  }
  bool request_cancel(const std::string& id) override { return !down && inner.request_cancel(id); }
  bool cancel_requested(const std::string& id) override { return inner.cancel_requested(id); }
  bool remove(const std::string& id) override { return inner.remove(id); }
};

// A DELETE answered by a replica resumed after a pause, cut off from the shared store, for a job
// another replica took over meanwhile: the cancel was kept with the local copy only, which the
// next refused write of the job drops as taken over; the cancel still reaches the shared store at
// the resync, where the new owner reads it.
TEST(TieredJobStore, ACancelOnlyTheLocalCopyTookReachesTheSharedStoreThoughTheCopyIsDropped) {
  MemoryJobStore local;
  TakenOverStore shared;
  TieredJobStore old_owner(local, shared);
  ASSERT_TRUE(old_owner.put_record("job", "running 0"));
  ASSERT_TRUE(old_owner.put_rows("job", 0, {"r0"}));
  shared.down = true;
  EXPECT_TRUE(old_owner.request_cancel("job"));  // accepted: the DELETE is answered 202
  EXPECT_FALSE(shared.inner.cancel_requested("job"));
  shared.down = false;
  shared.taken = true;
  ASSERT_TRUE(shared.inner.put_record("job", "running 1 by line-2"));
  old_owner.resync();
  EXPECT_FALSE(old_owner.put_record("job", "cancelled 0"));  // its heartbeat's write is refused
  EXPECT_EQ(local.record("job"), std::nullopt);              // and the copy here dropped
  EXPECT_TRUE(shared.inner.cancel_requested("job"));
  EXPECT_TRUE(old_owner.cancel_requested("job"));
}

// A job another replica took over (the shared store refuses this replica's writes of it, naming
// the new owner) is dropped here at the first refused write, by a write or by the resync of what
// this replica kept: its local record and rows are gone, it is read from the shared store as the
// new owner wrote it, and nothing of it is written here again.
TEST(TieredJobStore, AJobAnotherReplicaTookOverIsDroppedHereAndNeverWrittenHereAgain) {
  for (const bool by_resync : {false, true}) {
    MemoryJobStore local;
    TakenOverStore shared;
    TieredJobStore owner(local, shared);
    ASSERT_TRUE(owner.put_record("job", "running 0"));
    ASSERT_TRUE(owner.put_rows("job", 0, {"r0"}));
    if (by_resync) {
      // Cut off from the shared store: the job's end is kept here, to be sent at the heartbeat.
      shared.down = true;
      ASSERT_TRUE(owner.put_rows("job", 1, {"r1"}));
      ASSERT_TRUE(owner.put_record("job", "done here"));
      EXPECT_EQ(owner.record("job"), "done here");
      shared.down = false;
    }
    shared.taken = true;
    ASSERT_TRUE(shared.inner.put_record("job", "running 1 by line-2"));
    if (by_resync) {
      owner.resync();
    } else {
      EXPECT_FALSE(owner.put_rows("job", 1, {"r1"}));
    }
    EXPECT_EQ(local.record("job"), std::nullopt) << by_resync;
    EXPECT_EQ(owner.record("job"), "running 1 by line-2") << by_resync;
    EXPECT_FALSE(owner.unshared("job")) << by_resync;
    EXPECT_FALSE(owner.put_record("job", "done here"));
    EXPECT_FALSE(owner.put_rows("job", 2, {"r2"}));
    owner.resync();
    EXPECT_EQ(local.record("job"), std::nullopt) << by_resync;
    // Taken back over (keep_copy at a takeover): written here again.
    shared.taken = false;
    ASSERT_TRUE(owner.keep_copy("job", "running 1", {"r0"}));
    EXPECT_TRUE(owner.put_record("job", "running 2"));
    EXPECT_EQ(shared.inner.record("job"), "running 2");
  }
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

// The note of a DELETE taken for another replica's job says when the owner stops it: at its next
// read of the store (every 0.5 s) only while its record is fresh; an owner that has missed a
// heartbeat is said to be silent, with how long.
TEST(JobMessages, ACancelNotePromisesAStopAtTheNextReadOnlyFromAnOwnerThatMissedNoHeartbeat) {
  const std::string fresh = remote_cancel_text(400, -1, 30, true);
  EXPECT_NE(fresh.find("stops it when it next reads the store (every 0.5 s)"), std::string::npos)
      << fresh;
  const std::string silent = remote_cancel_text(1500, -1, 30, true);
  EXPECT_EQ(silent.find("every 0.5 s"), std::string::npos) << silent;
  EXPECT_NE(silent.find("has not answered for 1.5 s"), std::string::npos) << silent;
  EXPECT_NE(silent.find("half of batch_job_stale_s = 30 s (15 s)"), std::string::npos) << silent;
}

}  // namespace test_job_store
}  // namespace slosh::service
