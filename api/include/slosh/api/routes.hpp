#pragma once
// Every HTTP route of the service, listed once: the server registers its handlers from this list
// and the OpenAPI document's `paths` iterate it.

#include <span>
#include <string_view>

namespace slosh::api {

/// What a route does (one per route).
enum class Operation {
  kPlan,
  kPlanBatch,
  kMinTime,
  kGetPlan,
  kSimulate,
  kFluids,
  kOpenapi,
  kHealth,
  kReady,
  kMetrics,
  kCamTable,
  kCamTableSt,
  kPage,
  kAsset,
  kCreateJob,
  kGetJob,
  kCancelJob,
  kJobResultsCsv,
  kJobResultsJsonl,
  kCreateCalibration,
  kGetCalibration
};

struct Route {
  std::string_view method;  // "GET", "POST" or "DELETE"
  std::string_view path;    // OpenAPI path, e.g. "/v1/plans/{key}"
  Operation operation;
  std::string_view operation_id;  // OpenAPI operationId
  std::string_view summary;       // one line
};

/// Every route of the service, in the order the OpenAPI document lists them.
[[nodiscard]] std::span<const Route> routes();

}  // namespace slosh::api
