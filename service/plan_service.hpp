#pragma once
// What the HTTP endpoints do, without the HTTP library: parse, cache, solve on the worker pool,
// render. Every method returns a Reply and never throws (errors become the JSON envelope).

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "cam_export.hpp"
#include "export_budget.hpp"
#include "metrics.hpp"
#include "plan_cache.hpp"
#include "plan_facts.hpp"
#include "redis_client.hpp"
#include "rendered_plans.hpp"
#include "server_config.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_view.hpp"
#include "worker_pool.hpp"

namespace slosh::service {

/// An HTTP-level answer.
struct Reply {
  int status{200};
  std::string body;
  std::string content_type{"application/json"};
  /// "gzip" when `body` is already gzip-coded (a cached plan's stored coding); empty: `body` is
  /// the identity coding (the HTTP layer may compress it for a client that accepts gzip).
  std::string content_encoding;
  std::vector<std::pair<std::string, std::string>> headers;
  /// Kept alive until the body has been written to the client (a cam export's reservation of
  /// the export budget); empty for most replies.
  std::shared_ptr<const void> hold;
  /// Set when the reply carries a plan (POST /v1/plans, GET /v1/plans/{key}): for the access log.
  std::optional<PlanFacts> plan;
};

/// What a solve or a min-time search produced: the stored body (an api::StoredPlan body, or a
/// stored min-time answer), or the error.
struct SolveOutcome {
  std::string body;
  std::optional<api::ApiError> error;
};

/// Who waits for a running solve or search (one per flight): a flight that only clients wait for
/// (each of whom may hang up) is stopped when the last of them has gone; one that any batch item
/// waits for (pinned) runs to its end.
struct FlightWaiters {
  /// Read by the solve (PlanOptions::stop): set once nobody waits any more.
  std::atomic<bool> stop{false};
  int waiters{0};      ///< clients waiting (under the service's flight lock)
  bool pinned{false};  ///< a waiter that cannot hang up joined (under the flight lock)
};

/// A min-time request on its way (PlanService::start_min_time): answered from the cache at once,
/// or the future of its search (a new one, or the running search of the same key it joined).
struct PendingMinTime {
  std::string key;
  /// The stored answer when it came from the cache (then `search` is invalid).
  std::optional<std::string> cached;
  /// The search's outcome otherwise; already ready with a 503 error when it could not be queued.
  std::shared_future<SolveOutcome> search;
  /// The waiters of the search this request waits for, when it was started `cancellable`.
  std::shared_ptr<FlightWaiters> waiters;
};

/// One item of a batch: a rendered plan, or the error of the item (field paths relative to the
/// item's request).
struct BatchResult {
  std::string plan;                    ///< rendered plan JSON; empty when `error` is set
  std::optional<api::ApiError> error;  ///< set when the item failed
  bool cached{false};                  ///< the plan came from the cache
  [[nodiscard]] bool ok() const { return !error; }
};

/// The items of a batch in request order while their solves run on the pool.
class PendingBatch {
 public:
  [[nodiscard]] std::size_t size() const { return results_.size(); }
  /// Items finished now (cache hits, invalid items and finished solves).
  [[nodiscard]] std::size_t finished() const;
  /// Waits up to `timeout` for item `i`; true when it is finished.
  [[nodiscard]] bool wait_for(std::size_t i, std::chrono::milliseconds timeout) const;
  /// Waits for item `i` and returns it.
  [[nodiscard]] BatchResult get(std::size_t i) const;

 private:
  friend class PlanService;
  std::vector<BatchResult> results_;
  std::vector<std::shared_future<SolveOutcome>> pending_;  // invalid where results_ is final
};

/// One batch item on its way (PlanService::start_batch_item): finished now (a cache hit, an
/// invalid request), or the future of its solve.
struct StartedItem {
  BatchResult result;                        ///< final when `pending` is invalid
  std::shared_future<SolveOutcome> pending;  ///< the solve (new, or the running one joined)
  /// The item's result once finished (waits for the solve).
  [[nodiscard]] BatchResult get() const;
};

/// The reply of an API error: its status and envelope; 503 overloaded adds Retry-After.
Reply reply_of(const api::ApiError& error);

/// The reply of the 500 envelope for an exception that is not an api::ApiError.
Reply internal_error_reply(const char* what);

/// What `body` returns; an api::ApiError thrown by it becomes its reply (reply_of) and any other
/// exception the 500 envelope, so that an endpoint never throws.
template <typename F>
Reply guarded_reply(F&& body) {
  try {
    return body();
  } catch (const api::ApiError& e) {
    return reply_of(e);
  } catch (const std::exception& e) {
    return internal_error_reply(e.what());
  } catch (...) {
    return internal_error_reply("unknown error");
  }
}

/// What a plan request asks of a hit: the view and whether the client accepts gzip.
struct HitView {
  api::PlanView view{api::PlanView::kFull};
  bool gzip{false};
};

class PlanService {
 public:
  explicit PlanService(const ServerConfig& config);
  /// Finishes queued and running solves.
  ~PlanService();

