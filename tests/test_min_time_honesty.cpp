// Min-time's verdicts checked against plans made on their own: every T the search calls
// infeasible is infeasible when planned as a plan request plans it (the planner's own starts, no
// warm start: POST /v1/plans), every T it calls feasible is feasible from the start it records,
// T_min's plan meets the limits, and a plan budget that runs out on the curve gives an answer
// that says the curve is partial.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "slosh/api/min_time.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/strategy/min_time.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/min_time_checks.hpp"
#include "support/random_format.hpp"

namespace slosh {
namespace test_min_time_honesty {

using nlohmann::json;

/// The docs' request (docs/min-time.md): the thesis container, free board 68 mm, eta_rest 3 mm.
json thesis_min_time_request() {
  return json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": {"density_kg_m3": 1000, "viscosity_pa_s": 0.001}, "stroke_mm": 800},
    "free_board_margin_mm": 0, "eta_rest_max_mm": 3, "strategies": ["time_domain"]
  })");
}

/// A strategy's answer found its T_min: `optimal`, or `acceptable` because its plan at T_min is
/// not optimal by its own warnings (SPEC §5: on the thesis container with eta_motion <= the free
/// board on the nonlinear model, the linear model's wave at T_min can spill), which the message
/// then leads with and the plan's status shows.
::testing::AssertionResult found_t_min(const json& s) {
  const std::string status = s.at("status");
  if (status == "optimal") return ::testing::AssertionSuccess();
  if (status == "acceptable" &&
      s.at("message").get<std::string>().starts_with("not optimal: the plan at T_min is not (") &&
      s.at("plan").at("status") == "acceptable") {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << status << ": " << s.at("message");
}

using test::found_t_min;

/// POST /v1/plans at T in process: the same format, strategy and limits, no warm start.
json direct_plan(const json& min_time_request, const std::string& strategy, double T) {
  json body{{"format", min_time_request.at("format")},
            {"strategy", strategy},
            {"options", {{"robustness", false}}}};
  body["format"]["motion_time_s"] = T;
  return api::run_plan(api::parse_plan_request(body));
}

/// A plan response meets the limits [mm] on the nonlinear model, within the planner's 1e-6.
bool plan_feasible(const json& plan, double eta_motion_max_mm, double eta_rest_max_mm) {
  const std::string status = plan.at("status");
  const json& nl = plan.at("prediction").at("nonlinear");
  return (status == "optimal" || status == "acceptable") &&
         nl.at("eta_motion_mm").get<double>() <= eta_motion_max_mm * (1.0 + 1e-6) &&
         nl.at("eta_rest_mm").get<double>() <= eta_rest_max_mm * (1.0 + 1e-6);
}

// The docs' request: time_domain's scan point 0.640 s, warm-started from the 0.600 s law, once
// followed a branch with eta_rest 43 mm and was called infeasible ("feasibility is not monotone"),
// while a plan request at 0.640 s holds 66.0 / 3.00 mm. Every point of the curve is held against
// the plan request at its T.
TEST(MinTimeHonesty, ThesisTimeDomainCurveAgreesWithPlanRequestsAtTheSameT) {
  const json request = thesis_min_time_request();
  const json answer = api::run_min_time(api::parse_min_time_request(request, 600.0));
  const json& s = answer.at("strategies").at(0);
  ASSERT_TRUE(found_t_min(s));
  const double t_min = s.at("t_min_s");
  EXPECT_EQ(s.at("feasible_above"), true) << s.at("message");
  EXPECT_EQ(s.at("message").get<std::string>().find("not monotone"), std::string::npos)
      << s.at("message");
  // T_min's plan (the one the answer carries) meets the limits.
  EXPECT_TRUE(plan_feasible(s.at("plan"), 68.0, 3.0));
  EXPECT_NEAR(s.at("plan").at("format").at("motion_time_s").get<double>(), t_min, 1e-9);
  const json& curve = s.at("curve");
  bool saw_640 = false;
  for (std::size_t i = 0; i < curve.at("t_s").size(); ++i) {
    const double T = curve.at("t_s").at(i);
    const bool feasible = curve.at("feasible").at(i);
    SCOPED_TRACE("T = " + std::to_string(T));
    const json direct = direct_plan(request, "time_domain", T);
    if (!feasible) {
      EXPECT_FALSE(plan_feasible(direct, 68.0, 3.0));
    }
    if (std::abs(T - 0.640) < 1e-9) {
      saw_640 = true;
      EXPECT_TRUE(feasible);
      EXPECT_TRUE(plan_feasible(direct, 68.0, 3.0));
      // The point is the plan request's plan: the same figures.
      EXPECT_NEAR(curve.at("nonlinear").at("eta_motion_mm").at(i).get<double>(),
                  direct.at("prediction").at("nonlinear").at("eta_motion_mm").get<double>(), 1e-6);
    }
  }
  EXPECT_TRUE(saw_640);  // 0.640 s is a scan point (0.2 s + 11 steps of 40 ms)
}

/// The thesis container with its 150 mm height.
Format thesis_container() {
  Format f = thesis_format();
  f.container.height = 0.150;
  return f;
}

struct Judged {
  bool feasible{false};
  double excess{};
};

/// plan() of T with the search's limits, from `warm_start` (none: the planner's own starts).
Judged judge(const Format& format, Strategy strategy, const MinTimeOptions& o,
             const MinTimeResult& r, double T, const std::optional<Durations>& warm_start) {
  Format f = format;
  f.motion_time = T;
  PlanOptions po = o.plan;
  po.warm_start = warm_start;
  po.eta_rest_max = r.eta_rest_max;
  po.eta_motion_max = r.eta_motion_max;
  po.robustness = false;
  po.time_limit = 60.0;
  const PlanResult p = plan(f, strategy, po);
  const bool usable = p.status == SolveStatus::kOptimal || p.status == SolveStatus::kAcceptable;
  const double excess = std::max(p.prediction.nonlinear.motion.value / r.eta_motion_max,
                                 p.prediction.nonlinear.rest.value / r.eta_rest_max);
  return {usable && excess <= 1.0 + 1e-6, excess};
}

// Property over seeded random formats near the benchmark one (the thesis container, free board
// 68 mm or 63 mm; then stroke +-20 mm, fill +-4 mm, radius +-1.5 mm): every curve point the search
// calls infeasible is infeasible from the planner's own starts; every point it calls feasible is
// feasible from the start it records (plan() reproduces it); T_min's plan meets the limits; and a
// search costs at most 30 plans. time_domain, whose plans are local optima that depend on their
// start, and min_jerk_band.
TEST(MinTimeHonesty, CurveVerdictsAgreeWithDirectPlansOnSeededRandomFormats) {
  const int count = test::property_format_count(5);
  for (int k = 0; k < count; ++k) {
    std::mt19937 rng(static_cast<unsigned>(2026 + k));
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Format f = thesis_container();
    MinTimeOptions o;
    o.plan.time_limit = 60.0;
    o.free_board_margin = k == 1 ? 0.005 : 0.0;
    if (k >= 2) {
      f.stroke = 0.8 + 0.02 * u(rng);
      f.fill_height = 0.082 + 0.004 * u(rng);
      f.container.radius = 0.0485 + 0.0015 * u(rng);
      o.free_board_margin = rng() % 2 == 0 ? 0.0 : 0.005;
    }
    for (Strategy s : {Strategy::kTimeDomain, Strategy::kMinJerkBand}) {
      SCOPED_TRACE("format " + std::to_string(k) + " " + to_string(s) + " stroke " +
                   std::to_string(f.stroke));
      const MinTimeResult r = min_time(f, s, o);
      ASSERT_TRUE(found_t_min(r));
      EXPECT_LE(r.plans, 30);
      ASSERT_TRUE(r.plan);
      EXPECT_LE(r.plan->prediction.nonlinear.motion.value, r.eta_motion_max * (1.0 + 1e-6));
      EXPECT_LE(r.plan->prediction.nonlinear.rest.value, r.eta_rest_max * (1.0 + 1e-6));
      for (const MinTimePoint& p : r.curve) {
        SCOPED_TRACE("T = " + std::to_string(p.motion_time));
        if (p.feasible) {
          EXPECT_TRUE(judge(f, s, o, r, p.motion_time, p.warm_start).feasible);
        } else {
          const Judged fresh = judge(f, s, o, r, p.motion_time, std::nullopt);
          EXPECT_FALSE(fresh.feasible) << "excess " << fresh.excess;
        }
      }
    }
  }
}

/// The catalogue-water request of the hostile review: the examples/min-time.json format with a
/// stroke 0.2 um longer, the default margin (eta_motion <= 63 mm), time_domain.
json nearby_stroke_request() {
  return json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800.0002},
    "strategies": ["time_domain"]
  })");
}

