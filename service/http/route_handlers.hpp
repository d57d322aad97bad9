#pragma once
// The handler of every operation of the route table (api::routes()): what each route asks of the
// resource handlers (PlanService, BatchJobs, CalibrationService), read from the request's body,
// path parameters, query and headers. http_server.cpp registers them through the route table.

#include <httplib.h>

#include <functional>
#include <string>

#include "calibration/calibration_service.hpp"
#include "http/http_query.hpp"
#include "http/http_reply.hpp"
#include "http/plan_service.hpp"
#include "jobs/batch_jobs.hpp"
#include "slosh/api/routes.hpp"

namespace slosh::service {

/// One request as a handler sees it: the library's request, the body (empty but for POST), the
/// parsed query and whether the client accepts the gzip coding.
struct Call {
  const httplib::Request& req;
  const std::string& body;
  const Query& query;
  bool gzip{false};
  /// The path parameter `i` (1-based) of the route's template.
  [[nodiscard]] std::string param(std::size_t i) const { return req.matches[i]; }
};

/// The handler of one operation.
using Handler = std::function<Reply(const Call&)>;

/// What the handlers answer with.
struct Resources {
  PlanService& service;
  BatchJobs& jobs;
  CalibrationService& calibrations;
  /// Whether the client of a request has hung up (work nobody waits for is stopped).
  std::function<std::function<bool()>(const httplib::Request&)> client_gone;
};

/// The handler of `operation`; `resources` must outlive it.
[[nodiscard]] Handler handler_of(api::Operation operation, Resources& resources);

}  // namespace slosh::service
