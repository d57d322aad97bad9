#include "slosh/api/spatial_simulate.hpp"

#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/motion_json.hpp"
#include "slosh/api/trajectory_csv.hpp"
#include "slosh/core/motion/invalid_motion.hpp"
#include "slosh/core/motion/planar_drive.hpp"

namespace slosh::api {

namespace {

constexpr double kDegPerRad{180.0 / std::numbers::pi};

PlanarDrive make_drive(const SpatialMotion& motion, const SloshingModel& model,
                       const MotionLaw& law) {
  if (!motion.trajectory) return PlanarDrive(*motion.path, law);
  try {
    motion.trajectory->check_sampling(model.omega1());
  } catch (const InvalidMotion& e) {
    motion_refusal(e.member(), e.what());
  }
  return PlanarDrive(*motion.trajectory);
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
  if (given_member(body, "sample_period_s") != nullptr) {
    invalid("sample_period_s",
            "sample_period_s: series are not available with format.motion yet (the answer gives "
            "both models' peaks); leave sample_period_s out");
  }
  // The straight-line parser reads the law and the options on the format with the motion's
  // length as its stroke.
  nlohmann::json plain = body;
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
  return {parse_simulate_request(plain), std::move(spatial.motion)};
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
  if (request.format.container.rectangular) {
    // The planar models are the cylinder's (its modes do not care which way it moves).
    invalid("format.container.shape",
            "format.container.shape = \"rectangular\" is not simulated along format.motion: the "
            "planar sloshing models are the cylinder's; move a rectangular container along the "
            "straight stroke (without format.motion), turned by orientation_deg");
  }
  const SloshingModel model = make_sloshing_model(request.format, request.options.model);
  const PlanarDrive drive = make_drive(motion, model, law);
  const double rest = request.options.rest_time;
  const PlanarPeaks linear = planar_linear_peaks(model, drive, rest);
  const PlanarPeaks nonlinear = planar_nonlinear_peaks(model, drive, rest);
  for (const auto& [name, p] : {std::pair{"nonlinear", &nonlinear}, {"linear", &linear}}) {
    if (!std::isfinite(p->motion.value) || !std::isfinite(p->rest.value)) {
      invalid(join_path("format", "motion"),
              std::string("the ") + name +
                  " planar sloshing model diverges for this motion on this format: the motion is "
                  "outside what the model describes");
    }
  }
  nlohmann::json out;
  nlohmann::json format = format_json(request.format);
  nlohmann::json summary{{"type", type_name(motion.type)}, {"duration_s", drive.duration()}};
  if (motion.trajectory) {
    format.erase("stroke_mm");
    format.erase("motion_time_s");
    summary["samples"] = motion.trajectory->size();
  } else {
    summary["length_mm"] = motion.path->length() * 1e3;
    summary["container_turns"] = motion.path->container_turns();
    nlohmann::json law_json{{"type", to_string(request.law_type)},
                            {"duration_s", law.duration()},
                            {"stroke_mm", mm_of(request.format.stroke)},
                            {"breakpoints_s", law.breakpoints()}};
    if (seven) law_json["durations_s"] = seven->durations();
    out["law"] = law_json;
  }
  format["motion"] = motion.echo;
  out["format"] = format;
  out["motion"] = summary;
  out["model"] = model_json(model, request.options.model);
  out["prediction"] = {{"nonlinear", planar_peaks_json(nonlinear)},
                       {"linear", planar_peaks_json(linear)}};
  out["rest_time_s"] = rest;
  out["warnings"] = nlohmann::json::array();
  require_finite(out);
  return out;
}

std::string simulate_trajectory_reply(std::string_view request, std::istream& csv,
                                      const std::string& source) {
  nlohmann::json body = parse_json_body(request);
  if (given_motion(body) != nullptr) {
    invalid("--trajectory",
            "--trajectory and the request's format.motion both give the motion: give one of them");
  }
  TrajectorySamples samples;
  try {
    samples = read_trajectory_csv(csv, source);
  } catch (const InvalidMotion& e) {
    invalid("--trajectory", "--trajectory " + std::string(e.what()));
  }
  if (body.is_object() && body.contains("format") && body["format"].is_object()) {
    body["format"]["motion"] = trajectory_motion_json(samples);
  }
  return dump_json(simulate_response(body), 2);
}

}  // namespace slosh::api
