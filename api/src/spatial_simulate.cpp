#include "slosh/api/spatial_simulate.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/motion_json.hpp"
#include "slosh/api/spatial_rectangular_series.hpp"
#include "slosh/api/spatial_series.hpp"
#include "slosh/api/trajectory_csv.hpp"
#include "slosh/core/constants.hpp"
#include "slosh/core/model/modal_truncation.hpp"
#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/motion/invalid_motion.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/motion/trajectory_ends.hpp"
#include "slosh/core/response/rectangular_planar.hpp"
#include "slosh/core/response/rectangular_yaw.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/strategy/path_plan.hpp"

namespace slosh::api {

namespace {

// Both models hold the liquid on the bottom under the effective gravity g + a_z: a trajectory
// that accelerates downward at g or more (a delta robot's fast descent) is outside both, refused
// at the first sample where it happens (its time on the samples' clock). The acceleration is the
// samples' (sample_vertical_acceleration), not the spline's between them: where a descent stops
// at once the spline overshoots the step (-10.2 m/s^2 on a stop from -9 m/s^2), an artefact of
// the interpolation that is no reason to refuse the motion; the models are driven by the spline
// all the same, whose overshoot lasts a sample interval.
void require_positive_gravity(const SampledTrajectory& trajectory) {
  const std::vector<double>& t = trajectory.samples().t;
  for (std::size_t i = 1; i + 1 < t.size(); ++i) {
    const double az = trajectory.sample_vertical_acceleration(i);
    if (kGravity + az > 0.0) continue;
    const std::string field = "format.motion.z_mm[" + std::to_string(i) + "]";
    invalid(field, field + ": the vertical acceleration of the samples' spline is " +
                       number_text(az) + " m/s^2 at t = " + number_text(t[i]) +
                       " s, so the effective gravity g + a_z = " + number_text(kGravity + az) +
                       " m/s^2 is not positive: the liquid leaves the bottom and neither model "
                       "describes it; allowed a_z > " +
                       number_text(-kGravity) + " m/s^2");
  }
}

PlanarDrive make_drive(const SpatialMotion& motion, const SloshingModel& model,
                       const MotionLaw& law) {
  if (!motion.trajectory) return PlanarDrive(*motion.path, law);
  try {
    motion.trajectory->check_sampling(model.omega1());
  } catch (const InvalidMotion& e) {
    motion_refusal(e.member(), e.what());
  }
  if (motion.trajectory->has_vertical_motion()) require_positive_gravity(*motion.trajectory);
  return PlanarDrive(*motion.trajectory);
}

// The largest horizontal acceleration of the motion [m/s^2]: along a path the law's exact
// maximum of sqrt(s''^2 + (s'^2/rho)^2) (as plans report it); a trajectory's spline acceleration
// is linear on every sample interval, so its magnitude (convex there) peaks at a sample.
double peak_horizontal_acceleration(const SpatialMotion& motion, const PlanarDrive& drive,
                                    const MotionLaw& law) {
  if (motion.path) return path_acceleration(*motion.path, law).total;
  double peak = 0.0;
  const std::vector<DrivePiece>& pieces = drive.pieces();
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    for (const double t : {pieces[k].t_begin, pieces[k].t_end}) {
      const PlanarExcitation e = drive.excitation(k, t);
      peak = std::max(peak, std::hypot(e.ax, e.ay));
    }
  }
  return peak;
}

/// The refusal of a motion on which a model diverged (`model`: "the nonlinear planar sloshing
/// model", …). A trajectory's is named by its sample of largest horizontal acceleration (the
/// spline's, which peaks at a sample), with the figure: one sample out of line with its
/// neighbours (a logger's extra sample 1 ns after another and 1 um off) makes the spline
/// accelerate at 1e6 m/s^2 and more there, and the refusal said only "outside what the model
/// describes".
[[noreturn]] void refuse_diverging_motion(const SpatialMotion& motion, const std::string& model) {
  const std::string head =
      model +
      " diverges for this motion on this format: the motion is outside what the model describes";
  if (!motion.trajectory) invalid(join_path("format", "motion"), head);
  const SampledTrajectory& tr = *motion.trajectory;
  const std::vector<double>& t = tr.samples().t;
  std::size_t at = 0;
  double peak = -1.0;
  bool along_x = true;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const PlanarKinematics k = tr.at(std::min(i, t.size() - 2), t[i]);
    const double a = std::hypot(k.ax, k.ay);
    if (a > peak || !std::isfinite(a)) {
      peak = a;
      at = i;
      along_x = !(std::abs(k.ay) > std::abs(k.ax));
      if (!std::isfinite(a)) break;
    }
  }
  const std::string field =
      "format.motion." + std::string(along_x ? "x_mm" : "y_mm") + "[" + std::to_string(at) + "]";
  invalid(field, field + ": " + head + " (the samples' spline accelerates at " + number_text(peak) +
                     " m/s^2 horizontally there, t = " + number_text(t[at]) + " s)");
}

