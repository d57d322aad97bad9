#include "slosh/api/routes.hpp"

#include <array>

namespace slosh::api {

namespace {

constexpr std::array<Route, 9> kRoutes{{
    {"POST", "/v1/plans", Operation::kPlan, "createPlan",
     "Plan one format (idempotent: identical recipes share one key and cache entry)"},
    {"GET", "/v1/plans/{key}", Operation::kGetPlan, "getPlan", "A cached plan by its recipe key"},
    {"POST", "/v1/plans/batch", Operation::kPlanBatch, "createPlans",
     "Plan many formats in parallel (recipe-table precompute)"},
    {"POST", "/v1/simulate", Operation::kSimulate, "simulate",
     "Wave-height response and peaks of any supported law"},
    {"GET", "/v1/fluids", Operation::kFluids, "listFluids", "The fluid catalogue"},
    {"GET", "/v1/openapi.json", Operation::kOpenapi, "openapi", "This document"},
    {"GET", "/healthz", Operation::kHealth, "health", "Liveness"},
    {"GET", "/readyz", Operation::kReady, "ready", "Readiness: accepts new solves"},
    {"GET", "/metrics", Operation::kMetrics, "metrics", "Prometheus metrics"},
}};

}  // namespace

std::span<const Route> routes() {
  return kRoutes;
}

}  // namespace slosh::api
