#include "cli/cli_commands.hpp"

#include <exception>
#include <iostream>

#include "cli/io.hpp"
#include "slosh/api/calibration_json.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_summary.hpp"
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

std::vector<std::string> QuickPlanFlags::given() const {
  std::vector<std::string> out;
  auto note = [&](bool set, const char* flag) {
    if (set) out.emplace_back(flag);
  };
  note(radius_mm.has_value(), "--radius");
  note(fill_mm.has_value(), "--fill");
  note(height_mm.has_value(), "--height");
  note(fluid.has_value(), "--fluid");
  note(density_kg_m3.has_value(), "--density");
  note(viscosity_pa_s.has_value(), "--viscosity");
  note(stroke_mm.has_value(), "--stroke");
  note(time_s.has_value(), "--time");
  note(strategy.has_value(), "--strategy");
  return out;
}

namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& i : items) out += (out.empty() ? "" : ", ") + i;
  return out;
}

/// Why the flags cannot make a request (conflicts, missing flags), or "" when they can.
std::string quick_flags_problem(const PlanCommandOptions& o) {
  const QuickPlanFlags& q = o.quick;
  const std::vector<std::string> given = q.given();
  if (o.request_given && !given.empty()) {
    return "--request cannot be combined with the format flags (" + joined(given) +
           "): give the format either as a request file or as flags";
  }
  if (given.empty()) return "";
  if (q.fluid && (q.density_kg_m3 || q.viscosity_pa_s)) {
    return "--fluid cannot be combined with --density/--viscosity: name a catalogue fluid "
           "(slosh fluids) or give a custom one";
  }
  std::vector<std::string> missing;
  if (!q.radius_mm) missing.emplace_back("--radius");
  if (!q.fill_mm) missing.emplace_back("--fill");
  if (!q.fluid && !q.density_kg_m3)
    missing.emplace_back(q.viscosity_pa_s ? "--density" : "--fluid");
  if (!q.fluid && q.density_kg_m3 && !q.viscosity_pa_s) missing.emplace_back("--viscosity");
  if (!q.stroke_mm) missing.emplace_back("--stroke");
  if (!q.time_s) missing.emplace_back("--time");
  if (!missing.empty()) {
    return "the format flags need --radius, --fill, --fluid (or --density and --viscosity), "
           "--stroke and --time: missing " +
           joined(missing);
  }
  return "";
}

/// The plan request the quick flags stand for (the values are validated by the request parser).
nlohmann::json quick_request(const QuickPlanFlags& q) {
  nlohmann::json container{{"radius_mm", *q.radius_mm}};
  if (q.height_mm) container["height_mm"] = *q.height_mm;
  nlohmann::json fluid = q.fluid ? nlohmann::json(*q.fluid)
                                 : nlohmann::json{{"density_kg_m3", *q.density_kg_m3},
                                                  {"viscosity_pa_s", *q.viscosity_pa_s}};
  return {{"format",
           {{"container", container},
            {"fill_height_mm", *q.fill_mm},
            {"fluid", fluid},
            {"stroke_mm", *q.stroke_mm},
            {"motion_time_s", *q.time_s}}},
          {"strategy", q.strategy.value_or("auto")}};
}

/// The flag a request field came from ("" when none).
std::string flag_of(const std::string& field) {
  static const std::pair<const char*, const char*> flags[] = {
      {"format.container.radius_mm", "--radius"},
      {"format.container.height_mm", "--height"},
      {"format.fill_height_mm", "--fill"},
      {"format.fluid.density_kg_m3", "--density"},
      {"format.fluid.viscosity_pa_s", "--viscosity"},
      {"format.fluid", "--fluid"},
      {"format.stroke_mm", "--stroke"},
      {"format.motion_time_s", "--time"},
      {"strategy", "--strategy"}};
  for (const auto& [path, flag] : flags) {
    if (field == path) return flag;
  }
  return "";
}

int plan_as_text(const nlohmann::json& request, bool from_flags) {
  try {
    std::cout << api::plan_summary_text(api::run_plan(api::parse_plan_request(request)));
    return kExitOk;
  } catch (const api::ApiError& e) {
    const std::string flag = from_flags ? flag_of(e.field()) : "";
    std::cerr << "slosh plan: " << e.what()
              << (flag.empty() ? (e.field().empty() ? "" : " (field " + e.field() + ")")
                               : " (flag " + flag + ")")
              << '\n';
    return e.status() < 500 ? kExitInvalidInput : kExitFailure;
  } catch (const std::exception& e) {
    std::cerr << "slosh plan: internal error: " << e.what() << '\n';
    return kExitFailure;
  }
}

}  // namespace

int run_plan_command(const PlanCommandOptions& o) {
  if (const std::string problem = quick_flags_problem(o); !problem.empty()) {
    std::cerr << "slosh plan: " << problem << '\n';
    return kExitInvalidInput;
  }
  const bool from_flags = !o.quick.given().empty();
  const std::string format = o.format.value_or(from_flags ? "text" : "json");
  if (format == "text" && o.view) {
    std::cerr << "slosh plan: --view applies to the JSON output: add --format json\n";
    return kExitInvalidInput;
  }
  if (format == "text") {
    nlohmann::json request;
    try {
      request = from_flags ? quick_request(o.quick) : read_request(o.request_path);
    } catch (const api::ApiError& e) {
      std::cerr << "slosh plan: " << e.what() << '\n';
      return kExitInvalidInput;
    }
    return plan_as_text(request, from_flags);
  }
  return print_json_or_error([&] {
    const api::PlanView v = o.view ? api::parse_plan_view(*o.view) : api::PlanView::kFull;
    const api::PlanRequest request =
        api::parse_plan_request(from_flags ? quick_request(o.quick) : read_request(o.request_path));
    api::require_no_series(v, request.sample_period);
    const nlohmann::json plan = api::run_plan(request);
    return v == api::PlanView::kCompact ? api::compact_plan(plan) : plan;
  });
}

int run_fluids_command(const std::string& format) {
  const nlohmann::json fluids = api::fluids_json();
  if (format == "json") {
    std::cout << api::dump_json(fluids, 2) << '\n';
  } else {
    std::cout << api::fluids_table_text(fluids);
  }
  return kExitOk;
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
