#pragma once
// The Redis side of a batch job run by the replica that accepted it and helped by the others
// (batch_job_spread = "helpers", the default with a Redis cache; SPEC §13). The owner runs the
// job as "owner" does (its record, and every row in table order, through the tiered job store):
// it finishes and serves the job alone while Redis refuses writes. The other replicas solve the
// job's plans from the end of the table into the shared plan cache, so the owner's items there
// are cache hits; they store no row, so every row is stored and counted once, by the owner.
//
// Keys of job <id> besides the job store's: <id>:help (a hash: owner = the replica running it,
// front = the index below which the owner has started every item: helpers skip those),
// <id>:items (a stream, one entry per recipe in reverse table order, read by the group
// "helpers"), <id>:helped (a hash: index -> the replica credited with the item, the first that
// solved it: a helper when it noted it, else the owner when it stored the row; the shares and
// each replica's slosh_batch_job_items_total count the same), <id>:solved (a sorted set of the
// indexes the helpers solved, scored by index: the items solved ahead of the owner's rows).
// <prefix>helping is a sorted set of the helped jobs by creation time.
//
// When the owner's heartbeat (the job store's <id>:alive) has been silent for half of
// batch_job_stale_s, a helper adopts the job (a lock, then owner = itself): it reads the table
// from the stream's entries and the record and first `done` rows from Redis, and runs the job
// from there as its owner. So kill -9 of the owner loses no row, and the job has one owner (one
// writer of its record) at a time.

#include <chrono>
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "jobs/batch_job_record.hpp"
#include "jobs/recipe_table.hpp"
#include "jobs/shared_job_queue.hpp"
#include "storage/redis_client.hpp"

namespace slosh::service {

class HelpedJobs {
 public:
  /// `replica`: this replica's name; `ttl`: the job keys' time to live.
  HelpedJobs(std::shared_ptr<RedisClient> client, std::string replica,
             std::chrono::milliseconds ttl, std::string prefix = "slosh:jobs:");

  /// Offers job `status` (run here) to the helpers: its owner, its items in reverse order, and
  /// `front` (the owner has started the items below it: the helpers skip them). Whether Redis
  /// took it all (else the job runs here alone).
  bool publish(const JobStatus& status, const std::vector<RecipeRow>& recipes,
               std::size_t front = 0);
  /// The owner's heartbeat: the helpers skip items below `front`. Returns the job's owner as
  /// Redis holds it ("" when Redis does not hold the job; nullopt when it cannot be asked).
  std::optional<std::string> beat(const std::string& id, std::size_t front);
  /// Holds this replica's name in Redis for `alive` under this process's `token` (and lists it
  /// among the helpers); false when another live process holds it (a duplicate --replica-id).
  /// True when Redis does not answer.
  bool hold_name(const std::string& token, std::chrono::milliseconds alive);
  /// The replica that owns job `id` as its owner mark in Redis says (the mark outlives the job's
  /// end, so a paused former owner learns another replica took the job over and ended it); ""
  /// when Redis holds no mark, nullopt when it cannot be asked. Writes nothing.
  std::optional<std::string> owner_of(const std::string& id);
  /// Who is credited with a stored row: the replica that solved its plan first, and whether
  /// this call noted it for this replica (else a helper did, maybe this replica's own helper,
  /// which counted it then).
  struct Credit {
    std::string solver;
    bool noted_now{false};
  };
  /// The owner stored the rows `indexes` (0-based) of job `id`: each is credited to the replica
  /// that solved its plan first (a helper that noted it, else this replica, noted now); nullopt
  /// when Redis cannot be asked (nothing credited yet).
  std::optional<std::vector<Credit>> credit(const std::string& id,
                                            const std::vector<std::size_t>& indexes);
  /// Items of job `id` from index `done` on whose plans the helpers have solved (the owner has
  /// not stored their rows yet); nullopt when Redis cannot be asked.
  std::optional<std::size_t> solved_from(const std::string& id, std::size_t done);
  /// This replica stops (SIGTERM) while it runs job `id`: when the job is offered and another
  /// helper is live, its heartbeat is taken away so that a helper adopts it at once (its record
  /// stays running, with every row stored so far); whether it was handed over. Only while the
  /// owner mark names this replica (one atomic script).
  bool hand_over(const std::string& id);
  /// This replica won job `id`'s takeover but could not start it (it is stopping, or Redis did
  /// not give the job's table): its heartbeat and adoption lock go, so that another helper takes
  /// the job at its next looks instead of after the lock.
  void give_back(const std::string& id);
  /// The job has finished: no more help. `as_owner`: closed by the replica that ran it, only
  /// while its owner mark names this replica (one atomic script).
  void close(const std::string& id, bool as_owner = false);

  /// A helped job as a helper sees it.
  struct Helped {
    std::string id;
    std::string owner;
    std::size_t front{0};
  };
  /// The helped jobs, oldest first; empty when Redis cannot be asked.
  std::vector<Helped> jobs();
  /// Up to `n` new items of job `id`, in stream order (from the table's end).
  std::vector<SharedItem> take(const std::string& id, std::size_t n);
  /// This replica solved the plan of item `index` of job `id`: whether it is credited with it
  /// (the first replica to note an item is; false also when Redis cannot be asked).
  bool note_helped(const std::string& id, std::size_t index);
  /// Makes this replica the owner of job `id` when no other replica did within `lock`: whether
  /// it now owns it. Its heartbeat (`alive`, batch_job_stale_s) starts at once: a taker that dies
  /// before its first is judged from its takeover, not from the silence of the owner before it.
  bool adopt(const std::string& id, std::chrono::milliseconds lock,
             std::chrono::milliseconds alive);
  /// Job `id`'s table as its stream holds it.
  struct TableRead {
    /// All `total` recipes; nullopt when some are missing or Redis did not answer.
    std::optional<std::vector<RecipeRow>> recipes;
    /// Whether Redis answered every read (then a missing recipe is lost, not late).
    bool answered{true};
    std::size_t missing{0};  ///< recipes Redis answered without
  };
  /// The recipes of job `id` (`total` of them) from its stream.
  TableRead table(const std::string& id, std::size_t total);

  [[nodiscard]] const std::string& replica() const { return replica_; }

 private:
  [[nodiscard]] std::string key(const std::string& id, const char* part) const {
    return prefix_ + id + ":" + part;
  }
  std::shared_ptr<RedisClient> client_;
  std::string replica_;
  std::string ttl_ms_;
  std::string prefix_;
};

}  // namespace slosh::service