/// A trajectory that starts or ends moving: the models take it at rest before its first sample and
/// after its last (trajectory_ends.hpp), so the answer says which end moves and how fast. Its
/// ends are judged over a stretch of the first mode's period `omega1` [rad/s].
void add_moving_end_warnings(const SpatialMotion& motion, double omega1,
                             std::vector<Warning>& warnings) {
  if (!motion.trajectory) return;
  for (std::string& w : moving_end_warnings(*motion.trajectory, omega1)) {
    warnings.push_back({WarningKind::kTrajectoryEndMoving, std::move(w)});
  }
}

/// The clock the answer's times are on [s]: a trajectory's own, whose first sample is at t_s[0]
/// (a log cut out of a run at 0.5 s, or stamped with the machine's clock at 1e6 s), so that its
/// peaks, its series and its warnings name the same instants as its samples; 0 for a law along a
/// line, an arc or a path, which starts at 0.
double time_origin(const SpatialMotion& motion) {
  return motion.trajectory ? motion.trajectory->start_time() : 0.0;
}

/// Puts the answer's times, computed from the motion's start, on the clock of time_origin: the
/// peaks' t_motion_s and t_rest_s (each model's and each direction's of a rectangular tank) and
/// the series' t_s. Nothing changes for an origin of 0 (a law's answer stays as it was).
void to_motion_clock(nlohmann::json& out, double origin) {
  if (origin == 0.0) return;
  auto shift = [origin](nlohmann::json& peaks) {
    for (const char* key : {"t_motion_s", "t_rest_s"}) {
      if (peaks.contains(key)) peaks[key] = peaks[key].get<double>() + origin;
    }
  };
  nlohmann::json& prediction = out["prediction"];
  for (const char* model : {"nonlinear", "linear"}) shift(prediction[model]);
  if (prediction.contains("directions")) {
    for (auto& [name, peaks] : prediction["directions"].items()) shift(peaks);
  }
  if (out.contains("series")) {
    for (nlohmann::json& t : out["series"]["t_s"]) t = t.get<double>() + origin;
  }
}

/// The answer's warnings and, one per entry in their order, their kinds' codes.
void put_warnings(const std::vector<Warning>& warnings, nlohmann::json& out) {
  out["warnings"] = warning_texts(warnings);
  out["warning_codes"] = warning_codes(warnings);
}

const char* type_name(MotionType type) {
  switch (type) {
    case MotionType::kLine:
      return "line";
    case MotionType::kArc:
      return "arc";
    case MotionType::kPath:
      return "path";
    case MotionType::kTrajectory:
      return "trajectory";
  }
  return "line";
}

/// The world angle of a rectangular tank's L axis when the drive's heading is 0 [rad]: along a
/// path, orientation_deg from the path's start tangent; on a trajectory, from the world x axis
/// (the samples' theta turns it from there).
double tank_frame_angle(const SpatialMotion& motion, const RectangularTank& tank) {
  const double start = motion.path ? motion.path->start_heading() : 0.0;
  return start + tank.orientation_deg / kDegPerRad;
}

/// What a series' theta counts from [rad]: a path's start heading (its drive's theta is the
/// heading change since the start), 0 for a trajectory (its theta is the world heading).
double theta_origin(const SpatialMotion& motion) {
  return motion.path ? motion.path->start_heading() : 0.0;
}

