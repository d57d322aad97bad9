#pragma once
// A calibration request (POST /v1/calibrations) on the thesis format whose truth is known: one
// series of the nonlinear model with omega_scale 1.05 and height_gain 0.9, sampled at 50 Hz.

#include <nlohmann/json.hpp>

#include "slosh/api/format_json.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh::test {

/// The thesis format (r = 48.5 mm, h = 82 mm of water, 800 mm stroke in 1 s) as request JSON.
inline nlohmann::json thesis_format_json() {
  return nlohmann::json::parse(R"({"container": {"radius_mm": 48.5, "height_mm": 150},
    "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0})");
}

/// The calibration request: zeta and alpha not fitted.
inline nlohmann::json calibration_body() {
  using nlohmann::json;
  json body = {{"format", thesis_format_json()}};
  const Format f = api::parse_request_format(body);
  ModelOptions truth;
  truth.omega_scale = 1.05;
  truth.height_gain = 0.9;
  const MotionLaw law = make_modified_trapezoid_law(0.8, 0.8);
  const NonlinearResponse response(make_sloshing_model(f, truth), law, 1.2);
  json t = json::array(), eta = json::array();
  for (int k = 0; k <= 100; ++k) {
    t.push_back(0.02 * k);
    eta.push_back(response.eta(0.02 * k) * 1e3);
  }
  body["moves"] = json::array({{{"name", "mod-trap 0.8 s"},
                                {"motion_time_s", 0.8},
                                {"law", {{"type", "modified_trapezoid"}}},
                                {"series", {{"t_s", t}, {"eta_mm", eta}}}}});
  body["fit"] = {{"zeta", {{"fit", false}}}, {"alpha", {{"fit", false}}}};
  return body;
}

}  // namespace slosh::test
