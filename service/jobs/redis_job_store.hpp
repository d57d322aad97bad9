#pragma once
// The job store on Redis (SPEC §13): batch jobs whose state any replica can read.
//
// Keys of job <id> (under the prefix, default "slosh:jobs:"): <id>:record (a string: the
// record), <id>:rows (a hash: field = the row's index, value = the row; HSET
// is idempotent, so a write retried after a timeout cannot duplicate a row), <id>:cancel (a string,
// present once cancelling was asked), <id>:removed (a string, present once the job was removed:
// its record then reads as missing even if its owner writes it again). Every write sets the time to
// live of all three keys to `ttl` again, so a job is kept `ttl` after its last write: a running job
// writes its progress and stays, a finished job (or one whose replica died) expires `ttl` after its
// last record. <id>:alive is the owner's heartbeat: set with every record for `settle` (the
// replicas' batch_job_stale_s) and renewed by touch() while the record cannot be written (Redis
// at maxmemory refuses SET and HSET but takes PEXPIRE), so that another replica does not read a
// live job as failed.
//
// With an `owner` (the replica's name), the record and row writes are conditional: they land only
// while the job's owner mark (<id>:owner, set by HelpedJobs when a replica publishes or takes the
// job over) is missing or names this replica, checked and written in one Lua script (EVAL), so a
// replica that was cut off or paused while another took its job over never writes over the new
// owner's state, whatever it finished meanwhile. A Lua script rather than WATCH/MULTI: WATCH needs
// the check and the transaction on one pinned connection in two round trips (the client's
// connections are a pool), and a lost race then only shows as a nil EXEC to tell apart from a
// refusal; the script is one atomic round trip with the other replica's name as its answer.

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "jobs/job_store.hpp"
#include "storage/redis_client.hpp"

namespace slosh::service {

class RedisJobStore final : public JobStore {
 public:
  /// `ttl`: how long a job is kept after its last write (> 0); `prefix`: the keys' prefix.
  /// `settle`: how long after an emptying a job the store does not know may be one that was
  /// lost and is answered 503, not 404 (its owner republishes it at its next heartbeat, or when
  /// it is running again after a pause: config batch_job_stale_s, past which its jobs read as
  /// failed anyway).
  RedisJobStore(std::shared_ptr<RedisClient> client, std::chrono::seconds ttl,
                std::string prefix = "slosh:jobs:",
                std::chrono::milliseconds settle = std::chrono::milliseconds(kSettleMs),
                std::string owner = "");