nlohmann::json law_json(const SimulateRequest& request, const MotionLaw& law,
                        const std::optional<SevenSegmentLaw>& seven) {
  nlohmann::json out{{"type", to_string(request.law_type)},
                     {"duration_s", law.duration()},
                     {"stroke_mm", mm_of(request.format.stroke)},
                     {"breakpoints_s", law.breakpoints()}};
  if (seven) out["durations_s"] = seven->durations();
  return out;
}

nlohmann::json motion_summary(const SpatialMotion& motion, const PlanarDrive& drive) {
  nlohmann::json summary{{"type", type_name(motion.type)}, {"duration_s", drive.duration()}};
  if (motion.trajectory) {
    summary["samples"] = motion.trajectory->size();
  } else {
    summary["length_mm"] = motion.path->length() * 1e3;
    summary["container_turns"] = motion.path->container_turns();
  }
  return summary;
}

/// The answer's echo of what was simulated: the format with its motion (a trajectory has no
/// stroke or motion time), the law when there is one, and the motion's summary.
nlohmann::json motion_echo(const SimulateRequest& request, const SpatialMotion& motion,
                           const PlanarDrive& drive, const MotionLaw& law,
                           const std::optional<SevenSegmentLaw>& seven) {
  nlohmann::json out;
  nlohmann::json format = format_json(request.format);
  if (motion.trajectory) {
    format.erase("stroke_mm");
    format.erase("motion_time_s");
  } else {
    out["law"] = law_json(request, law, seven);
  }
  format["motion"] = motion.echo;
  out["format"] = format;
  out["motion"] = motion_summary(motion, drive);
  return out;
}

/// A rectangular tank along the motion: the tank-frame models of rectangular_planar.hpp.
nlohmann::json run_rectangular(const SpatialSimulateRequest& spatial, const MotionLaw& law,
                               const std::optional<SevenSegmentLaw>& seven) {
  const SimulateRequest& request = spatial.base;
  const SpatialMotion& motion = spatial.motion;
  const RectangularModel tank = rectangular_model_of(request.format, request.options.model);
  // The sampling must follow the faster of the two directions' first modes.
  SloshingModel fastest = tank.along_length.omega1() >= tank.along_width.omega1()
                              ? tank.along_length
                              : tank.along_width;
  const PlanarDrive drive = make_drive(motion, fastest, law);
  const double rest = request.options.rest_time;
  const double frame = tank_frame_angle(motion, *request.format.container.rectangular);
  const RectangularPlanarPeaks linear = rectangular_planar_linear_peaks(tank, drive, frame, rest);
  const RectangularPlanarNonlinearPeaks nonlinear =
      rectangular_planar_nonlinear_peaks(tank, drive, frame, rest);
  for (const auto& [name, p] :
       {std::pair{"nonlinear", &nonlinear.peaks}, std::pair{"linear", &linear}}) {
    if (!std::isfinite(p->highest.motion.value) || !std::isfinite(p->highest.rest.value)) {
      refuse_diverging_motion(
          motion, std::string("the ") + name + " sloshing model of the rectangular tank");
    }
  }
  nlohmann::json out = motion_echo(request, motion, drive, law, seven);
  out["model"] =
      model_json(make_sloshing_model(request.format, request.options.model), request.options.model);
  add_rectangular_model(out["model"], tank, request.options.model);
  const RectangularPlanarPeaks& nl = nonlinear.peaks;
  out["prediction"] = {
      {"nonlinear", planar_peaks_json(nl.highest)},
      {"linear", planar_peaks_json(linear.highest)},
      {"directions",
       {{"length", peaks_json(nl.along_length)}, {"width", peaks_json(nl.along_width)}}}};
  out["rest_time_s"] = rest;
  if (request.options.sample_period) {
    out["series"] = rectangular_spatial_series_json(
        tank, drive, frame, motion.trajectory ? nullptr : &law, rest,
        *request.options.sample_period, nonlinear.nonlinear, theta_origin(motion));
  }
  const double horizontal = peak_horizontal_acceleration(motion, drive, law);
  const DirectionWaves directions{linear.along_length, linear.along_width};
  std::vector<Warning> warnings = validity_warnings(
      request.format, horizontal, linear.highest.motion.value, nl.highest.motion.value,
      nonlinear.nonlinear, linear.highest.rest.value, &directions);
  if (!nonlinear.warning.empty()) {
    warnings.push_back({WarningKind::kNonlinearModelNotValid, nonlinear.warning});
  }
  // Every motion but a line may drive both directions; a line the orientation's.
  for (const Warning& t :
       modal_truncation_warnings(*request.format.container.rectangular, request.format.fill_height,
                                 tank, drive.duration(), motion.type != MotionType::kLine)) {
    warnings.push_back(t);
  }
  const std::string yaw = yaw_mode_warning(*request.format.container.rectangular,
                                           request.format.fill_height, drive, horizontal);
  if (!yaw.empty()) warnings.push_back({WarningKind::kYawModesNotModelled, yaw});
  add_moving_end_warnings(motion, fastest.omega1(), warnings);
  put_warnings(warnings, out);
  to_motion_clock(out, time_origin(motion));
  require_finite(out);
  return out;
}

}  // namespace

