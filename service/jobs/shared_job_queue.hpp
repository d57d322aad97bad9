#pragma once
// A batch job shared out to every replica through Redis (SPEC §13, batch_job_spread =
// "replicas"): the Redis side of it, no solving.
//
// Keys of job <id> besides the job store's (<id>:record, :rows, :cancel, :removed, :alive; see
// RedisJobStore): <id>:spec (what a record needs that no replica but the owner knows: total,
// format, view, created), <id>:items (a stream, one entry per recipe, with the consumer group
// "workers"), <id>:counts (a hash: done, failed, started_ms, and r:<replica> = rows it stored),
// <id>:final (set once, by the replica that wrote the final record). <prefix>shared is a sorted
// set of the jobs with items left, by creation time: every replica works on the oldest first.
//
// Why a stream with a consumer group: each entry is delivered to one consumer (replica) only,
// stays in the group's pending list until acknowledged, and XAUTOCLAIM hands the entries a
// consumer has held longer than a bound to another one: exactly "each item taken by one replica,
// acknowledged when its row is stored, taken over when its taker stops answering", with no lock
// or lease of our own. A row is stored by a script (HSETNX by index, then the counters, then
// XACK, atomically), so an item solved twice (taken over from a replica that was only slow) is
// stored and counted once.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "jobs/batch_job_record.hpp"
#include "jobs/recipe_table.hpp"
#include "storage/redis_client.hpp"

namespace slosh::service {

/// One item of a shared job as taken from its stream.
struct SharedItem {
  std::string entry;                ///< the stream entry's id (acknowledged when the row is stored)
  std::size_t index{0};             ///< 0-based row index in the job's table
  RecipeRow recipe;                 ///< the recipe (or its reading error)
  std::size_t total{0};             ///< the job's recipes
  std::optional<std::string> view;  ///< the job's plan view (null: no plan in the rows)
  /// Times the item was handed out, this take included (its delivery count in the group): more
  /// than SharedQueueOptions::max_takes means that many takers never stored its row.
  std::size_t takes{1};
};

/// Settings of a SharedJobQueue.
struct SharedQueueOptions {
  /// This replica's name: its consumer name in the group and its key in the shares.
  std::string replica;
  /// An item held unacknowledged this long by another replica is taken over [ms]; a replica
  /// renews the items it is solving (keep()) well within it.
  std::chrono::milliseconds claim_idle{30000};
  /// A job's keys are kept this long after its last write [ms].
  std::chrono::milliseconds ttl{3600000};
  /// The heartbeat's time to live [ms] (the replicas' batch_job_stale_s).
  std::chrono::milliseconds alive{30000};
  std::string prefix{"slosh:jobs:"};
  /// Most bytes of result rows one shared job stores in Redis (the accepting replica's
  /// batch_jobs_bytes, kept in the job's spec so every replica applies the same bound): the row
  /// that passes it is the job's last, and the job ends failed naming batch_jobs_bytes.
  std::size_t max_bytes{std::size_t{256} << 20};
  /// An item handed out more often than this is not solved again: its row is recorded failed
  /// (dead_item_text). The replicas' batch_job_max_takes.
  std::size_t max_takes{3};
};

class SharedJobQueue {
 public:
  SharedJobQueue(std::shared_ptr<RedisClient> client, SharedQueueOptions options);

  /// Puts job `status` with its `recipes` into Redis: spec, record, the items whose rows are not
  /// stored yet, the group, the job in the shared set. nullopt once done; else why not (naming
  /// the store).
  [[nodiscard]] std::optional<std::string> publish(const JobStatus& status,
                                                   const std::vector<RecipeRow>& recipes);
  /// The jobs with items left, oldest first; empty when Redis cannot be asked.
  [[nodiscard]] std::vector<std::string> jobs();
  /// Up to `n` items of job `id`: first those Redis handed to this replica in a take whose reply
  /// was lost (pending for this replica but not among `held`, the entries it is solving), then
  /// those another replica held longer than claim_idle, then new ones. Empty when it has none
  /// left to hand out or Redis cannot be asked.
  [[nodiscard]] std::vector<SharedItem> take(const std::string& id, std::size_t n,
                                             const std::set<std::string>& held = {});
  /// Renews this replica's hold of `entries` of job `id` (they are being solved).
  void keep(const std::string& id, const std::vector<std::string>& entries);