// The search once spent all 40 plans on this stroke (a warm start's branch with eta_rest 43 mm at
// 0.640 s made a false local minimum to refine and stalled the regula falsi) and still answered
// optimal with a curve cut at 0.779 s.
TEST(MinTimeHonesty, AStrokeNextToTheBenchmarkIsSearchedWithinThirtyPlans) {
  const json answer =
      api::run_min_time(api::parse_min_time_request(nearby_stroke_request(), 600.0));
  const json& s = answer.at("strategies").at(0);
  ASSERT_TRUE(found_t_min(s));
  EXPECT_LE(s.at("plans").get<int>(), 30);
  const double t_min = s.at("t_min_s");
  const json& t = s.at("curve").at("t_s");
  EXPECT_NEAR(t.back().get<double>(), std::round(1.5 * t_min * 1000.0) / 1000.0, 1.5e-3);
  EXPECT_EQ(s.at("feasible_above"), true);
}

// The plan budget running out after T_min was bracketed, on the curve above it: time_limit, T_min
// kept with its 1 ms bracket, feasible_above unknown, and the message says the curve is partial.
TEST(MinTimeHonesty, APlanBudgetThatEndsTheCurveGivesTimeLimitAndAPartialCurve) {
  const json full = api::run_min_time(api::parse_min_time_request(nearby_stroke_request(), 600.0));
  const json& whole = full.at("strategies").at(0);
  ASSERT_TRUE(found_t_min(whole));
  json request = nearby_stroke_request();
  // One plan fewer than the whole search: the search is deterministic, so it runs out on its last
  // plan, a point of the curve above T_min.
  request["max_plans"] = whole.at("plans").get<int>() - 1;
  const json answer = api::run_min_time(api::parse_min_time_request(request, 600.0));
  const json& s = answer.at("strategies").at(0);
  EXPECT_EQ(s.at("status"), "time_limit");
  EXPECT_EQ(s.at("plans"), request["max_plans"]);
  EXPECT_EQ(s.at("t_min_s"), whole.at("t_min_s"));
  EXPECT_NEAR(s.at("infeasible_below_s").get<double>(), s.at("t_min_s").get<double>() - 1e-3, 1e-9);
  EXPECT_TRUE(s.at("feasible_above").is_null());
  const std::string message = s.at("message");
  EXPECT_NE(message.find("the search's plan budget (max_plans " +
                         std::to_string(request["max_plans"].get<int>()) +
                         ", all planned; raise max_plans) ran out at T = "),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("after T_min was bracketed"), std::string::npos) << message;
  EXPECT_NE(message.find("the curve is partial"), std::string::npos) << message;
  EXPECT_LT(s.at("curve").at("t_s").back().get<double>(),
            whole.at("curve").at("t_s").back().get<double>());
  // T_min is final: the headline still names it.
  EXPECT_EQ(answer.at("headline").at("winner"), "time_domain");
  EXPECT_EQ(answer.at("headline").at("t_min_s"), whole.at("t_min_s"));
  EXPECT_EQ(answer.at("headline").at("t_min_is_bound"), false);
}

