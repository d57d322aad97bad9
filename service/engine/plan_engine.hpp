#pragma once
// The engine of the service: solves plans and min-time searches on the worker pool with single
// flight (one solve per recipe, in this process and across the replicas sharing a Redis), answers
// them from the tiered caches, keeps the cam exports within their memory budget and says whether
// it is ready. It knows nothing of HTTP (no status codes, headers or entity tags): every answer
// is a typed result, every refusal an api::ApiError thrown or handed back. The HTTP handlers
// (plan_service.hpp) and the CLI (slosh batch, slosh export) both drive it.

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
#include <vector>

#include "cache/plan_cache.hpp"
#include "cache/rendered_plans.hpp"
#include "config/server_config.hpp"
#include "engine/worker_pool.hpp"
#include "export/cam_export.hpp"
#include "export/export_budget.hpp"
#include "http/plan_facts.hpp"
#include "metrics/metrics.hpp"
#include "metrics/metrics_registry.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/service_bodies.hpp"
#include "storage/redis_client.hpp"

namespace slosh::service {

/// What a solve or a min-time search produced: the stored body (an api::StoredPlan body, or a
/// stored min-time answer), or the error.
struct SolveOutcome {
  std::string body;
  std::optional<api::ApiError> error;
  /// The body was cut short (a time budget ran out, or the solve was stopped) or failed: it is not
  /// cached, and a later complete answer of the same key would be another body.
  bool partial{false};
};

/// Who waits for a running solve or search (one per flight): a flight that only clients wait for
/// (each of whom may hang up) is stopped when the last of them has gone; one that any batch item
/// waits for (pinned) runs to its end.
struct FlightWaiters {
  /// Read by the solve (PlanOptions::stop): set once nobody waits any more.
  std::atomic<bool> stop{false};
  int waiters{0};      ///< clients waiting (under the engine's flight lock)
  bool pinned{false};  ///< a waiter that cannot hang up joined (under the flight lock)
};

/// A min-time request on its way (PlanEngine::start_min_time): answered from the cache at once,
/// or the future of its search (a new one, or the running search of the same key it joined).
struct PendingMinTime {
  std::string key;
  /// The stored answer when it came from the cache (then `search` is invalid).
  std::optional<std::string> cached;
  /// The search's outcome otherwise; already ready with a 503 error when it could not be queued.
  std::shared_future<SolveOutcome> search;
  /// The waiters of the search this request waits for, when it was started `cancellable`.
  std::shared_ptr<FlightWaiters> waiters;
  /// The single-flight entry of that search (PlanEngine::flight_name of its key and budget).
  std::string flight;
};

/// One item of a batch: a rendered plan, or the error of the item (field paths relative to the
/// item's request).
struct BatchResult {
  std::string plan;                    ///< rendered plan JSON; empty when `error` is set
  std::optional<api::ApiError> error;  ///< set when the item failed
  bool cached{false};                  ///< the plan came from the cache
  [[nodiscard]] bool ok() const { return !error; }
  /// The pool refused the solve (kOverloaded). Batch items wait for room in the queue, so for
  /// them this is only ever the shutdown's refusal: not the recipe's result.
  [[nodiscard]] bool refused() const {
    return error && error->code() == api::ErrorCode::kOverloaded;
  }
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
  friend class PlanEngine;
  std::vector<BatchResult> results_;
  std::vector<std::shared_future<SolveOutcome>> pending_;  // invalid where results_ is final
  // For a batch whose client may hang up: each solving item's flight (its name and waiters), so
  // that the items still queued or running stop when the client has gone (PlanEngine::leave_batch).
  std::vector<std::string> flights_;
  std::vector<std::shared_ptr<FlightWaiters>> waiters_;
};

/// One batch item on its way (PlanEngine::start_batch_item): finished now (a cache hit, an
/// invalid request), or the future of its solve.
struct StartedItem {
  BatchResult result;                        ///< final when `pending` is invalid
  std::shared_future<SolveOutcome> pending;  ///< the solve (new, or the running one joined)
  /// The item's result once finished (waits for the solve).
  [[nodiscard]] BatchResult get() const;
};

/// What a plan request asks of a hit: the view and whether the client accepts gzip.
struct HitView {
  api::PlanView view{api::PlanView::kFull};
  bool gzip{false};
};

/// The plan a request is answered with (PlanEngine::answer_plan): a cache hit answered from the
/// cached plan's kept renderings, or a stored plan body (solved now, or a hit that adds series).
struct PlanAnswer {
  std::string key;                          ///< the recipe key
  bool cached{false};                       ///< from the cache (else solved for this request)
  std::shared_ptr<const CachedValue> hit;   ///< set for a hit without series
  std::string body;                         ///< the stored plan body when `hit` is null
  std::optional<api::PlanRequest> request;  ///< the parsed request when `hit` is null
  std::optional<double> sample_period;      ///< the series the request asks for [s]
  api::PlanView view{api::PlanView::kFull};
  /// Solved for this request and cut short (SolveOutcome::partial): its reply carries no ETag,
  /// since the key's tag names the complete plan a later request gets from the cache.
  bool partial{false};
};

/// A min-time request's answer (PlanEngine::answer_min_time): the stored answer of its key.
struct MinTimeAnswer {
  std::string key;
  std::string stored;
  bool cached{false};  ///< from the cache; false also for one that joined another's search
  /// Not cacheable (a search cut short by its budget or failed): its reply carries no ETag.
  bool partial{false};
};

/// The readiness of the engine (PlanEngine::readiness).
struct Readiness {
  api::ReadyReport report;
  /// False while stopping or stalled, or with Redis down and redis_required set.
  bool ready{true};
};

/// A cam table file of a cached plan and its reservation of the export budget (keep `hold` alive
/// until the file has been written).
struct CamExport {
  std::string file;
  std::shared_ptr<const void> hold;
};

class PlanEngine {
 public:
  explicit PlanEngine(const ServerConfig& config);
  /// Finishes queued and running solves.
  ~PlanEngine();
  PlanEngine(const PlanEngine&) = delete;
  PlanEngine& operator=(const PlanEngine&) = delete;

