// The plan request/response layer: validation messages name the field, the value and the range;
// the recipe key is the same for the same recipe however it is written and differs otherwise; the
// response carries every field of the SPEC §7 contract with numbers checked against independent
// computations (Simpson integration of the rebuilt law for the stroke, quadrature for the
// spectrum, the plateau levels of the returned durations).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "support/plan_errors.hpp"
#include "support/reference_integrators.hpp"

namespace slosh::api {
namespace test_plan_api {

using nlohmann::json;

json thesis_plan(const std::string& strategy) {
  json body = json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150},
               "fill_height_mm": 82, "fluid": "water",
               "stroke_mm": 800, "motion_time_s": 1.0},
    "options": {}
  })");
  body["strategy"] = strategy;
  return body;
}

TEST(PlanValidation, UnknownStrategyListsTheAllowedOnes) {
  const ApiError e = test::plan_parse_error(thesis_plan("multinotch"));
  EXPECT_EQ(e.status(), 422);
  EXPECT_EQ(e.field(), "strategy");
  EXPECT_STREQ(e.what(),
               "strategy = \"multinotch\" is not allowed: one of \"baseline\", \"notch\", "
               "\"multi_notch\", \"min_jerk_band\", \"time_domain\", \"fir_chain\", \"shaper\", "
               "\"iir\", \"auto\"");
}

TEST(PlanValidation, UnknownOptionIsRejected) {
  json body = thesis_plan("notch");
  body["options"]["pnotch"] = 0.1;
  const ApiError e = test::plan_parse_error(body);
  EXPECT_EQ(e.field(), "options.pnotch");
  EXPECT_NE(std::string(e.what()).find("options.pnotch"), std::string::npos) << e.what();
}

TEST(PlanValidation, OutOfRangeOptionsNameFieldValueAndRange) {
  struct Case {
    const char* key;
    json value;
    const char* field;
    const char* message;
  };
  const Case cases[] = {
      {"p_notch", 1.0, "options.p_notch",
       "options.p_notch = 1 is out of range: allowed > 0 and < 1"},
      {"band", 0.0, "options.band", "options.band = 0 is out of range: allowed > 0 and < 1"},
      {"tol_rel", -0.2, "options.tol_rel",
       "options.tol_rel = -0.2 is out of range: allowed > 0 and <= 10"},
      {"eta_rest_max_mm", 0, "options.eta_rest_max_mm",
       "options.eta_rest_max_mm = 0 is out of range: allowed > 0 and <= 10000 mm"},
      {"n_band", 0, "options.n_band", nullptr},
      {"weights", json::array({1, 1}), "options.weights",
       "options.weights must be an array of 3 numbers, got [1,1]"},
      {"weights", json::array({1, -1, 1}), "options.weights[1]", nullptr},
      {"objective", "speed", "options.objective",
       "options.objective = \"speed\" is not allowed: one of \"motion\", \"rest\""},
      {"solver", "cplex", "options.solver",
       "options.solver = \"cplex\" is not allowed: one of \"auto\", \"nlopt\", \"ipopt\""},
      {"fix_constant_velocity_zero", 1, "options.fix_constant_velocity_zero", nullptr},
  };
  for (const Case& c : cases) {
    json body = thesis_plan("notch");
    body["options"][c.key] = c.value;
    const ApiError e = test::plan_parse_error(body);
    EXPECT_EQ(e.status(), 422) << c.key;
    EXPECT_EQ(e.field(), c.field) << c.key;
    if (c.message != nullptr) {
      EXPECT_STREQ(e.what(), c.message) << c.key;
    }
    EXPECT_NE(std::string(e.what()).find(c.field), std::string::npos) << e.what();
  }
}

TEST(PlanValidation, LimitsMustBePositive) {
  json body = thesis_plan("notch");
  body["options"]["limits"] = {{"a_max", -10}};
  const ApiError e = test::plan_parse_error(body);
  EXPECT_EQ(e.field(), "options.limits.a_max");
  EXPECT_STREQ(e.what(),
               "options.limits.a_max = -10 is out of range: allowed > 0 and <= 1000 m/s^2");
  body["options"]["limits"] = {{"jmax", 10}};
  EXPECT_EQ(test::plan_parse_error(body).field(), "options.limits.jmax");
}

TEST(PlanValidation, MinRampAboveAQuarterOfTheMotionTime) {
  json body = thesis_plan("notch");
  body["options"]["min_ramp_s"] = 0.3;
  const ApiError e = test::plan_parse_error(body);
  EXPECT_EQ(e.field(), "options.min_ramp_s");
  EXPECT_STREQ(e.what(),
               "options.min_ramp_s = 0.3 is out of range: allowed 0.001 to 0.25 s (the upper "
               "bound is format.motion_time_s / 4: four ramps must fit)");
}