nlohmann::json planar_peaks_json(const PlanarPeaks& p) {
  return {{"eta_motion_mm", p.motion.value * 1e3},
          {"eta_rest_mm", p.rest.value * 1e3},
          {"t_motion_s", p.motion.time},
          {"t_rest_s", p.rest.time},
          {"direction_motion_deg", p.motion.direction * kDegPerRad},
          {"direction_rest_deg", p.rest.direction * kDegPerRad}};
}

SpatialSimulateRequest parse_spatial_simulate_request(const nlohmann::json& body) {
  require_object(body, "");
  reject_unknown_fields(body, "", {"format", "law", "rest_time_s", "sample_period_s", "options"});
  SpatialFormat spatial = parse_spatial_format(body, true);
  // The straight-line parser reads the law and the options on the format with the motion's
  // length as its stroke; the series' span is the motion's.
  nlohmann::json plain = body;
  plain.erase("sample_period_s");
  nlohmann::json& format = plain["format"];
  format.erase("motion");
  if (spatial.motion.trajectory) {
    if (given_member(body, "law") != nullptr) {
      invalid("law",
              "law is not part of a trajectory motion: its samples give the times; leave law out");
    }
    format["stroke_mm"] = 1.0;
    format["motion_time_s"] = 1.0;
    plain["law"] = {{"type", "seven_segment_uniform"}};
  } else {
    format["stroke_mm"] = mm_of(spatial.format.stroke);
  }
  SimulateRequest base = parse_simulate_request(plain);
  const double duration = spatial.motion.trajectory ? spatial.motion.trajectory->end_time() -
                                                          spatial.motion.trajectory->start_time()
                                                    : base.format.motion_time;
  base.options.sample_period = parse_sample_period(body, duration + base.options.rest_time);
  return {std::move(base), std::move(spatial.motion)};
}

nlohmann::json simulate_response(const nlohmann::json& body) {
  if (given_motion(body) != nullptr) {
    return run_spatial_simulate(parse_spatial_simulate_request(body));
  }
  if (const std::optional<nlohmann::json> plain = straight_line_body(body)) {
    return run_simulate(parse_simulate_request(*plain));  // "motion": null
  }
  return run_simulate(parse_simulate_request(body));
}

