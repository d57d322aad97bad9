#pragma once
// The HTTP handlers of the service's resources, without the HTTP library: each parses what the
// request carries (body, query values, If-None-Match), asks the engine (plan_engine.hpp) and adds
// the HTTP parts of the answer (status, ETag and 304, X-Cache, Retry-After, content types). Every
// handler returns a Reply and never throws (errors become the JSON envelope). The handlers live
// in one file per resource: plan_handlers.cpp (plans, cam tables, simulate), min_time_handlers.cpp,
// batch_handlers.cpp, ops_handlers.cpp (health, ready, metrics, fluids, OpenAPI) and
// web_handlers.cpp (the page's files).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "config/server_config.hpp"
#include "engine/plan_engine.hpp"
#include "export/cam_export.hpp"
#include "http/http_reply.hpp"
#include "metrics/metrics_registry.hpp"

namespace slosh::service {

class PlanService {
 public:
  explicit PlanService(const ServerConfig& config);
  /// Finishes queued and running solves.
  ~PlanService();
  PlanService(const PlanService&) = delete;
  PlanService& operator=(const PlanService&) = delete;

  /// POST /v1/plans. `view`: the values of the request's `view` query parameter
  /// (api::parse_view_query; none = the full plan). The view changes neither the key nor the
  /// cache entry, only the reply. `gzip`: the client accepts the gzip coding; a cache hit then
  /// answers the plan's stored gzip bytes (Reply::content_encoding), compressed once when the
  /// plan was rendered. `abandoned` (optional) tells whether the client has gone away: its solve
  /// is stopped then, unless another request still waits for it.
  Reply post_plan(const std::string& body, const std::string& if_none_match,
                  const std::vector<std::string>& view = {}, bool gzip = false,
                  const std::function<bool()>& abandoned = {});
  /// GET /v1/plans/{key}: the cached plan (404 when it is not cached).
  Reply get_plan(const std::string& key, const std::string& if_none_match,
                 const std::vector<std::string>& view = {}, bool gzip = false);
  /// POST /v1/plans/batch. `abandoned` (optional) tells whether the client has gone away: no
  /// further solves are queued for it then. `view`: the query's view values (api::batch_view,
  /// with the body's "view").
  Reply post_batch(const std::string& body, const std::function<bool()>& abandoned = {},
                   const std::vector<std::string>& view = {});
  /// POST /v1/simulate.
  Reply post_simulate(const std::string& body);
  /// POST /v1/min-time (SPEC §9, PlanEngine::answer_min_time): 503 when the queue has no room
  /// for the strategies' searches, 504 when they have not finished their budget plus
  /// queue_wait_s after. Answers are cached per request key; identical concurrent requests share
  /// one search, and those that waited for another's search answer as it did (cached: false).
  /// `abandoned` (optional): as for post_plan, the search stops when its last client has gone.
  Reply post_min_time(const std::string& body, const std::string& if_none_match,
                      const std::function<bool()>& abandoned = {});
  /// GET /v1/fluids.
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
  /// GET /readyz: 200 while ready or degraded, 503 otherwise. `job_store_warning`: why batch
  /// jobs' rows are held on this replica only (BatchJobs::store_warning()); non-empty, it makes
  /// a ready replica degraded and is shown as jobs.store_warning.
  Reply ready(const std::string& job_store_warning = {}) const;
  /// GET /metrics: every collector of metrics_registry() in order.
  Reply metrics_text() const;
  /// Where the other parts of the server add what /metrics reports (batch jobs, cancellations).
  MetricsRegistry& metrics_registry() { return registry_; }

  /// The engine the handlers drive.
  PlanEngine& engine() { return engine_; }
  [[nodiscard]] const PlanEngine& engine() const { return engine_; }

  // The engine's parts, for the batch jobs and the tests.
  StartedItem start_batch_item(const api::BatchItem& request,
                               TaskPriority priority = TaskPriority::kInteractive) {
    return engine_.start_batch_item(request, priority);
  }
  PendingBatch start_batch(const std::vector<api::BatchItem>& requests,
                           const std::function<bool()>& abandoned = {}) {
    return engine_.start_batch(requests, abandoned);
  }
  PendingMinTime start_min_time(const api::MinTimeRequest& request, bool wait_for_room,
                                bool cancellable = false) {
    return engine_.start_min_time(request, wait_for_room, cancellable);
  }
  void leave_min_time(const PendingMinTime& pending, bool gone, bool timed_out = false) {
    engine_.leave_min_time(pending, gone, timed_out);
  }
  [[nodiscard]] const WorkerPool& pool() const { return engine_.pool(); }
  [[nodiscard]] WorkerPool& worker_pool() { return engine_.worker_pool(); }
  [[nodiscard]] const ServerConfig& config() const { return engine_.config(); }
  [[nodiscard]] bool accepting() const { return engine_.accepting(); }
  [[nodiscard]] std::uint64_t cancelled_plans() const { return engine_.cancelled_plans(); }
  [[nodiscard]] std::uint64_t cancelled_min_times() const { return engine_.cancelled_min_times(); }
  [[nodiscard]] std::uint64_t timed_out_plans() const { return engine_.timed_out_plans(); }
  [[nodiscard]] std::uint64_t timed_out_min_times() const { return engine_.timed_out_min_times(); }
  void begin_shutdown() { engine_.begin_shutdown(); }
  Metrics& metrics() { return engine_.metrics(); }
  [[nodiscard]] std::size_t workers() const { return engine_.workers(); }
  [[nodiscard]] const PlanCache& cache() const { return engine_.cache(); }
  [[nodiscard]] const PlanCache& min_time_cache() const { return engine_.min_time_cache(); }
  [[nodiscard]] const std::shared_ptr<RedisClient>& redis() const { return engine_.redis(); }
  [[nodiscard]] std::string cache_description() const { return engine_.cache_description(); }

  /// The envelope reply of an error status with a message (and optional field).
  static Reply error_reply(api::ErrorCode code, const std::string& message,
                           const std::string& field = "") {
    return service::error_reply(code, message, field);
  }

 private:
  // The reply of a plan answer: ETag and X-Cache, 304 for a cached plan whose ETag
  // `if_none_match` names, else the body (gzip-coded for a hit when `gzip`); counted in
  // slosh_plans_total.
  Reply plan_reply(const PlanAnswer& answer, const std::string& if_none_match, bool gzip);

  PlanEngine engine_;
  MetricsRegistry registry_;
};

}  // namespace slosh::service