TEST(PlanValidation, RampsAndPlateauMinimumsLongerThanTheMotion) {
  json body = thesis_plan("notch");
  body["options"]["min_ramp_s"] = 0.2;
  body["options"]["plateau_min_s"] = {0.15, 0.1};
  const ApiError e = test::plan_parse_error(body);
  EXPECT_EQ(e.field(), "options");
  EXPECT_STREQ(e.what(),
               "options.min_ramp_s = 0.2 s and plateau_min_s = [0.15, 0.1] s need 4 ramps + 2 "
               "plateaus = 1.05 s, more than the motion time 1 s: allowed min_ramp_s <= (T - "
               "plateau minimums) / 4 = 0.188 s");
}

TEST(PlanValidation, DefaultsAreTheSeedSettings) {
  const PlanRequest r = parse_plan_request(thesis_plan("multi_notch"));
  EXPECT_EQ(r.strategy, Strategy::kMultiNotch);
  EXPECT_EQ(r.options.p_notch, 0.15);
  EXPECT_EQ(r.options.band, 0.15);
  EXPECT_EQ(r.options.n_band, 51);
  EXPECT_EQ(r.options.tol_rel, 0.2);
  EXPECT_DOUBLE_EQ(r.options.eta_rest_max, 0.003);
  EXPECT_EQ(r.options.min_ramp, 0.05);
  EXPECT_EQ(r.options.rest_time, 1.0);
  EXPECT_FALSE(r.options.limits.a_max.has_value());
  json no_strategy = thesis_plan("x");
  no_strategy.erase("strategy");
  EXPECT_EQ(parse_plan_request(no_strategy).strategy, Strategy::kAuto);
}

TEST(RecipeKey, SameRecipeWrittenDifferentlyGivesOneKey) {
  json a = thesis_plan("multi_notch");
  json b = json::parse(R"({"strategy": "multi_notch",
    "options": {"p_notch": 0.15, "weights": [1.0, 1, 1], "damping": "thesis", "modes": 3},
    "format": {"motion_time_s": 1, "stroke_mm": 800.0, "fluid": "water",
               "fill_height_mm": 82.0, "container": {"height_mm": 150, "radius_mm": 48.5}}})");
  const std::string key = recipe_key(parse_plan_request(a));
  EXPECT_EQ(key, recipe_key(parse_plan_request(b)));
  EXPECT_EQ(key.size(), 32u);
  EXPECT_EQ(key.find_first_not_of("0123456789abcdef"), std::string::npos);
  // The time budget does not change the recipe.
  b["options"]["time_limit_s"] = 2;
  EXPECT_EQ(key, recipe_key(parse_plan_request(b)));
}

TEST(RecipeKey, EveryRecipeChangeGivesAnotherKey) {
  const std::string key = recipe_key(parse_plan_request(thesis_plan("multi_notch")));
  auto changed = [](const char* path, json value) {
    json body = thesis_plan("multi_notch");
    body[json::json_pointer(path)] = std::move(value);
    return recipe_key(parse_plan_request(body));
  };
  EXPECT_NE(key, changed("/strategy", "notch"));
  EXPECT_NE(key, changed("/format/stroke_mm", 800.001));
  EXPECT_NE(key, changed("/format/motion_time_s", 0.9));
  EXPECT_NE(key, changed("/format/fluid", "ethanol"));
  EXPECT_NE(key, changed("/options/p_notch", 0.2));
  EXPECT_NE(key, changed("/options/limits", json{{"a_max", 10}}));
  EXPECT_NE(key, changed("/options/fix_constant_velocity_zero", true));
  EXPECT_NE(key, changed("/options/solver", "ipopt"));
}

