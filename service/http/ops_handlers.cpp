// The handlers of the operations endpoints (GET /healthz, /readyz, /metrics) and of the
// service's self-description (GET /v1/fluids, /v1/openapi.json); the handlers' construction.

#include "config/version.hpp"
#include "http/plan_service.hpp"
#include "metrics/process_metrics.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/openapi.hpp"
#include "slosh/api/service_bodies.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::service {

PlanService::PlanService(const ServerConfig& config) : engine_(config) {
  // The order of the families on /metrics: the engine's counters, the process, the engine's
  // gauges; the server adds the batch jobs' and the cancellations' after these.
  registry_.add([this](MetricsText& out) { engine_.collect_metrics(out); });
  registry_.add([](MetricsText& out) { collect_process_metrics(out, read_process_stats()); });
  registry_.add([this](MetricsText& out) { engine_.collect_store_metrics(out); });
}

PlanService::~PlanService() = default;

Reply PlanService::fluids() const {
  Reply r;
  r.body = api::dump_json(api::fluids_json());
  return r;
}

Reply PlanService::openapi() const {
  // The document depends on nothing but this build: rendered once, at the first request.
  static const std::string document = api::dump_json(api::openapi_document(kVersion));
  Reply r;
  r.body = document;
  return r;
}

Reply PlanService::health() const {
  Reply r;
  r.body = api::health_body(kVersion);
  return r;
}

Reply PlanService::ready(const std::string& job_store_warning) const {
  Readiness readiness = engine_.readiness();
  api::ReadyReport& report = readiness.report;
  if (!job_store_warning.empty()) {
    // Still serving (the owner holds the rows and serves them), but other replicas cannot.
    report.job_store_warning = job_store_warning;
    if (report.status == "ready") report.status = "degraded";
    report.reason =
        report.reason.empty() ? job_store_warning : report.reason + "; " + job_store_warning;
  }
  Reply r;
  r.status = readiness.ready ? 200 : 503;
  r.body = api::ready_body(report);
  return r;
}

Reply PlanService::metrics_text() const {
  Reply r;
  r.content_type = "text/plain; version=0.0.4";
  r.body = registry_.render();
  return r;
}

}  // namespace slosh::service
