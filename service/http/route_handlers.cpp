#include "http/route_handlers.hpp"

#include <stdexcept>
#include <string>

#include "export/cam_export.hpp"

namespace slosh::service {

namespace {

// `handle` of the body with options.model = "<name>" resolved to the stored calibration's model.
// A refusal of the resolution (an unknown name, the store unavailable: 503 with Retry-After) is
// thrown to the one wrapper every handler runs behind (respond's guarded_reply).
template <typename F>
Reply with_models(const Resources& r, const std::string& body, F&& handle) {
  return handle(r.calibrations.resolve_model_names(body));
}

// The plan routes (POST /v1/plans, the batch, GET /v1/plans/{key}), min-time and simulate; an
// empty handler for another operation.
Handler plan_handler_of(api::Operation operation, Resources& r) {
  switch (operation) {
    case api::Operation::kPlan:
      return [&r](const Call& c) {
        return with_models(r, c.body, [&](const std::string& resolved) {
          return r.service.post_plan(resolved, c.req.get_header_value("If-None-Match"),
                                     c.query.values("view"), c.gzip, r.client_gone(c.req));
        });
      };
    case api::Operation::kPlanBatch:
      return [&r](const Call& c) {
        // A client that hangs up gets no more solves queued.
        return r.service.post_batch(r.calibrations.resolve_batch_model_names(c.body),
                                    r.client_gone(c.req), c.query.values("view"));
      };
    case api::Operation::kMinTime:
      return [&r](const Call& c) {
        return with_models(r, c.body, [&](const std::string& resolved) {
          return r.service.post_min_time(resolved, c.req.get_header_value("If-None-Match"),
                                         r.client_gone(c.req));
        });
      };
    case api::Operation::kGetPlan:
      return [&r](const Call& c) {
        return r.service.get_plan(c.param(1), c.req.get_header_value("If-None-Match"),
                                  c.query.values("view"), c.gzip);
      };
    case api::Operation::kSimulate:
      return [&r](const Call& c) {
        return with_models(r, c.body, [&](const std::string& resolved) {
          return r.service.post_simulate(resolved);
        });
      };
    default:
      return {};
  }
}

// GET /v1/plans/{key}/cam.csv and cam.st.
Handler cam_handler_of(api::Operation operation, Resources& r) {
  const CamFileFormat format =
      operation == api::Operation::kCamTableSt ? CamFileFormat::kSt : CamFileFormat::kCsv;
  return [&r, format](const Call& c) {
    const Query& q = c.query;
    const CamQuery query{q.values("period_ms"),       q.values("master_period"),
                         q.values("master_start"),    q.values("master_end"),
                         q.values("master_step"),     q.values("st_name"),
                         q.values("allow_infeasible")};
    return r.service.cam_table(c.param(1), format, query);
  };
}

// The operations endpoints, the self-description and the web page; empty for another operation.
Handler ops_handler_of(api::Operation operation, Resources& r) {
  PlanService& service = r.service;
  switch (operation) {
    case api::Operation::kFluids:
      return [&service](const Call&) { return service.fluids(); };
    case api::Operation::kOpenapi:
      return [&service](const Call&) { return service.openapi(); };
    case api::Operation::kHealth:
      return [&service](const Call&) { return service.health(); };
    case api::Operation::kReady:
      return
          [&service, &jobs = r.jobs](const Call&) { return service.ready(jobs.store_warning()); };
    case api::Operation::kMetrics:
      return [&service](const Call&) { return service.metrics_text(); };
    case api::Operation::kPage:
      return [&service](const Call& c) {
        return service.web_asset("", c.req.get_header_value("If-None-Match"), c.gzip);
      };
    case api::Operation::kAsset:
      return [&service](const Call& c) {
        return service.web_asset(c.param(1), c.req.get_header_value("If-None-Match"), c.gzip);
      };
    default:
      return {};
  }
}

// The batch job routes (POST /v1/batches, GET and DELETE /v1/batches/{id}, the downloads) and the
// calibrations.
Handler job_handler_of(api::Operation operation, Resources& r) {
  BatchJobs& jobs = r.jobs;
  switch (operation) {
    case api::Operation::kCreateJob:
      return [&jobs](const Call& c) { return jobs.post(c.body); };
    case api::Operation::kGetJob:
      return [&jobs](const Call& c) {
        return jobs.get(c.param(1),
                        JobPageQuery{c.query.values("offset"), c.query.values("limit")});
      };
    case api::Operation::kCancelJob:
      return [&jobs](const Call& c) { return jobs.cancel(c.param(1)); };
    case api::Operation::kJobResultsCsv:
    case api::Operation::kJobResultsJsonl: {
      const TableFormat format =
          operation == api::Operation::kJobResultsCsv ? TableFormat::kCsv : TableFormat::kJsonLines;
      return [&jobs, format](const Call& c) {
        return jobs.results(c.param(1), format, c.query.values("partial"));
      };
    }
    case api::Operation::kCreateCalibration:
      return [&r](const Call& c) {
        return r.calibrations.post_calibration(c.body, r.client_gone(c.req));
      };
    case api::Operation::kGetCalibration:
      return [&r](const Call& c) { return r.calibrations.get_calibration(c.param(1)); };
    default:
      return {};
  }
}

}  // namespace

Handler handler_of(api::Operation operation, Resources& resources) {
  if (operation == api::Operation::kCamTable || operation == api::Operation::kCamTableSt) {
    return cam_handler_of(operation, resources);
  }
  for (const auto of : {plan_handler_of, ops_handler_of, job_handler_of}) {
    if (Handler handler = of(operation, resources)) return handler;
  }
  throw std::logic_error("an operation without a handler");
}

}  // namespace slosh::service
