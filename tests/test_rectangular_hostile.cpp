// Hostile checks of rectangular containers through a real `slosh serve` on loopback: the answer
// must be continuous in the orientation, the validity warnings must name every direction out of
// range, and a calibration must not carry one tank's unfitted damping into another container.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "support/server.hpp"

namespace slosh::test {
namespace test_rectangular_hostile {

using nlohmann::json;

json cup(double orientation_deg, double length_mm = 120, double width_mm = 80,
         double fill_mm = 50) {
  return {{"container",
           {{"shape", "rectangular"},
            {"length_mm", length_mm},
            {"width_mm", width_mm},
            {"height_mm", 70},
            {"orientation_deg", orientation_deg}}},
          {"fill_height_mm", fill_mm},
          {"fluid", "water"},
          {"stroke_mm", 200},
          {"motion_time_s", 1}};
}

json post(const Server& server, const std::string& path, const json& body, int expect = 200) {
  auto r = server.client().Post(path, body.dump(), "application/json");
  EXPECT_TRUE(r);
  if (!r) return json();
  EXPECT_EQ(r->status, expect) << r->body;
  return json::parse(r->body);
}

double rest(const json& plan, const char* model) {
  return plan["prediction"][model]["eta_rest_mm"].get<double>();
}

class RectangularHostile : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new Server({"--cache", ""}); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static Server* server_;
};
Server* RectangularHostile::server_ = nullptr;

// A width share of sin(1e-9 deg) ~ 1.7e-11 must not change the plan: same physics as 0 deg.
TEST_F(RectangularHostile, OrientationJustOffTheAxisPlansAsOnTheAxis) {
  const json at_zero = post(*server_, "/v1/plans", {{"format", cup(0.0)}});
  for (double tiny : {1e-9, -1e-9, 1e-300}) {
    const json off = post(*server_, "/v1/plans", {{"format", cup(tiny)}});
    for (const char* model : {"linear", "nonlinear"}) {
      EXPECT_NEAR(rest(off, model), rest(at_zero, model), 1e-3 * rest(at_zero, model) + 1e-6)
          << "orientation " << tiny << ", " << model << " model";
    }
  }
  const json at_ninety = post(*server_, "/v1/plans", {{"format", cup(90.0)}});
  const json near_ninety = post(*server_, "/v1/plans", {{"format", cup(89.9999999)}});
  for (const char* model : {"linear", "nonlinear"}) {
    EXPECT_NEAR(rest(near_ninety, model), rest(at_ninety, model),
                1e-3 * rest(at_ninety, model) + 1e-6)
        << model;
  }
}

// A square tank moved diagonally in shallow fill is out of the nonlinear range along both sides.
TEST_F(RectangularHostile, ShallowSquareAtFortyFiveWarnsForBothDirections) {
  const json plan = post(*server_, "/v1/plans", {{"format", cup(45.0, 100, 100, 20)}});
  bool length = false, width = false;
  for (const auto& w : plan["warnings"]) {
    const std::string text = w.get<std::string>();
    length = length || text.find("not valid along the length") != std::string::npos;
    width = width || text.find("not valid along the width") != std::string::npos;
  }
  EXPECT_TRUE(length) << plan["warnings"].dump();
  EXPECT_TRUE(width) << plan["warnings"].dump();
}

// Two measured moves of the 120 x 80 cup along its length, for a calibration.
json two_cup_moves() {
  return json::array(
      {{{"name", "m1"},
        {"law", {{"type", "modified_trapezoid"}}},
        {"peaks", {{"eta_motion_mm", 14}, {"eta_rest_mm", 12}, {"rest_window_s", 1.0}}}},
       {{"name", "m2"},
        {"law", {{"type", "poly5"}}},
        {"peaks", {{"eta_motion_mm", 12}, {"eta_rest_mm", 3}, {"rest_window_s", 1.0}}}}});
}

// A calibration whose zeta stayed at the cup's prior must not override another tank's damping:
// another tank is refused by name, and the same cup at another fill keeps its own damping there.
TEST_F(RectangularHostile, CalibrationOfOneCupDoesNotImposeItsDampingPriorElsewhere) {
  const json fitted = post(*server_, "/v1/calibrations",
                           {{"name", "hostile-cup"},
                            {"format", cup(0.0)},
                            {"moves", two_cup_moves()},
                            {"fit", {{"zeta", {{"fit", false}}}}}});
  // zeta held at the cup's prior (not fitted): the stored model carries none.
  ASSERT_EQ(fitted["parameters"]["zeta"]["state"], "fixed") << fitted.dump();
  EXPECT_FALSE(fitted["model"].contains("zeta")) << fitted["model"].dump();
  // Another tank: refused, naming the calibration and both containers.
  json big = cup(0.0, 300, 200, 100);
  big["container"]["height_mm"] = 150;
  const json refused =
      post(*server_, "/v1/plans", {{"format", big}, {"options", {{"model", "hostile-cup"}}}}, 422);
  EXPECT_EQ(refused["error"]["field"], "options.model") << refused.dump();
  EXPECT_EQ(refused["error"]["message"],
            "options.model = \"hostile-cup\" was fitted on a rectangular container 120 x 80 mm "
            "moved along its length; this request's container is a rectangular container 300 x "
            "200 mm moved along its length: a calibration applies only to the container and the "
            "directions it was measured on (calibrate this one, or give its numbers as an "
            "options.model object)")
      << refused.dump();
  // The same cup filled 40 mm: the calibration's frequency scale applies, and the damping is the
  // tank's own boundary-layer damping at 40 mm, not the 50 mm fill's prior of the fit.
  const json shallower = cup(0.0, 120, 80, 40);
  const json own = post(*server_, "/v1/plans", {{"format", shallower}});
  const json calibrated =
      post(*server_, "/v1/plans", {{"format", shallower}, {"options", {{"model", "hostile-cup"}}}});
  const double own_zeta = own["model"]["zeta"].get<double>();
  EXPECT_DOUBLE_EQ(calibrated["model"]["zeta"].get<double>(), own_zeta) << calibrated.dump();
  EXPECT_NE(own_zeta, fitted["parameters"]["zeta"]["prior"].get<double>());
  EXPECT_EQ(calibrated["model"]["calibration"], fitted["model"]) << calibrated["model"].dump();
  const double scale = fitted["model"]["omega_scale"].get<double>();
  EXPECT_NEAR(calibrated["model"]["f_hz"][0].get<double>(),
              scale * own["model"]["f_hz"][0].get<double>(), 1e-12)
      << calibrated["model"].dump();
}

// The cup's calibration is refused on a cylinder moved along an arc, naming options.model.
TEST_F(RectangularHostile, CupCalibrationIsRefusedOnACylinderAlongAnArc) {
  const json moves = two_cup_moves();
  post(*server_, "/v1/calibrations", {{"name", "cup-arc"}, {"format", cup(0.0)}, {"moves", moves}});
  const json arc = {{"container", {{"radius_mm", 48.5}, {"height_mm", 150}}},
                    {"fill_height_mm", 82},
                    {"fluid", "water"},
                    {"motion_time_s", 1.2},
                    {"motion", {{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}}}};
  const json refused =
      post(*server_, "/v1/plans",
           {{"format", arc}, {"strategy", "baseline"}, {"options", {{"model", "cup-arc"}}}}, 422);
  EXPECT_EQ(refused["error"]["field"], "options.model") << refused.dump();
  EXPECT_EQ(refused["error"]["message"],
            "options.model = \"cup-arc\" was fitted on a rectangular container 120 x 80 mm moved "
            "along its length; this request's container is a cylinder of radius 48.5 mm: a "
            "calibration applies only to the container and the directions it was measured on "
            "(calibrate this one, or give its numbers as an options.model object)")
      << refused.dump();
}

// Physically identical orientations share one recipe key (one cache entry, one answer).
TEST_F(RectangularHostile, EquivalentOrientationsShareTheRecipeKey) {
  const std::string zero = post(*server_, "/v1/plans", {{"format", cup(0.0)}})["key"];
  const std::string minus_zero = post(*server_, "/v1/plans", {{"format", cup(-0.0)}})["key"];
  const std::string plus_180 = post(*server_, "/v1/plans", {{"format", cup(180.0)}})["key"];
  const std::string minus_180 = post(*server_, "/v1/plans", {{"format", cup(-180.0)}})["key"];
  EXPECT_EQ(zero, minus_zero);
  EXPECT_EQ(plus_180, minus_180);
}

std::string fixed(double value, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

bool has_warning(const json& plan, const std::string& text) {
  for (const auto& w : plan["warnings"]) {
    if (w.get<std::string>().find(text) != std::string::npos) return true;
  }
  return false;
}

// A shallow fill rings on after the motion: the linear-theory warning must quote the larger wave
// (here the one left at rest, 1.5 times the depth), not only the peak during the motion.
TEST_F(RectangularHostile, ShallowFillWarningQuotesTheLargerWaveAfterTheMotion) {
  json format = cup(0.0, 300, 80, 10);
  format["container"]["height_mm"] = 40;
  const json plan = post(*server_, "/v1/plans", {{"format", format}, {"strategy", "multi_notch"}});
  const double motion = plan["prediction"]["linear"]["eta_motion_mm"].get<double>();
  const double after = plan["prediction"]["linear"]["eta_rest_mm"].get<double>();
  ASSERT_GT(after, motion) << "the case must leave the larger wave after the motion";
  ASSERT_GT(after, 10.0) << "and a wave deeper than the fill";
  EXPECT_TRUE(has_warning(plan, "linear model beyond its theory: wall height " + fixed(after, 1) +
                                    " mm (after the motion; " + fixed(motion, 1) +
                                    " mm during it) is " + fixed(after / 10.0, 2) +
                                    " of the fill height 10.0 mm (above 0.5), a wave not small "
                                    "against the depth; the figures are not reliable"))
      << plan["warnings"].dump();
}

// SPEC §5 "Honest status": a law that spills and sloshes more than the uniform law is not called
// optimal, on a path as on a line; the uniform law itself stays optimal unless it spills.
TEST_F(RectangularHostile, SpillingLawWorseThanTheUniformLawIsNotOptimalAlongAPath) {
  json format = cup(30.0);
  format.erase("stroke_mm");
  format["motion_time_s"] = 1.5;
  format["motion"] = {{"type", "path"},
                      {"segments", json::array({{{"line_mm", 100}},
                                                {{"arc", {{"radius_mm", 100}, {"angle_deg", 90}}}},
                                                {{"line_mm", 100}}})},
                      {"start_heading_deg", 0},
                      {"container_turns", false}};
  const json plan = post(*server_, "/v1/plans", {{"format", format}, {"strategy", "multi_notch"}});
  EXPECT_EQ(plan["status"], "acceptable") << plan.dump();
  const std::string message = plan["message"];
  EXPECT_EQ(message.rfind("multi_notch acceptable: not optimal: the predicted sloshing exceeds "
                          "the free board (liquid will spill); the law sloshes more than the "
                          "uniform law (worse_than_baseline)",
                          0),
            0u)
      << message;
  const json uniform = post(*server_, "/v1/plans", {{"format", format}, {"strategy", "baseline"}});
  EXPECT_EQ(uniform["status"], "optimal") << uniform.dump();
}

// A motion far shorter than every mode's period of a deep tank (4 x 4 m, 2 m of water, 200 mm in
// 0.1 s): on the linear model every law that moves one way leaves an eta_rest over 0.9 of the
// uniform law's, so a shaping strategy's plan is not optimal; the uniform law's, which promises
// no reduction, is. The status follows the warning's kind (its code), not its sentence.
TEST_F(RectangularHostile, NoPlanCanActIsNotOptimal) {
  json format = cup(0.0, 4000, 4000, 2000);
  format["container"]["height_mm"] = 3000;
  format["motion_time_s"] = 0.1;
  auto coded = [](const json& plan) {
    const json& codes = plan["warning_codes"];
    return std::find(codes.begin(), codes.end(), json("motion_too_short")) != codes.end();
  };
  // Ramps of 10 ms at least: room for the laws to differ, the uniform law's T/7 admissible.
  const json options = {{"min_ramp_s", 0.01}};
  const json plan = post(*server_, "/v1/plans",
                         {{"format", format}, {"strategy", "multi_notch"}, {"options", options}});
  ASSERT_TRUE(coded(plan)) << plan["warnings"].dump();
  ASSERT_TRUE(has_warning(plan, "so no such plan can reduce it by more than"))
      << plan["warnings"].dump();
  EXPECT_EQ(plan["status"], "acceptable") << plan.dump();
  EXPECT_EQ(plan["message"].get<std::string>().rfind(
                "multi_notch acceptable: not optimal: the motion is too short for any law to "
                "act on the tank's modes",
                0),
            0u)
      << plan["message"];
  const json uniform = post(*server_, "/v1/plans",
                            {{"format", format}, {"strategy", "baseline"}, {"options", options}});
  EXPECT_TRUE(coded(uniform)) << uniform["warnings"].dump();
  EXPECT_EQ(uniform["status"], "optimal") << uniform.dump();
}

// The hostile tester's 4 x 4 m tank in 50 mm of water, 200 mm in 1 s, was called too short for any
// plan while time_domain halved its residual wave: its higher modes are no impulses at 1 s.
TEST_F(RectangularHostile, AShortMoveALawCanActOnIsNotCalledTooShort) {
  json format = cup(0.0, 4000, 4000, 50);
  format["container"]["height_mm"] = 200;
  const json plan = post(*server_, "/v1/plans", {{"format", format}, {"strategy", "multi_notch"}});
  for (const json& code : plan["warning_codes"]) EXPECT_NE(code, "motion_too_short");
  EXPECT_EQ(plan["status"], "optimal") << plan["message"];
}

}  // namespace test_rectangular_hostile
}  // namespace slosh::test