nlohmann::json run_spatial_simulate(const SpatialSimulateRequest& spatial) {
  const SimulateRequest& request = spatial.base;
  const SpatialMotion& motion = spatial.motion;
  const std::optional<SevenSegmentLaw> seven = seven_segment_law(request);
  const MotionLaw& law = seven ? seven->law() : request.law;
  if (request.format.container.rectangular) return run_rectangular(spatial, law, seven);
  const SloshingModel model = make_sloshing_model(request.format, request.options.model);
  const PlanarDrive drive = make_drive(motion, model, law);
  const double rest = request.options.rest_time;
  const PlanarPeaks linear = planar_linear_peaks(model, drive, rest);
  const PlanarPeaks nonlinear = planar_nonlinear_peaks(model, drive, rest);
  for (const auto& [name, p] : {std::pair{"nonlinear", &nonlinear}, {"linear", &linear}}) {
    if (!std::isfinite(p->motion.value) || !std::isfinite(p->rest.value)) {
      refuse_diverging_motion(motion, std::string("the ") + name + " planar sloshing model");
    }
  }
  nlohmann::json out = motion_echo(request, motion, drive, law, seven);
  out["model"] = model_json(model, request.options.model);
  out["prediction"] = {{"nonlinear", planar_peaks_json(nonlinear)},
                       {"linear", planar_peaks_json(linear)}};
  out["rest_time_s"] = rest;
  if (request.options.sample_period) {
    out["series"] = spatial_series_json(model, drive, motion.trajectory ? nullptr : &law, rest,
                                        *request.options.sample_period, theta_origin(motion));
  }
  // The validity warnings of a straight-line simulate or a plan along the same motion, on the
  // planar peaks and the total horizontal acceleration.
  std::vector<Warning> warnings =
      validity_warnings(request.format, peak_horizontal_acceleration(motion, drive, law),
                        linear.motion.value, nonlinear.motion.value, true, linear.rest.value);
  add_moving_end_warnings(motion, model.omega1(), warnings);
  put_warnings(warnings, out);
  to_motion_clock(out, time_origin(motion));
  require_finite(out);
  return out;
}

namespace {

/// The line of each sample of a trajectory CSV, 1-based: the header is line 1, and blank lines
/// (after a trailing carriage return) hold no sample, as the readers skip them.
std::vector<std::size_t> sample_lines(const std::string& text) {
  std::vector<std::size_t> lines;
  std::size_t line = 0, begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    ++line;
    std::size_t length = end - begin;
    if (length > 0 && text[begin + length - 1] == '\r') --length;
    if (line > 1 && length > 0) lines.push_back(line);
    begin = end + 1;
  }
  return lines;
}

/// The index i of a field "format.motion.<column>[i]", or nullopt.
std::optional<std::size_t> sample_index(const std::string& field) {
  constexpr std::string_view kMotionPrefix{"format.motion."};
  if (!field.starts_with(kMotionPrefix)) return std::nullopt;
  const std::size_t open = field.find('[', kMotionPrefix.size());
  const std::size_t close = field.find(']', open);
  if (open == std::string::npos || close != field.size() - 1 || close == open + 1) {
    return std::nullopt;
  }
  std::size_t i = 0;
  for (std::size_t k = open + 1; k < close; ++k) {
    if (field[k] < '0' || field[k] > '9') return std::nullopt;
    i = 10 * i + static_cast<std::size_t>(field[k] - '0');
  }
  return i;
}

}  // namespace

std::string simulate_trajectory_reply(std::string_view request, std::istream& csv,
                                      const std::string& source) {
  nlohmann::json body = parse_json_body(request);
  if (given_motion(body) != nullptr) {
    invalid("--trajectory",
            "--trajectory and the request's format.motion both give the motion: give one of them");
  }
  const std::string text{std::istreambuf_iterator<char>(csv), std::istreambuf_iterator<char>()};
  std::istringstream in(text);
  TrajectorySamples samples;
  try {
    samples = read_trajectory_csv(in, source);
  } catch (const InvalidMotion& e) {
    invalid("--trajectory", "--trajectory " + std::string(e.what()));
  }
  if (body.is_object() && body.contains("format") && body["format"].is_object()) {
    body["format"]["motion"] = trajectory_motion_json(samples);
  }
  try {
    return dump_json(simulate_response(body), 2);
  } catch (const ApiError& e) {
    // A sample the checks refuse is the file's: named by its line, not by the request's
    // format.motion the file was turned into.
    const std::optional<std::size_t> i = sample_index(e.field());
    const std::vector<std::size_t> lines = i ? sample_lines(text) : std::vector<std::size_t>{};
    if (!i || *i >= lines.size()) throw;
    std::string message = e.what();
    if (message.starts_with("format.motion.")) message.erase(0, 14);
    throw ApiError(e.code(), "--trajectory",
                   "--trajectory " + source + " line " + std::to_string(lines[*i]) + " (sample " +
                       std::to_string(*i) + ", from 0): " + message);
  }
}

}  // namespace slosh::api
