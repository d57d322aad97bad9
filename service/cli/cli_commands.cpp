#include "cli/cli_commands.hpp"

#include <exception>
#include <fstream>
#include <iostream>

#include "cli/io.hpp"
#include "slosh/api/command_replies.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/spatial_simulate.hpp"

namespace slosh::service {

namespace {

template <typename Body>
int print_json_or_error(Body&& body) {
  try {
    std::cout << body() << '\n';
    return kExitOk;
  } catch (const api::ApiError& e) {
    std::cerr << api::error_envelope_text(e) << '\n';
    return e.status() < 500 ? kExitInvalidInput : kExitFailure;
  } catch (const std::exception& e) {
    const api::ApiError wrapped(api::ErrorCode::kInternal, "", e.what());
    std::cerr << api::error_envelope_text(wrapped) << '\n';
    return kExitFailure;
  }
}

// The request text of `--request` (a file, or - for stdin); ApiError naming --request when it
// cannot be read.
std::string read_request(const std::string& request_path) {
  try {
    return read_request_text(request_path);
  } catch (const std::exception& e) {
    throw api::ApiError(api::ErrorCode::kInvalidValue, "--request", e.what());
  }
}

}  // namespace

int run_simulate_command(const std::string& request_path, const std::string& trajectory_path) {
  if (trajectory_path.empty()) {
    return print_json_or_error([&] { return api::simulate_reply(read_request(request_path)); });
  }
  return print_json_or_error([&] {
    std::ifstream csv(trajectory_path, std::ios::binary);
    if (!csv) {
      throw api::ApiError(api::ErrorCode::kInvalidValue, "--trajectory",
                          "--trajectory: cannot read the file '" + trajectory_path + "'");
    }
    return api::simulate_trajectory_reply(read_request(request_path), csv, trajectory_path);
  });
}

int run_calibrate_command(const std::string& request_path) {
  return print_json_or_error([&] { return api::calibration_reply(read_request(request_path)); });
}

std::vector<std::string> QuickPlanFlags::given() const {
  std::vector<std::string> out;
  auto note = [&](bool set, const char* flag) {
    if (set) out.emplace_back(flag);
  };
  note(radius_mm.has_value(), "--radius");
  note(length_mm.has_value(), "--length");
  note(width_mm.has_value(), "--width");
  note(orientation_deg.has_value(), "--orientation");
  note(fill_mm.has_value(), "--fill");
  note(height_mm.has_value(), "--height");
  note(fluid.has_value(), "--fluid");
  note(density_kg_m3.has_value(), "--density");
  note(viscosity_pa_s.has_value(), "--viscosity");
  note(stroke_mm.has_value(), "--stroke");
  note(time_s.has_value(), "--time");
  note(arc_radius_mm.has_value(), "--arc-radius");
  note(arc_angle_deg.has_value(), "--arc-angle");
  note(turns.has_value(), "--turns");
  note(motion_path.has_value(), "--motion");
  note(strategy.has_value(), "--strategy");
  return out;
}

std::string motion_flags_problem(const MotionFlags& m) {
  const bool arc = m.arc_radius_mm || m.arc_angle_deg;
  if (m.motion_path && (arc || m.turns)) {
    return "--motion cannot be combined with --arc-radius, --arc-angle or --turns: the file "
           "gives the whole motion";
  }
  if (m.turns && !arc) return "--turns applies to an arc: give --arc-radius and --arc-angle";
  return "";
}

namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& i : items) out += (out.empty() ? "" : ", ") + i;
  return out;
}

/// Why the move's flags conflict (--stroke, the arc's, --motion), or "" when they do not.
std::string stroke_and_motion_problem(const QuickPlanFlags& q) {
  const bool arc = q.arc_radius_mm || q.arc_angle_deg;
  if (q.motion_path && (q.stroke_mm || arc || q.turns)) {
    return "--motion cannot be combined with --stroke, --arc-radius, --arc-angle or --turns: the "
           "file gives the whole motion";
  }
  if (q.stroke_mm && arc) {
    return "--stroke cannot be combined with --arc-radius/--arc-angle: the law moves along the "
           "arc, its length is the stroke";
  }
  return motion_flags_problem(q);
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
  if (const std::string motion = stroke_and_motion_problem(q); !motion.empty()) return motion;
  const bool rectangular = q.length_mm || q.width_mm || q.orientation_deg;
  if (q.radius_mm && rectangular) {
    return "--radius cannot be combined with --length/--width/--orientation: a container is a "
           "cylinder (--radius) or rectangular (--length and --width)";
  }
  std::vector<std::string> missing;
  if (rectangular) {
    if (!q.length_mm) missing.emplace_back("--length");
    if (!q.width_mm) missing.emplace_back("--width");
  } else if (!q.radius_mm) {
    missing.emplace_back("--radius");
  }
  if (!q.fill_mm) missing.emplace_back("--fill");
  if (!q.fluid && !q.density_kg_m3)
    missing.emplace_back(q.viscosity_pa_s ? "--density" : "--fluid");
  if (!q.fluid && q.density_kg_m3 && !q.viscosity_pa_s) missing.emplace_back("--viscosity");
  const bool arc = q.arc_radius_mm || q.arc_angle_deg;
  if (arc && !q.arc_radius_mm) missing.emplace_back("--arc-radius");
  if (arc && !q.arc_angle_deg) missing.emplace_back("--arc-angle");
  if (!q.stroke_mm && !arc && !q.motion_path) missing.emplace_back("--stroke");
  if (!q.time_s) missing.emplace_back("--time");
  if (!missing.empty()) {
    return std::string("the format flags need ") +
           (rectangular ? "--length and --width" : "--radius") +
           ", --fill, --fluid (or --density and --viscosity), --stroke and --time: missing " +
           joined(missing);
  }
  return "";
}

