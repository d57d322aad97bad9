#pragma once
// Where batch jobs (POST /v1/batches, SPEC §13) keep their state, so that any replica can answer
// for a job: a memory store in one process, a Redis store shared by the replicas.
//
// The store holds opaque text: the job's record (its state as the job manager renders it, JSON)
// and its result rows in item order (one per recipe, in the job's row format). The job manager
// owns the meaning; a store only keeps, bounds and expires them.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace slosh::service {

/// What a store holds of a job whose record it lacks (JobStore::traces).
enum class JobTraces {
  kNone,        ///< nothing that says the job lives: unknown
  kRows,        ///< its rows (the record was evicted or deleted)
  kLiveCancel,  ///< its cancel flag, and the heartbeat of a replica running it
};

class JobStore {
 public:
  virtual ~JobStore() = default;

  /// Writes the record of job `id`, replacing the previous one (a new job's first write creates
  /// it). False when the store could not be written (the caller keeps its own copy).
  virtual bool put_record(const std::string& id, const std::string& record) = 0;
  /// Creates job `id` with its first record, where every replica that reads this store finds it:
  /// a shared store (or the shared level of a tiered one) must take the record, else the job is
  /// not created and nothing of it is kept, so that no replica ever answers 404 for a job that
  /// was accepted. nullopt once created; else why not, a sentence naming the store, e.g. "the
  /// shared job store (redis://127.0.0.1:6379/0) is unavailable: no reply within 200 ms".
  /// Default: put_record().
  [[nodiscard]] virtual std::optional<std::string> create(const std::string& id,
                                                          const std::string& record) {
    if (put_record(id, record)) return std::nullopt;
    return std::string("the job store did not take the job's record");
  }

  /// The record of job `id` and whether the store answered at all. A shared store that is
  /// down, slow or has every connection busy, or answered something that is not a record, did
  /// not answer: the job may run on another replica, so the caller must not read the missing
  /// record as "no such job". A job removed (remove()) is missing.
  struct RecordLookup {
    std::optional<std::string> text;
    bool answered{true};
    /// The store answered, but what it holds under the record's name is not a record (e.g. a
    /// Redis key of another type): the job's stored state is damaged, not unreachable.
    bool damaged{false};
  };
  [[nodiscard]] virtual RecordLookup lookup_record(const std::string& id) = 0;
  /// The record of job `id`; nullopt when the store does not know it or cannot be read.
  [[nodiscard]] std::optional<std::string> record(const std::string& id) {
    return lookup_record(id).text;
  }

  /// Writes result rows `first`, `first` + 1, ... of job `id`. Rows are keyed by their index, so
  /// writing a row again (a retried write whose first attempt did land) replaces it instead of
  /// adding a duplicate, and a write that was lost leaves its indexes missing (never shifts the
  /// later rows). False when the store could not be written or `first` would leave a gap.
  virtual bool put_rows(const std::string& id, std::size_t first,
                        const std::vector<std::string>& rows) = 0;
  /// Rows [offset, offset + count) of job `id` in index order, stopping before the first index
  /// the store does not hold (fewer at the end, or where a row is missing); nullopt when the
  /// store does not know the job or cannot be read.
  [[nodiscard]] virtual std::optional<std::vector<std::string>> rows(const std::string& id,
                                                                     std::size_t offset,
                                                                     std::size_t count) = 0;

  /// Rows [offset, offset + count) of job `id` as slots: nullopt for an index the store does not
  /// hold, so that a reader can name every missing row (rows() stops at the first). nullopt when
  /// the store does not know the job or cannot be read. Default: rows(), then empty slots.
  [[nodiscard]] virtual std::optional<std::vector<std::optional<std::string>>> row_slots(
      const std::string& id, std::size_t offset, std::size_t count) {
    const auto got = rows(id, offset, count);
    if (!got) return std::nullopt;
    std::vector<std::optional<std::string>> out(got->begin(), got->end());
    out.resize(count);
    return out;
  }
  /// row_slots() and, when the store did not answer, why (slots nullopt and `failure` naming the
  /// store, e.g. "the shared job store (redis://127.0.0.1:6379/0) did not answer in time: no reply
  /// within 200 ms"), so that a reader tells a store that is slow apart from rows that are gone.
  struct SlotsRead {
    std::optional<std::vector<std::optional<std::string>>> slots;
    std::string failure;  ///< empty unless the store did not answer
  };
  [[nodiscard]] virtual SlotsRead read_slots(const std::string& id, std::size_t offset,
                                             std::size_t count) {
    return {row_slots(id, offset, count), {}};
  }