  bool put_record(const std::string& id, const std::string& record) override;
  /// put_record(); on failure "the shared job store (<url>) is unavailable: <why>" (the client's
  /// last failure, or Redis's error reply). A write that timed out may still land later: the
  /// caller removes the job once Redis answers again (TieredJobStore does).
  [[nodiscard]] std::optional<std::string> create(const std::string& id,
                                                  const std::string& record) override;
  [[nodiscard]] RecordLookup lookup_record(const std::string& id) override;
  bool put_rows(const std::string& id, std::size_t first,
                const std::vector<std::string>& rows) override;
  [[nodiscard]] std::optional<std::vector<std::string>> rows(const std::string& id,
                                                             std::size_t offset,
                                                             std::size_t count) override;
  /// One HMGET of the asked indexes (bounded by HLEN as rows()).
  [[nodiscard]] std::optional<std::vector<std::optional<std::string>>> row_slots(
      const std::string& id, std::size_t offset, std::size_t count) override {
    return read_slots(id, offset, count).slots;
  }
  [[nodiscard]] SlotsRead read_slots(const std::string& id, std::size_t offset,
                                     std::size_t count) override;
  /// PEXPIRE of <id>:alive (a command Redis takes at maxmemory with noeviction); SET again when
  /// it has expired (which a full Redis refuses).
  bool touch(const std::string& id) override;
  /// From <id>:alive: its value is the time to live it was given [ms], so its age is that less
  /// its PTTL.
  [[nodiscard]] std::optional<std::int64_t> heartbeat_age_ms(const std::string& id) override;
  [[nodiscard]] std::string last_write_failure() override;
  /// The replica the owner mark of job `id` named when it refused this replica's last record or
  /// row write of the job; nullopt when none was refused so.
  [[nodiscard]] std::optional<std::string> taken_over_by(const std::string& id) override;
  /// The rows or cancel key exists (the removal mark does not).
  [[nodiscard]] JobTraces traces(const std::string& id) override;
  [[nodiscard]] std::vector<std::string> records_missing_among(
      const std::vector<std::string>& ids) override;
  bool request_cancel(const std::string& id) override;
  [[nodiscard]] bool cancel_requested(const std::string& id) override;
  bool remove(const std::string& id) override;
  [[nodiscard]] std::vector<std::string> removed_among(
      const std::vector<std::string>& ids) override;
  /// The generation mark (key <prefix>generation, "<token>:<unix ms set>") tells an emptied Redis
  /// apart: missing, it is set again (unix ms 0 on this object's first look: a fresh Redis, not a
  /// recent loss) and a new token means the store was emptied since the last look.
  bool emptied_since_last_check() override;
  /// The mark is missing or was set again less than `settle` ago.
  [[nodiscard]] bool recently_emptied() override;
  /// The default `settle` [ms]: the replicas republish their jobs at their next heartbeat (0.5 s).
  static constexpr std::int64_t kSettleMs = 5000;
  /// Whether the client believes Redis is up (its last command succeeded or backs off).
  [[nodiscard]] bool reachable() const override { return client_->state().up; }

  /// The Redis key of `part` (record, rows or cancel) of job `id`.
  [[nodiscard]] std::string key(const std::string& id, const std::string& part) const {
    return prefix_ + id + ":" + part;
  }

 private:
  // Runs `commands` in MULTI ... EXEC with the TTL of the job's keys renewed; false on failure.
  // `owned`: a write of the job's state, made only while its owner mark allows it (owned_write).
  bool write(const std::string& id, std::vector<std::vector<std::string>> commands,
             bool owned = false) {
    return write_failure(id, std::move(commands), owned).empty();
  }
  // write(): "" on success, else why it failed (the client's last failure or Redis's error).
  std::string write_failure(const std::string& id, std::vector<std::vector<std::string>> commands,
                            bool owned = false);
  // `commands` (with their TTL renewals) in one Lua script that first checks the owner mark;
  // "" on success, else why not; a refusal by the mark sets `taken` and is noted for
  // taken_over_by().
  std::string owned_write(const std::string& id,
                          const std::vector<std::vector<std::string>>& commands, bool& taken);
  // Why the replies of a write (MULTI ... EXEC) are a failure; "" when they are not.
  std::string write_replies_failure(const std::optional<std::vector<RedisReply>>& replies) const;

  // "the shared job store (<url>) did not answer in time: ..." (or "cannot be reached: ...")
  // after a read that got no reply.
  std::string unanswered() const;
  // The command that sets the heartbeat of job `id` for `settle`.
  std::vector<std::string> alive_command(const std::string& id) const;

  // The mark now, set (with `set_ms`) when missing; nullopt when Redis cannot be asked.
  std::optional<std::string> generation(std::int64_t set_ms);

  const std::shared_ptr<RedisClient> client_;
  std::mutex mutex_;
  std::string seen_generation_;  // the mark at the last look ("" before the first)
  std::mutex failure_mutex_;     // guards last_failure_ (mutex_ is held across commands)
  std::string last_failure_;     // of the last failed write, naming the store
  const std::string ttl_;        // seconds, as text
  const std::string prefix_;
  const std::int64_t settle_ms_;
  const std::string owner_;  // this replica's name; empty: writes are not conditional
  // Jobs whose write the owner mark refused, and the replica it named.
  std::mutex taken_mutex_;
  std::unordered_map<std::string, std::string> taken_;
};

}  // namespace slosh::service
