#include "cli_commands.hpp"

#include <exception>
#include <iostream>

#include "io.hpp"
#include "slosh/api/calibration_json.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::service {

namespace {

template <typename Body>
int print_json_or_error(Body&& body) {
  try {
    std::cout << api::dump_json(body(), 2) << '\n';
    return kExitOk;
  } catch (const api::ApiError& e) {
    std::cerr << api::dump_json(api::error_envelope(e), 2) << '\n';
    return e.status() < 500 ? kExitInvalidInput : kExitFailure;
  } catch (const std::exception& e) {
    const api::ApiError wrapped(api::ErrorCode::kInternal, "", e.what());
    std::cerr << api::dump_json(api::error_envelope(wrapped), 2) << '\n';
    return kExitFailure;
  }
}

nlohmann::json read_request(const std::string& request_path) {
  std::string text;
  try {
    text = read_request_text(request_path);
  } catch (const std::exception& e) {
    throw api::ApiError(api::ErrorCode::kInvalidValue, "--request", e.what());
  }
  return api::parse_json_body(text);
}

}  // namespace

int run_simulate_command(const std::string& request_path) {
  return print_json_or_error(
      [&] { return api::run_simulate(api::parse_simulate_request(read_request(request_path))); });
}

int run_calibrate_command(const std::string& request_path) {
  return print_json_or_error([&] {
    return api::run_calibration(api::parse_calibration_request(read_request(request_path)));
  });
}

int run_plan_command(const std::string& request_path, const std::optional<std::string>& view) {
  return print_json_or_error([&] {
    const api::PlanView v = view ? api::parse_plan_view(*view) : api::PlanView::kFull;
    const api::PlanRequest request = api::parse_plan_request(read_request(request_path));
    api::require_no_series(v, request.sample_period);
    const nlohmann::json plan = api::run_plan(request);
    return v == api::PlanView::kCompact ? api::compact_plan(plan) : plan;
  });
}

int run_min_time_command(const std::string& request_path) {
  return print_json_or_error([&] {
    // No server budget here: options.time_limit_s (per strategy) may be up to its 600 s maximum,
    // which is also its default (the searches end long before).
    return api::run_min_time(
        api::parse_min_time_request(read_request(request_path), api::plan_ranges::kTimeLimit.hi));
  });
}

}  // namespace slosh::service
