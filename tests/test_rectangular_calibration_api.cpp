// A turned rectangular tank calibrated through the product: series made by POST /v1/simulate's
// parser and runner with per-direction scales (options.model.width_omega_scale, width_zeta),
// fitted by POST /v1/calibrations' parser and runner (the scales recovered, the model stored as
// options.model takes it), a plan naming the stored calibration on a real server (the width's
// frequencies of its model are the calibrated ones, its key the inline model's), `slosh
// calibrate` on the real binary, and every refusal's field and text.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "slosh/api/calibration_json.hpp"
#include "slosh/api/calibration_models.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/core/constants.hpp"
#include "support/plan_errors.hpp"
#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace {

using nlohmann::json;

// The README's cup, 120 x 80 mm with 50 mm of water, turned by 30 degrees.
json cup_format() {
  return json::parse(R"({"container": {"shape": "rectangular", "length_mm": 120,
      "width_mm": 80, "height_mm": 70, "orientation_deg": 30}, "fill_height_mm": 50,
      "fluid": "water", "stroke_mm": 200, "motion_time_s": 1.0})");
}

const json kTruth = {{"omega_scale", 0.94},
                     {"zeta", 0.012},
                     {"height_gain", 0.9},
                     {"width_omega_scale", 1.04},
                     {"width_zeta", 0.02}};

// A measured move: simulate's nonlinear series of the truth at 100 Hz.
json measured_move(double motion_time, const char* law) {
  json format = cup_format();
  format["motion_time_s"] = motion_time;
  const json sim =
      api::run_simulate(api::parse_simulate_request({{"format", format},
                                                     {"law", {{"type", law}}},
                                                     {"rest_time_s", 1.5},
                                                     {"sample_period_s", 0.01},
                                                     {"options", {{"model", kTruth}}}}));
  return {
      {"motion_time_s", motion_time},
      {"law", {{"type", law}}},
      {"series", {{"t_s", sim["series"]["t_s"]}, {"eta_mm", sim["series"]["eta_nonlinear_mm"]}}}};
}

json turned_calibration() {
  return {{"format", cup_format()},
          {"moves",
           json::array({measured_move(1.0, "modified_trapezoid"), measured_move(0.7, "poly5")})}};
}

