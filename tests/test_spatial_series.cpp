// The series of POST /v1/simulate along a spatial motion (SPEC §14), through the API's request
// handling: a one-line path at 37 degrees gives the straight line's wave (its magnitude, the
// planar height being the maximum over the wall) and the pose on that line; an arc's series
// peaks where the prediction says and its pose lies on the circle; a trajectory's series has no
// distance along a path, and its span is the trajectory's duration and the rest.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/plan.hpp"
#include "slosh/api/spatial_simulate.hpp"

namespace slosh {
namespace test_spatial_series {

using nlohmann::json;

constexpr double kPi{std::numbers::pi};

json body_with(const json& motion, double sample_period) {
  json format{{"container", {{"radius_mm", 48.5}, {"height_mm", 150}}},
              {"fill_height_mm", 82},
              {"fluid", "water"},
              {"motion_time_s", 1.2}};
  if (motion.is_null()) {
    format["stroke_mm"] = 500;
  } else {
    format["motion"] = motion;
  }
  return {{"format", format},
          {"law", {{"type", "seven_segment_uniform"}}},
          {"sample_period_s", sample_period}};
}

std::vector<double> column(const json& series, const char* key) {
  return series.at(key).get<std::vector<double>>();
}

double peak_of(const std::vector<double>& v) {
  double m = 0.0;
  for (const double x : v) m = std::max(m, std::abs(x));
  return m;
}

/// Each model's largest height of a plan's series over the motion [0, T] is its predicted
/// eta_motion, from below within the sampling.
void expect_motion_peak_is_the_prediction(const json& plan, double T) {
  const json& series = plan.at("series");
  const std::vector<double> t = column(series, "t_s");
  for (const char* model : {"linear", "nonlinear"}) {
    SCOPED_TRACE(model);
    const std::vector<double> eta = column(series, ("eta_" + std::string(model) + "_mm").c_str());
    double motion = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      if (t[k] <= T) motion = std::max(motion, eta[k]);
    }
    const double want = plan["prediction"][model]["eta_motion_mm"].get<double>();
    EXPECT_LE(motion, want * (1 + 1e-7));
    EXPECT_GE(motion, want * (1 - 1e-3));
  }
}

TEST(SpatialSeries, OneLinePathAt37DegreesIsTheStraightLinesWave) {
  const json path{{"type", "path"}, {"segments", {{{"line_mm", 500}}}}, {"start_heading_deg", 37}};
  const json spatial = api::simulate_response(body_with(path, 0.002));
  const json plain = api::simulate_response(body_with(json(), 0.002));
  const json& a = spatial.at("series");
  const json& b = plain.at("series");
  ASSERT_EQ(a["t_s"], b["t_s"]);
  const double c = std::cos(37.0 * kPi / 180), s = std::sin(37.0 * kPi / 180);
  const std::vector<double> x = column(a, "x_mm"), y = column(a, "y_mm"), dist = column(b, "s");
  for (std::size_t k = 0; k < x.size(); ++k) {
    EXPECT_NEAR(x[k], dist[k] * 1e3 * c, 1e-9) << k;
    EXPECT_NEAR(y[k], dist[k] * 1e3 * s, 1e-9) << k;
  }
  EXPECT_EQ(a["s"], b["s"]);
  EXPECT_EQ(a["a"], b["a"]);
  for (const char* model : {"linear", "nonlinear"}) {
    SCOPED_TRACE(model);
    const std::vector<double> planar = column(a, ("eta_" + std::string(model) + "_mm").c_str());
    const std::vector<double> line = column(b, ("eta_" + std::string(model) + "_mm").c_str());
    const std::vector<double> dir = column(a, ("direction_" + std::string(model) + "_deg").c_str());
    const double peak = peak_of(line);
    ASSERT_GT(peak, 1.0);
    for (std::size_t k = 0; k < line.size(); ++k) {
      EXPECT_NEAR(planar[k], std::abs(line[k]), 1e-5 * peak) << k;
      if (std::abs(line[k]) > 0.01 * peak) {
        // The wave peaks at the wall the line's wave rises at: ahead (37) or behind (-143).
        const double want = line[k] > 0 ? 37.0 : -143.0;
        EXPECT_NEAR(dir[k], want, 1e-6) << k;
      }
    }
  }
}

TEST(SpatialSeries, ArcSeriesPeaksAtThePredictionOnTheCircle) {
  const json arc{{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}, {"container_turns", true}};
  const json r = api::simulate_response(body_with(arc, 0.001));
  const json& series = r.at("series");
  const std::vector<double> t = column(series, "t_s"), dist = column(series, "s");
  const std::vector<double> x = column(series, "x_mm"), y = column(series, "y_mm");
  const std::vector<double> theta = column(series, "theta_deg");
  ASSERT_EQ(t.size(), 2201u);  // 1.2 s of motion and 1 s of rest at 1 ms
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double phi = dist[k] / 0.3;
    EXPECT_NEAR(x[k], 300.0 * std::sin(phi), 1e-9) << k;
    EXPECT_NEAR(y[k], 300.0 * (1.0 - std::cos(phi)), 1e-9) << k;
    EXPECT_NEAR(theta[k], phi * 180.0 / kPi, 1e-9) << k;
  }
  for (const char* model : {"linear", "nonlinear"}) {
    SCOPED_TRACE(model);
    const std::vector<double> eta = column(series, ("eta_" + std::string(model) + "_mm").c_str());
    const json& p = r["prediction"][model];
    const double T = 1.2;
    double motion = 0.0, rest = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      double& window = t[k] <= T ? motion : rest;
      window = std::max(window, eta[k]);
    }
    // Sampled at 1 ms, the series' maximum is below the exact peak by at most (w1 dt)^2 / 2 of it.
    const double eta_motion = p["eta_motion_mm"].get<double>();
    EXPECT_LE(motion, eta_motion * (1 + 1e-7));
    EXPECT_GE(motion, eta_motion * (1 - 1e-3));
    const double eta_rest = p["eta_rest_mm"].get<double>();
    EXPECT_LE(rest, eta_rest * (1 + 1e-7));
    EXPECT_GE(rest, eta_rest * (1 - 1e-3));
  }
}