  /// `view`: the values of the request's `view` query parameter (api::parse_view_query; none =
  /// the full plan). The view changes neither the key nor the cache entry, only the reply.
  /// `gzip`: the client accepts the gzip coding; a cache hit then answers the plan's stored gzip
  /// bytes (Reply::content_encoding), compressed once when the plan was rendered.
  /// `abandoned` (optional) tells whether the client has gone away: its solve is stopped then,
  /// unless another request still waits for it.
  Reply post_plan(const std::string& body, const std::string& if_none_match,
                  const std::vector<std::string>& view = {}, bool gzip = false,
                  const std::function<bool()>& abandoned = {});
  Reply get_plan(const std::string& key, const std::string& if_none_match,
                 const std::vector<std::string>& view = {}, bool gzip = false);
  /// `abandoned` (optional) tells whether the client has gone away: no further solves are queued
  /// for it then. `view`: the query's view values (api::batch_view, with the body's "view").
  Reply post_batch(const std::string& body, const std::function<bool()>& abandoned = {},
                   const std::vector<std::string>& view = {});
  /// Starts a batch of parsed plan requests: cache hits and invalid items finish at once, the
  /// others are queued on the pool (waiting for queue room) with single-flight per recipe.
  PendingBatch start_batch(const std::vector<nlohmann::json>& requests,
                           const std::function<bool()>& abandoned = {});
  /// Starts one batch item: a cache hit or an invalid request finishes at once; otherwise its
  /// solve is queued at `priority` (waiting for queue room), or joins a running solve of the same
  /// recipe. Never throws: errors are the item's.
  StartedItem start_batch_item(const nlohmann::json& request,
                               TaskPriority priority = TaskPriority::kInteractive);
  /// The solve pool (its counters are reported by the batch jobs and tests).
  [[nodiscard]] const WorkerPool& pool() const { return pool_; }
  [[nodiscard]] const ServerConfig& config() const { return config_; }
  /// False once begin_shutdown has run.
  [[nodiscard]] bool accepting() const { return ready_; }
  Reply post_simulate(const std::string& body);
  /// POST /v1/min-time (SPEC §9): each strategy's search is one task on the worker pool (so the
  /// strategies run in parallel), within options.time_limit_s per search; 503 when the queue has
  /// no room for them, 504 when they have not finished their budget plus queue_wait_s after.
  /// Answers are cached per request key (memory, and the store's min_times table) when every
  /// search ended optimal or infeasible. Identical concurrent requests share one search (see
  /// start_min_time); those that waited for another's search answer as it did (cached: false).
  /// `abandoned` (optional): as for post_plan, the search stops when its last client has gone.
  Reply post_min_time(const std::string& body, const std::string& if_none_match,
                      const std::function<bool()>& abandoned = {});
  /// Starts a validated min-time request: the cached answer, or the running search of the same
  /// key (single flight, when that search has at least this request's budget), or a new search
  /// of one pool task per strategy (`wait_for_room`: wait for queue slots instead of refusing
  /// with 503). The last task to finish assembles, caches and publishes the answer, so nobody
  /// waits on a worker and no lock is held while searching or queueing.
  /// `cancellable`: the caller may hang up (PendingMinTime::waiters; call leave_min_time when it
  /// stops waiting); otherwise the search runs to its end whoever else leaves.
  PendingMinTime start_min_time(const api::MinTimeRequest& request, bool wait_for_room,
                                bool cancellable = false);
  /// The caller of a cancellable start_min_time stops waiting; `gone`: its client hung up (the
  /// search stops when nobody else waits for it).
  void leave_min_time(const PendingMinTime& pending, bool gone);
  /// Solves and searches stopped because every client waiting for them had gone.
  [[nodiscard]] std::uint64_t cancelled_plans() const { return cancelled_plans_; }
  [[nodiscard]] std::uint64_t cancelled_min_times() const { return cancelled_min_times_; }
  Reply fluids() const;
  /// The web page's file `name` ("" = index.html) with its ETag and Cache-Control; 304 when
  /// `if_none_match` names the ETag, 404 for an unknown name. `gzip`: the client accepts the gzip
  /// coding; a file worth coding is then answered in its gzip bytes, compressed once per process.
  Reply web_asset(const std::string& name, const std::string& if_none_match,
                  bool gzip = false) const;
  /// The cam table file of the cached plan `key` (GET /v1/plans/{key}/cam.csv, cam.st): `query`
  /// as received (plan_cam_file: time-based at period_ms, default 1 ms, or on the master axis;
  /// allow_infeasible "true" or "false"; each parameter at most once). 404 for an unknown key,
  /// 422 naming a parameter, 503 with Retry-After when the exports in flight leave too little of
  /// the export budget (config cam_export_bytes); the reply holds its reservation until written.
  Reply cam_table(const std::string& key, CamFileFormat format, const CamQuery& query);
  Reply openapi() const;
  Reply health() const;
  Reply ready() const;
  Reply metrics_text() const;