api::ApiError calibration_error(const json& body) {
  try {
    (void)api::run_calibration(api::parse_calibration_request(body));
  } catch (const api::ApiError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << body.dump().substr(0, 300);
  return {api::ErrorCode::kInternal, "", ""};
}

TEST(TurnedTankCalibration, RecoversBothDirectionsAndStoresThemAsOptionsModel) {
  const json out = api::run_calibration(api::parse_calibration_request(turned_calibration()));
  EXPECT_EQ(out["status"], "converged") << out.dump().substr(0, 500);
  for (const auto& [name, value] : kTruth.items()) {
    ASSERT_TRUE(out["model"].contains(name)) << name;
    EXPECT_NEAR(out["model"][name].get<double>(), value.get<double>(), 1e-3 * value.get<double>())
        << name;
    EXPECT_EQ(out["parameters"][name]["state"], "fitted") << name;
  }
  EXPECT_FALSE(out["model"].contains("alpha"));
  EXPECT_EQ(out["container"], json::parse(R"({"shape": "rectangular", "length_mm": 120,
                "width_mm": 80, "directions": ["length", "width"]})"));
  EXPECT_TRUE(out["identifiability"].empty()) << out["identifiability"].dump();
  // The stored model plans: the width's modes take their own scale and damping.
  const json plan_body = {{"format", cup_format()},
                          {"strategy", "multi_notch"},
                          {"options", {{"model", out["model"]}}}};
  const api::PlanRequest request = api::parse_plan_request(plan_body);
  ASSERT_TRUE(request.options.model.width_omega_scale.has_value());
  EXPECT_EQ(*request.options.model.width_omega_scale, out["model"]["width_omega_scale"]);
  EXPECT_EQ(*request.options.model.width_zeta, out["model"]["width_zeta"]);
}

TEST(TurnedTankCalibration, PerDirectionModelOptionsAreKeyedOnlyWhenGiven) {
  auto key = [](const json& model) {
    json body = {{"format", cup_format()}, {"strategy", "multi_notch"}};
    if (!model.is_null()) body["options"] = {{"model", model}};
    return api::recipe_key(api::parse_plan_request(body));
  };
  EXPECT_EQ(key(nullptr), key(json::object()));
  EXPECT_NE(key({{"omega_scale", 0.94}}),
            key({{"omega_scale", 0.94}, {"width_omega_scale", 1.04}}));
  EXPECT_NE(key({{"zeta", 0.01}}), key({{"zeta", 0.01}, {"width_zeta", 0.02}}));
}

TEST(TurnedTankCalibration, RefusalsNameTheField) {
  // The moves of one turned square tank's peaks cannot tell its directions apart.
  json square = {{"format", cup_format()}};
  square["format"]["container"]["length_mm"] = 100;
  square["format"]["container"]["width_mm"] = 100;
  square["format"]["container"]["orientation_deg"] = 45;
  square["moves"] = json::array({{{"law", {{"type", "modified_trapezoid"}}},
                                  {"peaks", {{"eta_motion_mm", 12}, {"eta_rest_mm", 4}}}}});
  square["fit"] = {{"zeta", {{"fit", false}}}};
  api::ApiError e = calibration_error(square);
  EXPECT_EQ(e.status(), 422);
  EXPECT_EQ(e.field(), "moves");
  EXPECT_STREQ(e.what(),
               "moves cannot calibrate this container: the length's omega_scale and the width's "
               "omega_scale cannot be separated by these moves (J^T J is singular in that "
               "direction): add a move along the length (orientation 0 or 180 degrees) and one "
               "along the width (90 or -90 degrees), or a measured series of a turned move, "
               "whose two frequencies tell the directions apart");
  // The per-direction fit takes a series' offset as given: asking it to fit one is refused.
  json offset = turned_calibration();
  offset["moves"][1]["series"]["fit_offset"] = true;
  e = calibration_error(offset);
  EXPECT_EQ(e.status(), 422);
  EXPECT_EQ(e.field(), "moves[1].series.fit_offset");
  EXPECT_STREQ(e.what(),
               "moves[1].series.fit_offset applies to moves along one side of a rectangular "
               "container: the fit of a turned tank's directions takes each series' offset_s as "
               "given; set offset_s to the move's start on the series' clock and fit_offset to "
               "false");
  // A move's own orientation: in range, and a rectangular container's only.
  json turned = turned_calibration();
  turned["moves"][0]["orientation_deg"] = 200;
  e = calibration_error(turned);
  EXPECT_EQ(e.field(), "moves[0].orientation_deg");
  EXPECT_EQ(e.status(), 422);
  json cylinder = turned_calibration();
  cylinder["format"]["container"] = {{"radius_mm", 50}, {"height_mm", 80}};
  cylinder["moves"][1]["orientation_deg"] = 30;
  e = calibration_error(cylinder);
  EXPECT_EQ(e.field(), "moves[1].orientation_deg");
  EXPECT_STREQ(e.what(),
               "moves[1].orientation_deg applies to a rectangular container only (the "
               "turn of its sides against the move)");
  // options.model's width members: a rectangular tank's, in range.
  json cylinder_plan = {{"format", cylinder["format"]},
                        {"strategy", "shaper"},
                        {"options", {{"model", {{"width_omega_scale", 1.04}}}}}};
  e = test::plan_parse_error(cylinder_plan);
  EXPECT_EQ(e.field(), "options.model.width_omega_scale");
  EXPECT_STREQ(e.what(),
               "options.model.width_omega_scale applies to a rectangular container only (the "
               "scale or damping of its modes along the width): a cylinder's modes take "
               "omega_scale and zeta");
  json out_of_range = {{"format", cup_format()},
                       {"strategy", "multi_notch"},
                       {"options", {{"model", {{"width_zeta", 0.7}}}}}};
  e = test::plan_parse_error(out_of_range);
  EXPECT_EQ(e.status(), 422);
  EXPECT_EQ(e.field(), "options.model.width_zeta");
  json simulate_range = {{"format", cup_format()},
                         {"law", {{"type", "poly5"}}},
                         {"options", {{"model", {{"width_omega_scale", 0}}}}}};
  try {
    (void)api::parse_simulate_request(simulate_range);
    ADD_FAILURE() << "width_omega_scale 0 was simulated";
  } catch (const api::ApiError& ex) {
    EXPECT_EQ(ex.field(), "options.model.width_omega_scale");
  }
}

TEST(TurnedTankCalibration, StoredThroughTheServiceAndTheCommandAndPlannedByName) {
  json body = turned_calibration();
  const test::RunResult cli = test::run_slosh({"calibrate", "--request", "-"}, body.dump());
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const json printed = json::parse(cli.out);
  EXPECT_NEAR(printed["model"]["width_omega_scale"].get<double>(), 1.04, 1.04e-3);

  test::Server server;
  httplib::Client client = server.client();
  body["name"] = "cup-turned";
  auto posted = client.Post("/v1/calibrations", body.dump(), "application/json");
  ASSERT_TRUE(posted);
  ASSERT_EQ(posted->status, 200) << posted->body.substr(0, 300);
  const json fit = json::parse(posted->body);
  EXPECT_EQ(fit["model"], printed["model"]);
  auto plan = [&](const json& model) {
    const json request = {
        {"format", cup_format()}, {"strategy", "multi_notch"}, {"options", {{"model", model}}}};
    auto r = client.Post("/v1/plans", request.dump(), "application/json");
    EXPECT_TRUE(r);
    EXPECT_EQ(r->status, 200) << r->body.substr(0, 300);
    return json::parse(r->body);
  };
  const json by_name = plan("cup-turned");
  const json inline_model = plan(fit["model"]);
  EXPECT_EQ(by_name["key"], inline_model["key"]);
  EXPECT_EQ(by_name["law"], inline_model["law"]);
  // The plan's width modes are the theory's times the calibrated width scale (independent:
  // omega_1 = sqrt(g k tanh(k h)), k = pi / W).
  const double k = std::numbers::pi / 0.08;
  const double f_width = fit["model"]["width_omega_scale"].get<double>() *
                         std::sqrt(kGravity * k * std::tanh(k * 0.05)) / (2.0 * std::numbers::pi);
  EXPECT_NEAR(by_name["model"]["rectangular"]["width"]["f_hz"][0].get<double>(), f_width,
              1e-9 * f_width)
      << by_name["model"]["rectangular"].dump();
  // The same cup moved along its width is covered; a cylinder is not.
  json cylinder = {{"format", {{"container", {{"radius_mm", 50}}}, {"fill_height_mm", 40}}},
                   {"strategy", "shaper"},
                   {"options", {{"model", "cup-turned"}}}};
  auto refused = client.Post("/v1/plans", cylinder.dump(), "application/json");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 422);
  EXPECT_EQ(json::parse(refused->body)["error"]["field"], "options.model");
  server.stop();
}

}  // namespace
}  // namespace slosh