  /// The plan of the request text `text` in `view`: a cache hit, or a solve (joined when the same
  /// recipe is being solved). `gzip`: the client accepts the gzip coding (what a later hit in that
  /// coding answers is prepared on the worker). `abandoned` (optional) tells whether the client
  /// has gone away: its solve is stopped then, unless another request still waits for it. Throws
  /// api::ApiError: invalid request, overloaded, cancelled, timeout, or the solve's error.
  PlanAnswer answer_plan(const std::string& text, api::PlanView view, bool gzip = false,
                         const std::function<bool()>& abandoned = {});
  /// The cache hit of `key` in `view` (counted); nullopt when the plan is not cached.
  std::optional<PlanAnswer> cached_plan(const std::string& key, api::PlanView view);
  /// The body `answer` is answered with (gzip-coded when `gzip` and worth it, for a hit).
  HitBody plan_body(const PlanAnswer& answer, bool gzip);
  /// What `answer` says about its plan (for the access log and slosh_plans_total).
  PlanFacts plan_facts(const PlanAnswer& answer);
  /// Counts a plan served in slosh_plans_total.
  void count_plan(const PlanFacts& facts);

  /// Starts a batch of read plan requests (api::read_batch_items): cache hits and invalid items
  /// finish at once, the others are queued on the pool at background priority (waiting for queue
  /// room; interactive plans overtake them) with single-flight per recipe. `abandoned` (optional)
  /// tells whether the client has gone away: no further solves are queued for it then, and its
  /// items wait as clients that may hang up (call leave_batch when the client has gone).
  PendingBatch start_batch(const std::vector<api::BatchItem>& requests,
                           const std::function<bool()>& abandoned = {});
  /// The client of `batch` (started with `abandoned`) has gone: each item not finished stops
  /// waiting, so its solve is skipped (queued) or stopped (running) unless another request waits
  /// for it. Counted in cancelled_plans().
  void leave_batch(const PendingBatch& batch);
  /// Starts one batch item: a cache hit or an invalid request finishes at once; otherwise its
  /// solve is queued at `priority` (waiting for queue room), or joins a running solve of the same
  /// recipe. Never throws: errors are the item's.
  /// `waiter` (optional): the item's client may hang up; receives the flight's waiters and
  /// `flight` its name (see leave_batch). Without it the flight is pinned (runs to its end).
  StartedItem start_batch_item(const api::BatchItem& request,
                               TaskPriority priority = TaskPriority::kInteractive,
                               std::shared_ptr<FlightWaiters>* waiter = nullptr,
                               std::string* flight = nullptr);

