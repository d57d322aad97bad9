#include "slosh/api/routes.hpp"

#include <array>

namespace slosh::api {

namespace {

constexpr std::array kRoutes{
    Route{"POST", "/v1/plans", Operation::kPlan, "createPlan",
          "Plan one format (idempotent: identical recipes share one key and cache entry)"},
    Route{"POST", "/v1/plans/batch", Operation::kPlanBatch, "createPlans",
          "Plan many formats in parallel (recipe-table precompute)"},
    Route{"GET", "/v1/plans/{key}", Operation::kGetPlan, "getPlan",
          "A cached plan by its recipe key"},
    Route{"POST", "/v1/min-time", Operation::kMinTime, "minTime",
          "Minimum motion time of a format per strategy (SPEC §9)"},
    Route{"POST", "/v1/simulate", Operation::kSimulate, "simulate",
          "Wave-height response and peaks of any supported law"},
    Route{"POST", "/v1/calibrations", Operation::kCreateCalibration, "createCalibration",
          "Fit the model to measured moves (and store the result under its name)"},
    Route{"GET", "/v1/calibrations/{name}", Operation::kGetCalibration, "getCalibration",
          "A stored calibration by name"},
    Route{"GET", "/v1/fluids", Operation::kFluids, "listFluids", "The fluid catalogue"},
    Route{"GET", "/v1/openapi.json", Operation::kOpenapi, "openapi", "This document"},
    Route{"GET", "/healthz", Operation::kHealth, "health", "Liveness"},
    Route{"GET", "/readyz", Operation::kReady, "ready", "Readiness: accepts new solves"},
    Route{"GET", "/metrics", Operation::kMetrics, "metrics", "Prometheus metrics"},
    Route{"GET", "/v1/plans/{key}/cam.csv", Operation::kCamTable, "getCamTable",
          "Cam table CSV of a cached plan, time-based at a controller period or on a master axis "
          "(what `slosh export` writes)"},
    Route{"GET", "/v1/plans/{key}/cam.st", Operation::kCamTableSt, "getCamTableSt",
          "Cam table of a cached plan as IEC 61131-3 structured text (what `slosh export --format "
          "st` writes)"},
    Route{"POST", "/v1/batches", Operation::kCreateJob, "createBatchJob",
          "Start a batch job of up to batch_job_max recipes (202 at once; SPEC §13)"},
    Route{"GET", "/v1/batches/{id}", Operation::kGetJob, "getBatchJob",
          "A batch job's state and progress, and a page of its results once finished"},
    Route{"DELETE", "/v1/batches/{id}", Operation::kCancelJob, "cancelBatchJob",
          "Cancel a queued or running batch job, or forget a finished one"},
    Route{"GET", "/v1/batches/{id}/results.csv", Operation::kJobResultsCsv, "getBatchJobCsv",
          "A finished batch job's rows as the CSV plan table `slosh batch` writes"},
    Route{"GET", "/v1/batches/{id}/results.jsonl", Operation::kJobResultsJsonl, "getBatchJobJsonl",
          "A finished batch job's rows as the JSON lines `slosh batch` writes"},
    Route{"GET", "/", Operation::kPage, "page", "The web page: plan a format and see the plan"},
    Route{"GET", "/assets/{name}", Operation::kAsset, "asset",
          "Scripts and styles of the web page (embedded in the binary)"},
};

}  // namespace

std::span<const Route> routes() {
  return kRoutes;
}

}  // namespace slosh::api