TEST(SpatialSeries, APlanAlongAnArcHasThePlanarSeriesOfItsLaw) {
  json body = body_with(
      {{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}, {"container_turns", true}}, 0.001);
  body.erase("law");
  body["strategy"] = "baseline";
  const json plan = api::run_plan(api::parse_plan_request(body));
  const json& series = plan.at("series");
  ASSERT_TRUE(series.contains("direction_nonlinear_deg"));  // the planar series, not the line's
  expect_motion_peak_is_the_prediction(plan, 1.2);
  // The same law simulated along the arc gives the same series.
  json simulate = body_with(
      {{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}, {"container_turns", true}}, 0.001);
  const json simulated = api::simulate_response(simulate);
  const std::vector<double> a = column(simulated["series"], "eta_nonlinear_mm");
  const std::vector<double> b = column(series, "eta_nonlinear_mm");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], 1e-12) << k;
}

// A rectangular tank's plan along an arc: its series is the tank's (the highest corner, as its
// prediction), not a cylinder's of the same fill.
TEST(SpatialSeries, ATankPlanAlongAnArcHasTheTanksSeries) {
  json body = body_with({{"type", "arc"}, {"radius_mm", 150}, {"angle_deg", 90}}, 0.001);
  body.erase("law");
  body["strategy"] = "multi_notch";
  body["format"]["container"] = {{"shape", "rectangular"},
                                 {"length_mm", 120},
                                 {"width_mm", 80},
                                 {"height_mm", 60},
                                 {"orientation_deg", 30}};
  body["format"]["fill_height_mm"] = 30;
  const json plan = api::run_plan(api::parse_plan_request(body));
  expect_motion_peak_is_the_prediction(plan, 1.2);
}

// The series' pose is one world frame (theta_deg the heading, start_heading_deg at the start),
// so a series fed back as a trajectory is the same motion: a turned tank on an arc that starts
// at 37 degrees gives the same heights both ways.
TEST(SpatialSeries, ASeriesFedBackAsATrajectoryIsTheSameMotion) {
  for (const bool turns : {true, false}) {
    SCOPED_TRACE(turns);
    json body = body_with({{"type", "arc"},
                           {"radius_mm", 150},
                           {"angle_deg", 90},
                           {"start_heading_deg", 37},
                           {"container_turns", turns}},
                          0.001);
    body["format"]["container"] = {{"shape", "rectangular"},
                                   {"length_mm", 120},
                                   {"width_mm", 80},
                                   {"height_mm", 60},
                                   {"orientation_deg", 30}};
    body["format"]["fill_height_mm"] = 30;
    const json arc = api::simulate_response(body);
    const json& series = arc.at("series");
    EXPECT_DOUBLE_EQ(series["theta_deg"][0].get<double>(), 37.0);
    json trajectory{{"type", "trajectory"}};
    for (const char* c : {"t_s", "x_mm", "y_mm", "theta_deg"}) {
      for (std::size_t k = 0; k < series["t_s"].size(); ++k) {
        if (series["t_s"][k].get<double>() > 1.2 + 1e-9) break;
        trajectory[c].push_back(series[c][k]);
      }
    }
    json again = body;
    again.erase("law");
    again.erase("sample_period_s");
    again["format"].erase("motion_time_s");
    again["format"]["motion"] = trajectory;
    const json replay = api::simulate_response(again);
    for (const char* model : {"linear", "nonlinear"}) {
      SCOPED_TRACE(model);
      for (const char* peak : {"eta_motion_mm", "eta_rest_mm"}) {
        const double want = arc["prediction"][model][peak].get<double>();
        EXPECT_NEAR(replay["prediction"][model][peak].get<double>(), want, 2e-3 * want) << peak;
      }
    }
  }
}

TEST(SpatialSeries, TrajectorySeriesHasThePoseButNoPathDistance) {
  // A circle of radius 20 mm at 1 turn/s, sampled at 200 Hz for 1 s.
  json motion{{"type", "trajectory"}};
  for (int k = 0; k <= 200; ++k) {
    const double t = k * 0.005;
    motion["t_s"].push_back(t);
    motion["x_mm"].push_back(20.0 * std::sin(2 * kPi * t));
    motion["y_mm"].push_back(20.0 * (1 - std::cos(2 * kPi * t)));
  }
  json body = body_with(motion, 0.01);
  body.erase("law");
  body["format"].erase("motion_time_s");
  const json r = api::simulate_response(body);
  const json& series = r.at("series");
  EXPECT_FALSE(series.contains("s"));
  EXPECT_FALSE(series.contains("a"));
  EXPECT_EQ(series["t_s"].size(), 201u);  // 1 s of motion, 1 s of rest at 10 ms
  const std::vector<double> x = column(series, "x_mm"), a_h = column(series, "a_h");
  EXPECT_NEAR(x[25], 20.0, 1e-9);  // t = 0.25 s, a sample
  // Mid-motion the centripetal acceleration of the circle, 0.02 (2 pi)^2 m/s^2 (the natural
  // splines' ends bend it near the start and the end).
  EXPECT_NEAR(a_h[50], 0.02 * 4 * kPi * kPi, 1e-3 * 0.02 * 4 * kPi * kPi);
}

}  // namespace test_spatial_series
}  // namespace slosh