  /// Readiness turns 503 and no new solve is queued; in-flight solves finish.
  void begin_shutdown();

  Metrics& metrics() { return metrics_; }
  /// Solve workers running (the configured count, or the cores for 0).
  [[nodiscard]] std::size_t workers() const { return pool_.workers(); }
  /// The solve pool, for other solves of the service (calibration fits).
  [[nodiscard]] WorkerPool& worker_pool() { return pool_; }
  [[nodiscard]] const PlanCache& cache() const { return cache_; }
  [[nodiscard]] const PlanCache& min_time_cache() const { return min_time_cache_; }
  /// The client of the shared cache level; null without a Redis cache.
  [[nodiscard]] const std::shared_ptr<RedisClient>& redis() const { return redis_; }
  /// The cache levels in words for the start-up log, e.g. "memory + sqlite plans.sqlite + redis
  /// redis://10.0.0.5:6379/0" (a password is never shown).
  [[nodiscard]] std::string cache_description() const;

  /// The envelope reply of an error status with a message (and optional field).
  static Reply error_reply(api::ErrorCode code, const std::string& message,
                           const std::string& field = "");

 private:
  using Outcome = SolveOutcome;
  // A running solve of a recipe or search of a min-time request: its result, its time budget [s],
  // and its number (so that only this solve removes its own entry).
  struct Flight {
    std::shared_future<Outcome> future;
    double budget{};
    std::uint64_t id{};
    std::shared_ptr<FlightWaiters> waiters;
  };
  // The rendered plan of `key`: from a running solve of the same recipe, or a new solve queued
  // on the pool (`wait_for_room`: block for a queue slot instead of answering 503). `waiter`
  // (optional): the caller may hang up; receives the flight's waiters (see leave_flight).
  // Without it the flight is pinned (runs to its end). `hit`: the view and coding the caller
  // asked for; once the plan is cached (and answered), what a hit in them answers is rendered on
  // the worker, since that client is likely to ask again (nothing for the plain full plan, which
  // a batch asks for).
  std::shared_future<Outcome> solve(const std::string& key, const api::PlanRequest& request,
                                    bool wait_for_room, bool* refused,
                                    TaskPriority priority = TaskPriority::kInteractive,
                                    std::shared_ptr<FlightWaiters>* waiter = nullptr,
                                    HitView hit = {});
  // Joins `waiters` (under inflight_mutex_): counted when `cancellable`, else pinned.
  static void join_locked(FlightWaiters& waiters, bool cancellable);
  // A waiter of the flight `waiters` of `key` in `flights` stops waiting; when its client is
  // `gone` and nobody else waits (and no batch pinned it), the flight is stopped and forgotten
  // (a new request starts afresh). True when this stopped it.
  bool leave_flight(std::unordered_map<std::string, Flight>& flights, const std::string& key,
                    const std::shared_ptr<FlightWaiters>& waiters, bool gone);
  // The reply of a rendered plan: 304 when `if_none_match` names it, the series of
  // `sample_period` added when set, in `view`.
  Reply plan_reply(const std::string& key, const std::string& body, bool cached,
                   const std::string& if_none_match, const std::optional<api::PlanRequest>& request,
                   std::optional<double> sample_period,
                   api::PlanView view = api::PlanView::kFull) const;
  // The reply of a cache hit of the plan `plan` in `view` (gzip-coded when `gzip`): 304 when
  // `if_none_match` names it; the body from the plan's kept renderings (hit_body).
  Reply hit_reply(const std::shared_ptr<const CachedValue>& plan, const std::string& if_none_match,
                  api::PlanView view, bool gzip);
  // The recipe key remembered for the request text `text`; nullopt when not remembered.
  std::optional<std::string> remembered_key(const std::string& text);
  void remember_key(const std::string& text, const std::string& key);
  // The reply of a hit of `key` in `view` (gzip-coded when `gzip`) when the plan is cached;
  // nullopt otherwise. Counts the hit.
  std::optional<Reply> cached_plan_reply(const std::string& key, const std::string& if_none_match,
                                         api::PlanView view, bool gzip);
  // 503 with Retry-After: the queue is full, or the service is shutting down.
  api::ApiError overloaded_error() const;
  struct MinTimeSearch;
  // Queues one task per strategy of `search`; on a refusal publishes the 503 at once (the tasks
  // already queued then skip their strategy).
  void queue_min_time_tasks(const std::shared_ptr<MinTimeSearch>& search, bool wait_for_room);
  // Runs strategy `i` of `search`; the last task to finish calls finish_min_time.
  void run_min_time_task(const std::shared_ptr<MinTimeSearch>& search, std::size_t i);
  // Assembles the answer of a finished search, caches it, forgets the flight, publishes it.
  void finish_min_time(MinTimeSearch& search);
  // Removes the flight `id` of `key` from `flights` (if it is still that one).
  void forget_flight(std::unordered_map<std::string, Flight>& flights, const std::string& key,
                     std::uint64_t id);
  Reply overloaded_reply() const;
  // `reply` after counting its plan (if any) in slosh_plans_total.
  Reply counted(Reply reply);
  // Solves `request` into `outcome` and caches it, unless another replica sharing the Redis is
  // solving the same key: then waits for its answer (RedisCache::lock_or_wait). Records the solve
  // time since `started`. The cache's entry of the answer when it is cached now (else null).
  // Throws what the solve throws.
  std::shared_ptr<const CachedValue> solve_once_across_replicas(
      const std::string& key, const api::PlanRequest& request, Outcome& outcome,
      std::chrono::steady_clock::time_point started);
  // A reservation of `bytes` of the export budget; throws ApiError kOverloaded (503 with
  // Retry-After) when the exports in flight leave too little.
  std::shared_ptr<const void> reserve_export(std::size_t bytes);
  // The plan store's failure (either table's), empty while it works.
  [[nodiscard]] std::string store_error() const;

