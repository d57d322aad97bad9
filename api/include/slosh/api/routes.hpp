#pragma once
// Every HTTP route of the service, listed once: the server registers its handlers from this list
// and the OpenAPI document's `paths` iterate it.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

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

/// The query parameters `operation` accepts, in the order its OpenAPI parameters list them
/// (empty: none); nullopt for the page, whose query string is the page's own state (?r=48.5&...)
/// and is read by its script, not by the service.
[[nodiscard]] std::optional<std::span<const std::string_view>> query_parameters(
    Operation operation);

/// The one rule for query strings, as for JSON bodies (whose unknown members are refused): throws
/// ApiError(kInvalidValue) with the field `name` for the first of `names` (the decoded names of
/// the request's query parameters, in order) that `route` does not accept: "periodms is not a
/// query parameter of GET /v1/plans/{key}/cam.csv; allowed here: period_ms, master_period, ..."
/// ("...; this route takes no query parameters" for a route without any).
void check_query_names(const Route& route, const std::vector<std::string>& names);

/// A path whose segments are routed as sent: a '/' sent encoded (%2F) inside a segment is part of
/// that segment, never a separator, and no key, id or name holds one. Throws
/// ApiError(kNotFound) when `raw_path` (the request target before '?', not decoded) holds %2F:
/// naming the route's parameter when the path has the shape of a route ("key "abc/cam.csv" holds
/// a '/' (sent as %2F) and no key of GET /v1/plans/{key} does"), else "no endpoint <method>
/// <path>: ...". Returns quietly for any other path.
void check_encoded_slashes(std::string_view method, std::string_view raw_path);

}  // namespace slosh::api