  /// The answer of a validated min-time request (SPEC §9): each strategy's search is one task on
  /// the worker pool, within options.time_limit_s per search. Throws api::ApiError: overloaded
  /// when the queue has no room, timeout when the searches have not finished their budget plus
  /// queue_wait_s after, cancelled when the client (`abandoned`) has gone.
  MinTimeAnswer answer_min_time(const api::MinTimeRequest& request,
                                const std::function<bool()>& abandoned = {});
  /// Starts a validated min-time request: the cached answer, or the running search of the same
  /// key (single flight, when that search has the same budget), or a new search
  /// of one pool task per strategy (`wait_for_room`: wait for queue slots instead of refusing
  /// with 503). The last task to finish assembles, caches and publishes the answer, so nobody
  /// waits on a worker and no lock is held while searching or queueing.
  /// `cancellable`: the caller may hang up (PendingMinTime::waiters; call leave_min_time when it
  /// stops waiting); otherwise the search runs to its end whoever else leaves.
  PendingMinTime start_min_time(const api::MinTimeRequest& request, bool wait_for_room,
                                bool cancellable = false);
  /// The caller of a cancellable start_min_time stops waiting; `gone`: its client hung up, or
  /// (`timed_out`) it was answered 504 (the search stops when nobody else waits for it).
  void leave_min_time(const PendingMinTime& pending, bool gone, bool timed_out = false);

  /// The cam table file of the cached plan `key` with `options` (plan_cam_file), holding its
  /// reservation of the export budget. Throws api::ApiError: not found (field "key"), the
  /// options' errors, overloaded when the exports in flight leave too little of the budget.
  CamExport cam_export(const std::string& key, const CamOptions& options, bool allow_infeasible);

  /// Ready, degraded, stopping or stalled, with the pool's and caches' figures.
  [[nodiscard]] Readiness readiness() const;
  /// Writes the engine's counters and histograms (Metrics) with the pool's gauges.
  void collect_metrics(MetricsText& out) const;
  /// Writes the plan store's, the shared cache's and the export budget's gauges.
  void collect_store_metrics(MetricsText& out) const;
  /// Solves and searches stopped because every client waiting for them had gone.
  [[nodiscard]] std::uint64_t cancelled_plans() const { return cancelled_plans_; }
  [[nodiscard]] std::uint64_t cancelled_min_times() const { return cancelled_min_times_; }
  /// Solves and searches stopped because every request waiting for them had been answered 504
  /// (their budget plus queue_wait_s passed).
  [[nodiscard]] std::uint64_t timed_out_plans() const { return timed_out_plans_; }
  [[nodiscard]] std::uint64_t timed_out_min_times() const { return timed_out_min_times_; }

  /// No new solve is queued (queued ones are refused, running ones finish); readiness says so.
  void begin_shutdown();
  /// False once begin_shutdown has run.
  [[nodiscard]] bool accepting() const { return ready_; }
  /// The refusal of a solve: the queue is full, or the engine is shutting down.
  [[nodiscard]] api::ApiError overloaded_error() const;

