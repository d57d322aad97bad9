#pragma once
// Settings of `slosh serve` (embedded defaults = `make run`; config/slosh.json lists them).

#include <cstddef>
#include <string>

#include "storage/redis_url.hpp"

namespace slosh::service {

struct ServerConfig {
  std::string host{"127.0.0.1"};  ///< bind address
  int port{8080};                 ///< TCP port; 0 picks a free one
  /// Solve workers; 0 = the number of cores. Default 0.
  std::size_t workers{0};
  /// Solves that may wait for a worker; beyond, POST /v1/plans answers 503. Default 64.
  std::size_t queue{64};
  /// The plan cache behind the memory LRU: a SQLite file, or a Redis URL
  /// (redis://host:port/db or redis://:password@host:port/db) shared by several replicas; empty =
  /// memory only. A leading ${XDG_STATE_HOME} stands for the per-user state directory
  /// ($XDG_STATE_HOME, default ~/.local/state; state_dir.hpp), which the commands create with mode
  /// 0700 when needed. Default "${XDG_STATE_HOME}/slosh/plans.sqlite". Config key `cache`, env
  /// SLOSH_CACHE, flag --cache.
  std::string cache_path{"${XDG_STATE_HOME}/slosh/plans.sqlite"};
  /// With a Redis `cache`: a SQLite file used as this replica's local level between memory and
  /// Redis (get: memory, SQLite, Redis, promoting hits into the faster levels; put: all three);
  /// empty = memory and Redis only. Must stay empty when `cache` is a SQLite file. Default "".
  std::string cache_local;
  /// Expiry of the values written to Redis [s]; 0 = none. Default 0: an answer never goes stale
  /// (the planner version is in its key); bound Redis with maxmemory and an LRU policy instead.
  std::size_t cache_ttl_s{0};
  /// Longest a Redis command may take, connecting included [ms]; beyond, the request goes on
  /// from the local levels and Redis is retried after 1 s. Default 200.
  std::size_t redis_timeout_ms{200};
  /// Whether /readyz answers 503 (instead of 200 "degraded") while Redis is down. Default false:
  /// a replica whose Redis is down still answers correctly from its local levels.
  bool redis_required{false};
  /// Plans kept in memory in front of SQLite. Default 10000.
  std::size_t cache_entries{10000};
  /// Default and largest per-plan solve budget [s] (options.time_limit_s). Default 10 s.
  double solve_budget_s{10.0};
  /// How long a plan request waits beyond its budget (queued behind other solves) before it
  /// answers 504 [s]. Default 30 s.
  double queue_wait_s{30.0};
  /// Largest request body [bytes]; larger ones get 413. Default 1 MiB.
  std::size_t max_body_bytes{1u << 20};
  /// Largest number of recipes in one POST /v1/plans/batch. Default 1000.
  std::size_t batch_max{1000};
  /// Largest batch response [bytes]; beyond it the batch answers 422 (its plans stay cached).
  /// Default 64 MiB.
  std::size_t max_response_bytes{std::size_t{64} << 20};
  /// Most HTTP connection threads, started as connections arrive; each open connection (also an
  /// idle keep-alive one) holds one. Default 256.
  std::size_t http_threads{256};
  /// Longest wait for the next bytes of a request, and for a blocked write to drain [s]. Default 5.
  double read_timeout_s{5.0};
  double write_timeout_s{5.0};
  /// An idle keep-alive connection is closed after this [s]. Default 5.
  double keep_alive_timeout_s{5.0};
  /// A connection must deliver a whole request (line, headers and body) within this of
  /// connecting or of its previous answer, beyond the keep-alive wait; else it is closed [s].
  /// Bounds slow ("trickling") clients, which per-read timeouts do not. Default 10.
  double request_timeout_s{10.0};
  /// Plan cache bounds: bytes of the memory tier (default 256 MiB) and of the plans in the SQLite
  /// store, pruned oldest first beyond it (default 1 GiB; 0 = unbounded).
  std::size_t cache_memory_bytes{std::size_t{256} << 20};
  std::size_t cache_store_bytes{std::size_t{1} << 30};
  /// Bound of the min-time answers in the same SQLite file (their own table), pruned oldest first
  /// beyond it [bytes]. Default 256 MiB; 0 = unbounded.
  std::size_t cache_min_time_store_bytes{std::size_t{256} << 20};
  /// Memory the cam exports in flight (GET /v1/plans/{key}/cam.csv and cam.st) may hold together:
  /// each reserves an upper bound of its rows and file until its response is written; one that
  /// does not fit answers 503 with Retry-After (one larger than the whole budget runs alone).
  /// Default 256 MiB (at least 3 of the largest, 200 000-row, tables at once).
  std::size_t cam_export_bytes{std::size_t{256} << 20};
  /// Log format: "text" (one line per message) or "json" (one JSON object per line: time, level,
  /// msg; the access log adds request_id, method, route, path, status, ms, bytes and, for a plan,
  /// plan_key, strategy, plan_status, cached). Default "text".
  std::string log_format{"text"};
  /// This replica's name in the X-Slosh-Replica header of every response (which replica behind a
  /// proxy answered); "" = the host name. Default "".
  std::string replica_id;
  /// Batch jobs (POST /v1/batches): most recipes in one job (more: 422 naming batch_job_max).
  /// Default 100000. The body limit max_body_bytes still holds (a CSV recipe row is ~100 bytes).
  std::size_t batch_job_max{100000};
  /// Most jobs queued or running on one replica (they run one after the other); beyond, POST
  /// /v1/batches answers 503 with Retry-After. Default 8.
  std::size_t batch_jobs_max{8};
  /// Most finished jobs the in-memory job store keeps (their results included); beyond, the
  /// least recently written go first. Default 100.
  std::size_t batch_jobs_kept{100};
  /// Most bytes of job records and result rows the in-memory job store keeps [bytes]; beyond,
  /// the least recently written jobs (finished ones: running jobs are rewritten every 0.5 s) are
  /// forgotten first, and a job whose own results pass it stops as failed, naming this setting.
  /// Default 256 MiB (the rows of "view": "full" are ~30 KiB each).
  std::size_t batch_jobs_bytes{std::size_t{256} << 20};
  /// A finished job is forgotten this long after its last write [s]. Default 3600.
  double batch_job_ttl_s{3600.0};
  /// A queued or running job whose record its replica has not rewritten for this long reads as
  /// failed ("the replica running it stopped"); the owner rewrites it every 0.5 s [s]. Default 30.
  double batch_job_stale_s{30.0};
  /// Where a batch job's items are solved when the cache is Redis: "helpers" (the replica that
  /// accepted it runs it as with "owner", and the other replicas solve its plans from the
  /// table's end into the shared plan cache; when its replica goes silent for half of
  /// batch_job_stale_s another one takes the job over from its record and rows in Redis),
  /// "owner" (the replica that accepted it runs them all; its record and rows are shared through
  /// Redis) or "replicas" (its items go into a Redis stream with a consumer group, every
  /// replica's workers take them, an item a stopped replica took is taken over after
  /// batch_job_stale_s, each row is stored once). Without Redis a job always runs on its
  /// replica. Default "helpers".
  std::string batch_job_spread{"helpers"};
  /// With batch_job_spread = "replicas": an item of a shared job taken this many times by
  /// replicas that never stored its row (each stopped, crashed or was cut off from Redis while
  /// solving it) is not handed out again: its row is recorded failed, naming this setting, so an
  /// item that kills its solver cannot circulate forever. Takes are Redis's delivery counts of
  /// the item in the job's consumer group. Default 3 (allowed 1 to 100).
  std::size_t batch_job_max_takes{3};
};

/// This replica's name: replica_id, or the host name when that is empty.
[[nodiscard]] std::string replica_name(const ServerConfig& config);

/// The SQLite file of the plan cache ("" = none): `cache`, or `cache_local` with a Redis cache.
[[nodiscard]] inline std::string local_cache_path(const ServerConfig& c) {
  return is_redis_url(c.cache_path) ? c.cache_local : c.cache_path;
}

/// The Redis URL of the plan cache's shared level ("" = none).
[[nodiscard]] inline std::string redis_cache_url(const ServerConfig& c) {
  return is_redis_url(c.cache_path) ? c.cache_path : std::string();
}

}  // namespace slosh::service
