#include "slosh/api/routes.hpp"

#include <algorithm>
#include <array>
#include <cctype>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"

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

constexpr std::array<std::string_view, 1> kViewQuery{"view"};
constexpr std::array<std::string_view, 6> kCamCsvQuery{
    "period_ms", "master_period", "master_start", "master_end", "master_step", "allow_infeasible"};
constexpr std::array<std::string_view, 7> kCamStQuery{
    "period_ms",   "master_period",    "master_start", "master_end",
    "master_step", "allow_infeasible", "st_name"};
constexpr std::array<std::string_view, 2> kJobPageQuery{"offset", "limit"};
constexpr std::array<std::string_view, 1> kJobResultsQuery{"partial"};

/// The path segments of `path` ("/v1/plans/x" -> "", "v1", "plans", "x").
std::vector<std::string_view> segments(std::string_view path) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (std::size_t slash; (slash = path.find('/', start)) != std::string_view::npos;
       start = slash + 1) {
    out.push_back(path.substr(start, slash - start));
  }
  out.push_back(path.substr(start));
  return out;
}

/// `text` with every %XX decoded (an incomplete escape stays as sent).
std::string percent_decoded(std::string_view text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() &&
        std::isxdigit(static_cast<unsigned char>(text[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(text[i + 2]))) {
      out += static_cast<char>(std::stoi(std::string(text.substr(i + 1, 2)), nullptr, 16));
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

bool has_encoded_slash(std::string_view text) {
  for (std::size_t i = 0; i + 2 < text.size(); ++i) {
    if (text[i] == '%' && text[i + 1] == '2' && (text[i + 2] == 'F' || text[i + 2] == 'f')) {
      return true;
    }
  }
  return false;
}

}  // namespace

std::span<const Route> routes() {
  return kRoutes;
}

std::optional<std::span<const std::string_view>> query_parameters(Operation operation) {
  switch (operation) {
    case Operation::kPlan:
    case Operation::kPlanBatch:
    case Operation::kGetPlan:
      return kViewQuery;
    case Operation::kCamTable:
      return kCamCsvQuery;
    case Operation::kCamTableSt:
      return kCamStQuery;
    case Operation::kGetJob:
      return kJobPageQuery;
    case Operation::kJobResultsCsv:
    case Operation::kJobResultsJsonl:
      return kJobResultsQuery;
    case Operation::kPage:
      return std::nullopt;
    default:
      return std::span<const std::string_view>();
  }
}

void check_query_names(const Route& route, const std::vector<std::string>& names) {
  const auto accepted = query_parameters(route.operation);
  if (!accepted) return;
  for (const std::string& name : names) {
    if (std::find(accepted->begin(), accepted->end(), name) != accepted->end()) continue;
    std::string list;
    for (std::string_view a : *accepted) list += (list.empty() ? "" : ", ") + std::string(a);
    // The name as received may be anything: quoted (and cut) when it is not a plain word.
    const bool plain =
        !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
          return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
        });
    const std::string shown = plain ? name : show(nlohmann::json(name));
    // A parameter of another route (st_name of cam.st on cam.csv, view on a job): which one.
    std::string elsewhere;
    for (const Route& other : kRoutes) {
      const auto takes = query_parameters(other.operation);
      if (&other == &route || !takes ||
          std::find(takes->begin(), takes->end(), name) == takes->end()) {
        continue;
      }
      elsewhere = " (" + std::string(other.method) + " " + std::string(other.path) + " takes it)";
      break;
    }
    invalid(
        name.substr(0, 64),
        shown + " is not a query parameter of " + std::string(route.method) + " " +
            std::string(route.path) + elsewhere +
            (list.empty() ? "; this route takes no query parameters" : "; allowed here: " + list));
  }
}

}  // namespace slosh::api

namespace slosh::api {

void check_encoded_slashes(std::string_view method, std::string_view raw_path) {
  if (!has_encoded_slash(raw_path)) return;
  const std::vector<std::string_view> sent = segments(raw_path);
  const std::string_view routed = method == "HEAD" ? std::string_view("GET") : method;
  // The routes of the request's method first: GET and DELETE /v1/batches/{id} share a shape.
  std::vector<const Route*> order;
  for (const Route& route : kRoutes) {
    if (route.method == routed) order.push_back(&route);
  }
  for (const Route& route : kRoutes) {
    if (route.method != routed) order.push_back(&route);
  }
  for (const Route* r : order) {
    const Route& route = *r;
    const std::vector<std::string_view> shape = segments(route.path);
    if (shape.size() != sent.size()) continue;
    std::optional<std::size_t> slashed;
    bool fits = true;
    for (std::size_t i = 0; i < shape.size() && fits; ++i) {
      if (shape[i].starts_with('{')) {
        if (has_encoded_slash(sent[i])) slashed = i;
      } else {
        fits = percent_decoded(sent[i]) == shape[i];
      }
    }
    if (!fits || !slashed) continue;
    const std::string name(shape[*slashed].substr(1, shape[*slashed].size() - 2));
    throw ApiError(ErrorCode::kNotFound, name,
                   name + " " + show(nlohmann::json(percent_decoded(sent[*slashed]))) +
                       " holds a '/' (sent as %2F) and no " + name + " of " +
                       std::string(route.method) + " " + std::string(route.path) + " does");
  }
  throw ApiError(ErrorCode::kNotFound, "",
                 "no endpoint " + std::string(method.substr(0, 16)) + " " +
                     std::string(raw_path.substr(0, 80)) +
                     ": a '/' sent as %2F is part of a path segment; see /v1/openapi.json");
}

}  // namespace slosh::api