  [[nodiscard]] const ServerConfig& config() const { return config_; }
  Metrics& metrics() { return metrics_; }
  /// The solve pool (its counters are reported by the batch jobs and tests; calibration fits run
  /// on it too).
  [[nodiscard]] const WorkerPool& pool() const { return pool_; }
  [[nodiscard]] WorkerPool& worker_pool() { return pool_; }
  /// Solve workers running (the configured count, or the cores for 0).
  [[nodiscard]] std::size_t workers() const { return pool_.workers(); }
  [[nodiscard]] const PlanCache& cache() const { return cache_; }
  [[nodiscard]] const PlanCache& min_time_cache() const { return min_time_cache_; }
  /// The client of the shared cache level; null without a Redis cache.
  [[nodiscard]] const std::shared_ptr<RedisClient>& redis() const { return redis_; }
  /// The cache levels in words for the start-up log, e.g. "memory + sqlite plans.sqlite + redis
  /// redis://10.0.0.5:6379/0" (a password is never shown).
  [[nodiscard]] std::string cache_description() const;

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
  struct MinTimeSearch;
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
  // The single-flight entry of `key` solved or searched within `budget` [s]: requests share a
  // solve only with the same budget. A smaller budget never waits for a larger one's solve (it
  // would wait past its own budget and be answered by another client's), and a larger one never
  // takes a smaller one's answer (a larger budget may find another).
  static std::string flight_name(const std::string& key, double budget);
  // Adds a new flight of `key` to inflight_ unless one with the same `budget` runs (then joins
  // it and returns its future). `refused` when the engine is shutting down.
  std::optional<std::shared_future<Outcome>> join_or_add_flight(
      const std::string& key, double budget, const std::shared_future<Outcome>& future,
      const std::shared_ptr<FlightWaiters>& waiters, std::shared_ptr<FlightWaiters>* waiter,
      std::uint64_t& flight, bool* refused);
  // The pool task of a solve: solves (or refuses), publishes, then prepares the hit's body.
  void run_solve(const std::string& key, const api::PlanRequest& request,
                 const std::shared_ptr<std::promise<Outcome>>& promise, std::uint64_t flight,
                 const std::shared_ptr<FlightWaiters>& waiters, HitView hit);
  // Waits for `future` of `key` on behalf of a client (`abandoned`); the outcome with its stored
  // body, or throws its error.
  Outcome wait_for_plan(const std::string& key, const api::PlanRequest& request,
                        const std::shared_future<Outcome>& future,
                        const std::shared_ptr<FlightWaiters>& waiters,
                        const std::function<bool()>& abandoned);
  // Joins `waiters` (under inflight_mutex_): counted when `cancellable`, else pinned.
  static void join_locked(FlightWaiters& waiters, bool cancellable);
  // A waiter of the flight `waiters` of `key` in `flights` stops waiting; when its client is
  // `gone` and nobody else waits (and no batch pinned it), the flight is stopped and forgotten
  // (a new request starts afresh). True when this stopped it.
  bool leave_flight(std::unordered_map<std::string, Flight>& flights, const std::string& key,
                    const std::shared_ptr<FlightWaiters>& waiters, bool gone);
  // Removes the flight `id` of `key` from `flights` (if it is still that one).
  void forget_flight(std::unordered_map<std::string, Flight>& flights, const std::string& key,
                     std::uint64_t id);
  // The recipe key remembered for the request text `text`; nullopt when not remembered.
  std::optional<std::string> remembered_key(const std::string& text);
  void remember_key(const std::string& text, const std::string& key);
  // The batch item `request` of a client that has gone: a cache hit, else cancelled.
  BatchResult abandoned_item(const api::BatchItem& request);
  // Joins a running search of `pending.key` with the same `budget`, or registers `search` as
  // the flight (unless shutting down: then search->flight stays 0). True when it joined.
  bool join_or_add_search(PendingMinTime& pending, const std::shared_ptr<MinTimeSearch>& search,
                          double budget, bool cancellable);
  // Queues one task per strategy of `search`; on a refusal publishes the 503 at once (the tasks
  // already queued then skip their strategy).
  void queue_min_time_tasks(const std::shared_ptr<MinTimeSearch>& search, bool wait_for_room);
  // Runs task `i` of `search` (its strategies, see MinTimeSearch::tasks); the last task to finish
  // calls finish_min_time.
  void run_min_time_task(const std::shared_ptr<MinTimeSearch>& search, std::size_t i);
  // The pool tasks of a search of `strategies` strategies: one each, at most workers + queue.
  [[nodiscard]] std::size_t min_time_tasks(std::size_t strategies) const;
  // Searches strategy `i` of `search` into its result slot.
  void run_min_time_strategy(MinTimeSearch& search, std::size_t i);
  // Assembles the answer of a finished search, caches it, forgets the flight, publishes it.
  void finish_min_time(MinTimeSearch& search);
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
  std::atomic<std::uint64_t> timed_out_plans_{0};
  std::atomic<std::uint64_t> timed_out_min_times_{0};
  std::atomic<bool> ready_{true};
  // Memory of the cam exports in flight (config cam_export_bytes).
  ExportBudget export_budget_;
  WorkerPool pool_;  // last: destroyed first, finishing the solves that use the members above
};

}  // namespace slosh::service