  ServerConfig config_;
  Metrics metrics_;
  // The shared level of both caches (config cache = redis://...); null otherwise.
  std::shared_ptr<RedisClient> redis_;
  PlanCache cache_;
  // Min-time answers by request key: the same store file, its own table (min_times).
  PlanCache min_time_cache_;
  // The recipe key of each plan request text (without series) seen lately: a repeated request
  // skips parsing, validation and hashing. A request's key is a pure function of its text (model
  // names are resolved into the text before, the service's settings do not change), so an entry
  // is never stale. Emptied whole when it reaches kRequestKeys entries.
  static constexpr std::size_t kRequestKeys{4096};
  static constexpr std::size_t kRequestKeyTextBytes{4096};  // longer texts are not remembered
  std::mutex request_keys_mutex_;
  std::unordered_map<std::string, std::string> request_keys_;
  // Guards both maps and the counter; held only to look up, add or remove an entry.
  std::mutex inflight_mutex_;
  std::unordered_map<std::string, Flight> inflight_;
  std::unordered_map<std::string, Flight> min_time_inflight_;
  std::uint64_t flights_{0};
  std::atomic<std::uint64_t> cancelled_plans_{0};
  std::atomic<std::uint64_t> cancelled_min_times_{0};
  std::atomic<bool> ready_{true};
  // Memory of the cam exports in flight (config cam_export_bytes).
  ExportBudget export_budget_;
  WorkerPool pool_;  // last: destroyed first, finishing the solves that use the members above
};

}  // namespace slosh::service