  /// What store() did with a row.
  enum class Stored {
    kNew,     ///< stored and counted for this replica
    kAgain,   ///< the row was stored before (by this or another replica); acknowledged
    kClosed,  ///< the job is cancelled, removed, past its bytes or no longer in Redis: not stored
    kFailed,  ///< Redis did not answer: the item stays pending and is taken over later
  };
  struct StoreResult {
    Stored stored{Stored::kFailed};
    std::size_t done{0};  ///< the job's stored rows after this one
  };
  /// Stores the row `text` of `item` once (by index), counts it (`failed`: a row in error) and
  /// acknowledges the item, atomically.
  StoreResult store(const std::string& id, const SharedItem& item, const std::string& text,
                    bool failed);

  /// Where a job stands after beat().
  enum class Fate { kRunning, kFinished, kGone, kUnknown };
  /// Rewrites the record of job `id` from its spec and counters (any replica may: the values are
  /// the job's, not this replica's) and renews its keys' time to live; a job whose rows are all
  /// stored, or that was asked to cancel, gets its final record (once: the first replica to write
  /// it) and leaves the shared set. kGone when Redis no longer holds the job (emptied, removed),
  /// kUnknown when Redis cannot be asked.
  Fate beat(const std::string& id);

  /// The record of a queued or running job `id` as of now (from its counters, not the last
  /// heartbeat's record); nullopt when it has finished, Redis does not hold it or cannot be asked.
  [[nodiscard]] std::optional<std::string> live_record(const std::string& id);

  /// Renews this replica's name in Redis (<prefix>replicas:<name>, for the heartbeat's time to
  /// live) with `token`, unique to this process; false when another live process held the name
  /// (two replicas with one --replica-id: their consumer names and shares would merge).
  bool hold_name(const std::string& token);

  /// Sets the cancel flag of job `id` (as a DELETE through any replica does); whether Redis took
  /// it.
  bool request_cancel(const std::string& id);

  [[nodiscard]] const SharedQueueOptions& options() const { return options_; }

  /// The items of a stream reply (XREADGROUP's, XAUTOCLAIM's or XRANGE's entry list).
  [[nodiscard]] static std::vector<SharedItem> items_of(const RedisReply& entries);
  /// The XADD of item `index` (recipe `r`) of job `status` to `stream`.
  [[nodiscard]] static std::vector<std::string> item_command(const std::string& stream,
                                                             const JobStatus& status,
                                                             std::size_t index, const RecipeRow& r);

 private:
  // A job's state in Redis: its composed status (nullopt without a spec), whether it has its
  // final record or was removed, whether Redis answered.
  struct Snapshot {
    std::optional<JobStatus> status;
    bool over{false};
    bool answered{false};
    bool too_large{false};     // its rows passed max_bytes: it ends failed
    std::size_t max_bytes{0};  // its spec's bound
  };
  // Reads it; `renew`: also renews its keys' time to live.
  Snapshot read(const std::string& id, bool renew);
  [[nodiscard]] std::string key(const std::string& id, const char* part) const;
  // The record of job `id` composed from the replies of its spec, counters and cancel flag.
  [[nodiscard]] std::optional<JobStatus> compose(const std::string& id, const RedisReply& spec,
                                                 const RedisReply& counts, bool cancel) const;
  // Writes `record` (final: only the first final write lands, and no later running one).
  bool write_record(const std::string& id, const std::string& record, bool final);
  // Sets the takes of `items` (taken over from another replica) from the group's delivery counts.
  void count_takes(const std::string& id, std::vector<SharedItem>& items);
  // Up to `n` entries of job `id` pending for this replica but not in `held`: a take whose reply
  // was lost (a Redis stall past the client's timeout) left them to this replica unknowingly.
  std::vector<SharedItem> take_lost(const std::string& id, std::size_t n,
                                    const std::set<std::string>& held);

  std::shared_ptr<RedisClient> client_;
  SharedQueueOptions options_;
  // Jobs in whose stream a take of this replica got no reply: look for its lost items.
  std::set<std::string> lost_;
};

}  // namespace slosh::service