// A search its plan budget cut holds a bound whose plan is judged as a T_min's: on the README's
// cup along its axis every T_min plan's limits were met on the linear figures standing in for the
// nonlinear model (nonlinear_model_not_valid), and min_jerk_band's bound of 1.08 s, with that
// caveat too, won the headline as the one honest T (-41.9 % against the uniform law's 0.761 s)
// over time_domain's 0.618 s.
TEST(MinTimeHonesty, ABoundWithTheLinearFiguresStandingInDoesNotWinTheHeadline) {
  const json request = json::parse(R"({
    "format": {"container": {"shape": "rectangular", "length_mm": 120, "width_mm": 80,
               "height_mm": 70, "orientation_deg": 0},
               "fill_height_mm": 40, "fluid": "water", "stroke_mm": 200},
    "strategies": ["notch", "multi_notch", "min_jerk_band", "fir_chain", "shaper",
                   "time_domain", "baseline"]})");
  const json answer = api::run_min_time(api::parse_min_time_request(request, 600.0));
  const json& headline = answer.at("headline");
  double least = 1e9;
  for (const json& s : answer.at("strategies")) {
    if (s.at("strategy") == "baseline" || s.at("t_min_s").is_null()) continue;
    least = std::min(least, s.at("t_min_s").get<double>());
    if (s.at("strategy") == "min_jerk_band" && s.at("status") == "time_limit") {
      EXPECT_NE(s.at("message").get<std::string>().find("so its linear figures stood in"),
                std::string::npos)
          << s.at("message");
    }
  }
  EXPECT_EQ(headline.at("t_min_s").get<double>(), least) << headline.dump();
  EXPECT_GT(headline.at("gain_pct").get<double>(), 0.0) << headline.dump();
  EXPECT_NE(headline.at("not_optimal").get<std::string>().find("nonlinear_model_not_valid"),
            std::string::npos)
      << headline.dump();
}

}  // namespace test_min_time_honesty
}  // namespace slosh