/// The text of the file a flag names; ApiError naming the flag when it cannot be read.
std::string read_file_flag(const std::string& path, const std::string& flag,
                           const std::string& what) {
  try {
    return read_request_text(path, what);
  } catch (const std::exception& e) {
    throw api::ApiError(api::ErrorCode::kInvalidValue, flag, e.what());
  }
}

/// The move flags as the API takes them (the --motion file read).
api::QuickMotion quick_motion(const MotionFlags& m) {
  api::QuickMotion p;
  p.arc_radius_mm = m.arc_radius_mm;
  p.arc_angle_deg = m.arc_angle_deg;
  p.turns = m.turns;
  if (m.motion_path) {
    p.motion_text = read_file_flag(*m.motion_path, "--motion", "motion");
    p.motion_source = *m.motion_path;
  }
  return p;
}

/// The quick flags as the API takes them (quick_flags_problem found none missing).
api::QuickPlan quick_plan(const QuickPlanFlags& q) {
  api::QuickPlan p;
  p.radius_mm = q.radius_mm.value_or(0.0);
  if (q.length_mm)
    p.rectangular = api::QuickRectangle{*q.length_mm, *q.width_mm, q.orientation_deg};
  p.height_mm = q.height_mm;
  p.fill_mm = *q.fill_mm;
  p.fluid = q.fluid;
  p.density_kg_m3 = q.density_kg_m3;
  p.viscosity_pa_s = q.viscosity_pa_s;
  if (q.stroke_mm) p.stroke_mm = *q.stroke_mm;
  p.motion = quick_motion(q);
  p.time_s = *q.time_s;
  p.strategy = q.strategy.value_or("auto");
  return p;
}

/// The flag a request field came from ("" when none).
std::string flag_of(const std::string& field) {
  static const std::pair<const char*, const char*> flags[] = {
      {"format.container.radius_mm", "--radius"},
      {"format.container.length_mm", "--length"},
      {"format.container.width_mm", "--width"},
      {"format.container.orientation_deg", "--orientation"},
      {"format.container.height_mm", "--height"},
      {"format.fill_height_mm", "--fill"},
      {"format.fluid.density_kg_m3", "--density"},
      {"format.fluid.viscosity_pa_s", "--viscosity"},
      {"format.fluid", "--fluid"},
      {"format.stroke_mm", "--stroke"},
      {"format.motion.radius_mm", "--arc-radius"},
      {"format.motion.angle_deg", "--arc-angle"},
      {"format.motion.container_turns", "--turns"},
      {"format.motion_time_s", "--time"},
      {"strategy", "--strategy"}};
  for (const auto& [path, flag] : flags) {
    if (field == path) return flag;
  }
  return "";
}

// The text summary of the plan of the flags (`from_flags`) or of the request text `request`.
int plan_as_text(const PlanCommandOptions& o, const std::string& request, bool from_flags) {
  try {
    std::cout << (from_flags ? api::plan_summary_reply(quick_plan(o.quick))
                             : api::plan_summary_reply(request));
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
    std::string request;
    try {
      if (!from_flags) request = read_request(o.request_path);
    } catch (const api::ApiError& e) {
      std::cerr << "slosh plan: " << e.what() << '\n';
      return kExitInvalidInput;
    }
    return plan_as_text(o, request, from_flags);
  }
  return print_json_or_error([&] {
    const api::PlanView v = o.view ? api::parse_plan_view(*o.view) : api::PlanView::kFull;
    return from_flags ? api::plan_reply(quick_plan(o.quick), v)
                      : api::plan_reply(read_request(o.request_path), v);
  });
}

int run_fluids_command(const std::string& format) {
  std::cout << api::fluids_reply(format != "json") << (format == "json" ? "\n" : "");
  return kExitOk;
}

int run_min_time_command(const std::string& request_path, const MotionFlags& motion) {
  std::string problem = motion_flags_problem(motion);
  if (problem.empty() && (motion.arc_radius_mm.has_value() != motion.arc_angle_deg.has_value())) {
    problem = std::string("an arc needs --arc-radius and --arc-angle: missing ") +
              (motion.arc_radius_mm ? "--arc-angle" : "--arc-radius");
  }
  if (!problem.empty()) {
    std::cerr << "slosh min-time: " << problem << '\n';
    return kExitInvalidInput;
  }
  return print_json_or_error(
      [&] { return api::min_time_reply(read_request(request_path), quick_motion(motion)); });
}

}  // namespace slosh::service