TEST(PlanResponse, MultiNotchCarriesTheContractWithConsistentNumbers) {
  const PlanRequest request = parse_plan_request(thesis_plan("multi_notch"));
  const json out = run_plan(request);
  for (const char* k : {"key", "cached", "strategy", "status", "message", "durations_s",
                        "durations_pct", "switch_times_s", "kinematics", "model", "prediction",
                        "baseline", "reduction_pct", "spectrum", "solver", "warnings"}) {
    EXPECT_TRUE(out.contains(k)) << k;
  }
  EXPECT_EQ(out["status"], "optimal");
  EXPECT_EQ(out["key"], recipe_key(request));
  const auto d = out["durations_s"].get<std::array<double, 7>>();
  double sum = 0.0, pct = 0.0;
  for (int i = 0; i < 7; ++i) {
    sum += d[i];
    pct += out["durations_pct"][i].get<double>();
  }
  EXPECT_NEAR(sum, 1.0, 1e-12);
  EXPECT_NEAR(pct, 100.0, 1e-9);
  ASSERT_EQ(out["switch_times_s"].size(), 8u);
  EXPECT_NEAR(out["switch_times_s"][7].get<double>(), 1.0, 1e-12);

  // The stroke and rest-to-rest rebuilt by Simpson from the reported A and B (SPEC §3).
  test::TrapezoidAcceleration acc{d, out["kinematics"]["a_max"].get<double>(),
                                  out["kinematics"]["a_min"].get<double>()};
  const double v_end = test::simpson_piecewise(acc, acc.knots(), 8);
  const double s_end =
      test::simpson_piecewise([&](double t) { return acc(t) * (1.0 - t); }, acc.knots(), 8);
  EXPECT_NEAR(v_end, 0.0, 1e-12);
  EXPECT_NEAR(s_end, 0.8, 1e-12);

  // Spectrum: 512 points from 0 to 5 f1; amplitudes equal the quadrature of the rebuilt law.
  const auto& sp = out["spectrum"];
  ASSERT_EQ(sp["f_hz"].size(), 512u);
  ASSERT_EQ(sp["amplitude"].size(), 512u);
  const double f1 = out["model"]["f_hz"][0].get<double>();
  EXPECT_DOUBLE_EQ(sp["markers"]["f1_hz"].get<double>(), f1);
  EXPECT_NEAR(sp["f_hz"][511].get<double>(), 5.0 * f1, 1e-12);
  EXPECT_NEAR(sp["markers"]["band_hz"][0].get<double>(), 0.85 * f1, 1e-12);
  EXPECT_NEAR(sp["markers"]["band_hz"][1].get<double>(), 1.15 * f1, 1e-12);
  for (int k : {0, 37, 102, 300, 511}) {
    const double w = 2.0 * std::numbers::pi * sp["f_hz"][k].get<double>();
    const auto X = test::simpson_piecewise(
        [&](double t) { return acc(t) * std::exp(std::complex<double>(0.0, -w * t)); }, acc.knots(),
        2000);
    EXPECT_NEAR(sp["amplitude"][k].get<double>(), std::abs(X), 1e-9) << k;
  }
  // The multi_notch amplitudes at the three notches are far below the baseline's.
  const double x1_base =
      std::abs(seven_segment_spectrum(uniform_durations(1.0), 0.8, 2.0 * std::numbers::pi * f1));
  for (double fn : {0.85 * f1, f1, 1.15 * f1}) {
    const double x = std::abs(seven_segment_spectrum(d, 0.8, 2.0 * std::numbers::pi * fn));
    EXPECT_LT(x, 0.05 * x1_base) << fn;
  }
  // Reductions are those of the reported predictions.
  const double bm = out["baseline"]["nonlinear"]["eta_motion_mm"].get<double>();
  const double pm = out["prediction"]["nonlinear"]["eta_motion_mm"].get<double>();
  EXPECT_NEAR(out["reduction_pct"]["motion"].get<double>(), 100.0 * (1.0 - pm / bm), 1e-9);
  EXPECT_GT(out["reduction_pct"]["rest"].get<double>(), 50.0);
  EXPECT_EQ(out["solver"]["name"], "nlopt-slsqp");
  EXPECT_GT(out["solver"]["starts"].get<int>(), 1);
}

TEST(PlanResponse, SamplePeriodAddsTheSeriesOfThePlannedLaw) {
  json body = thesis_plan("notch");
  body["sample_period_s"] = 0.01;
  const json out = run_plan(parse_plan_request(body));
  ASSERT_TRUE(out.contains("series"));
  EXPECT_EQ(out["series"]["t_s"].size(), 201u);
  EXPECT_NEAR(out["series"]["s"][100].get<double>(), 0.8, 1e-12);  // t = T: the stroke
  // The largest sampled |eta| cannot exceed the located peak.
  double peak = 0.0;
  for (std::size_t k = 0; k <= 100; ++k) {
    peak = std::max(peak, std::abs(out["series"]["eta_nonlinear_mm"][k].get<double>()));
  }
  EXPECT_LE(peak, out["prediction"]["nonlinear"]["eta_motion_mm"].get<double>() * (1 + 1e-12));
}

TEST(PlanResponse, AutoListsItsCandidates) {
  const json out = run_plan(parse_plan_request(thesis_plan("auto")));
  ASSERT_TRUE(out.contains("candidates"));
  ASSERT_EQ(out["candidates"].size(), 7u);
  int chosen = 0;
  for (const auto& c : out["candidates"]) {
    if (c["chosen"].get<bool>()) {
      ++chosen;
      EXPECT_EQ(c["durations_s"], out["durations_s"]);
      EXPECT_EQ(c["law_type"], out["law"]["type"]);
    }
  }
  EXPECT_EQ(chosen, 1);
}

}  // namespace test_plan_api
}  // namespace slosh::api