  /// Renews the heartbeat of job `id` in a shared store with a command that a store refusing
  /// writes (Redis at maxmemory with noeviction) still takes, so that other replicas know its
  /// owner is alive while its record there cannot be rewritten. Default: nothing to renew.
  virtual bool touch(const std::string& id) {
    (void)id;
    return true;
  }
  /// Milliseconds since the owner of job `id` last wrote its record or renewed its heartbeat in
  /// this store; nullopt when unknown (no heartbeat, expired, or the store cannot be asked).
  [[nodiscard]] virtual std::optional<std::int64_t> heartbeat_age_ms(const std::string& id) {
    (void)id;
    return std::nullopt;
  }
  /// What of job `id` this replica holds that the shared store does not (rows and the latest
  /// record kept here only, retried at every heartbeat), and why; nullopt when the shared store
  /// holds all of it (or there is none).
  struct Unshared {
    std::size_t rows{0};  ///< rows held here only
    std::string reason;   ///< the shared store's last refusal or failure, naming it
  };
  [[nodiscard]] virtual std::optional<Unshared> unshared(const std::string& id) {
    (void)id;
    return std::nullopt;
  }
  /// Why this store's most recent failed write failed, naming the store (e.g. "the shared job
  /// store (redis://127.0.0.1:6379/0) refused the write: OOM command not allowed when used memory
  /// > 'maxmemory'."); empty when no write failed yet. Default empty.
  [[nodiscard]] virtual std::string last_write_failure() { return {}; }
  /// The replica that took job `id` over, when this (shared) store refused this replica's last
  /// write of the job's record or rows because the job's owner mark names that replica; nullopt
  /// otherwise. Default nullopt (a store of one replica has no other owner).
  [[nodiscard]] virtual std::optional<std::string> taken_over_by(const std::string& id) {
    (void)id;
    return std::nullopt;
  }
  /// A sentence for /readyz while some jobs' rows or records are held here only because the
  /// shared store refuses or fails their writes (naming it and its reason); empty otherwise.
  [[nodiscard]] virtual std::string sharing_problem() { return {}; }

  /// Forgets this replica's own copy of job `id` and leaves the shared store as it is (another
  /// replica took the job over). Default: nothing (a store of one replica has no other copy).
  virtual void drop_local(const std::string& id) { (void)id; }
  /// What the store holds of job `id` besides a record (asked when it has no record for it):
  /// its rows, or its cancel flag while its heartbeat lives (the replica that runs it publishes
  /// the record again at its next heartbeat), so the job must not be answered as unknown. A
  /// cancel flag alone, with no live heartbeat, is no trace: no replica will publish the job (it
  /// was lost with an emptying of the store, and the flag is only a DELETE sent again). Default
  /// none.
  [[nodiscard]] virtual JobTraces traces(const std::string& id) {
    (void)id;
    return JobTraces::kNone;
  }
  /// Which of `ids` have no record in this store and were not removed (a shared store that
  /// evicted or lost a record key): their owner publishes them again. Default none.
  [[nodiscard]] virtual std::vector<std::string> records_missing_among(
      const std::vector<std::string>& ids) {
    (void)ids;
    return {};
  }

  /// Asks the replica that runs job `id` to cancel it (it polls cancel_requested()). False when
  /// the store could not be written.
  virtual bool request_cancel(const std::string& id) = 0;
  [[nodiscard]] virtual bool cancel_requested(const std::string& id) = 0;

  /// Forgets job `id` (its record, rows and cancel flag). A shared store keeps a mark that the
  /// job was removed (for its time to live), so that its owner drops its own copy and does not
  /// publish it again, and its cancel_requested() is then true. False when the store could not
  /// be written.
  virtual bool remove(const std::string& id) = 0;
  /// Which of `ids` were removed (remove()) through this store, e.g. by another replica. Default
  /// none (a local store forgets removed jobs at once).
  [[nodiscard]] virtual std::vector<std::string> removed_among(
      const std::vector<std::string>& ids) {
    (void)ids;
    return {};
  }

  /// Keeps a copy of job `id` that the shared store already holds whole (its final `record` and
  /// `rows` 0 .. n-1) on this replica only, so that it is published again if the shared store
  /// loses it (emptied, restarted): a job shared out to the replicas finished, kept by the
  /// replica that accepted it. Whether the copy was kept. Default: not kept (no local level).
  virtual bool keep_copy(const std::string& id, const std::string& record,
                         const std::vector<std::string>& rows) {
    (void)id;
    (void)record;
    (void)rows;
    return false;
  }

  /// The jobs this store holds (a local store: the ones a replica republishes to a shared store
  /// that lost them). Default none.
  [[nodiscard]] virtual std::vector<std::string> ids() { return {}; }

  /// A shared store: true once after each time it was emptied (FLUSHALL, a restart without
  /// persistence) since this object last asked, so that the replica publishes its jobs again;
  /// false otherwise or when it cannot be asked. Default false.
  virtual bool emptied_since_last_check() { return false; }
  /// Whether a job the store does not know may be one it lost in a recent emptying (the replicas
  /// are still publishing theirs again): such a job is answered 503, not 404. Default false.
  [[nodiscard]] virtual bool recently_emptied() { return false; }
  /// Sends the shared level of a tiered store what it is missing: every job after it was emptied,
  /// else the records and rows whose writes to it failed, and the cancels and removals this
  /// replica accepted that it lost; drops the local copies of jobs removed through another
  /// replica. Called at every heartbeat. Default no-op.
  virtual void resync() {}

  /// False while the store, or the shared level of a tiered one, cannot be asked (Redis down):
  /// a job it does not answer for may then run on another replica. Default true.
  [[nodiscard]] virtual bool reachable() const { return true; }
};

}  // namespace slosh::service
