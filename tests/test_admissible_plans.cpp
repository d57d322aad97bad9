// Every law a plan returns is one the law parser of `simulate` and `export` accepts ({"format",
// "law": plan.law} re-simulates any plan), checked over seeded random short moves where the
// optimised ramps sit on min_ramp_s; the fallback law of a filter strategy with no law; the
// baseline guard against the law `baseline` actually returns; and the sentences that promise
// something (time_domain's infeasibility, notch's depth), each against a computation made here.

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <string>
#include <vector>

#include "slosh/api/error.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "support/random_format.hpp"
#include "support/reference_optimum.hpp"

namespace slosh {
namespace test_admissible_plans {

using nlohmann::json;

json format_json(double radius_mm, double fill_mm, double stroke_mm, double motion_time) {
  return {{"container", {{"radius_mm", radius_mm}}},
          {"fill_height_mm", fill_mm},
          {"fluid", "water"},
          {"stroke_mm", stroke_mm},
          {"motion_time_s", motion_time}};
}

json plan_of(const json& format, const std::string& strategy, const json& options) {
  json body{{"format", format}, {"strategy", strategy}};
  if (!options.empty()) body["options"] = options;
  return api::run_plan(api::parse_plan_request(body));
}

/// The left-to-right sum of the durations, as the law is built from them.
double sum_of(const std::vector<double>& d) {
  double sum = 0.0;
  for (double x : d) sum += x;
  return sum;
}

/// The rules of motion-laws.md checked here, exactly (no slack): ramps >= min_ramp, plateaus >=
/// their minimums, no cruise under fix_constant_velocity_zero, the sum T to 1e-9 s.
std::string broken_rule(const std::vector<double>& d, double T, double min_ramp,
                        const std::array<double, 2>& plateau_min, bool no_cruise) {
  for (std::size_t i : {0U, 2U, 4U, 6U}) {
    if (d[i] < min_ramp) return "ramp " + std::to_string(i) + " below min_ramp";
  }
  if (d[1] < plateau_min[0] || d[5] < plateau_min[1]) return "plateau below its minimum";
  if (d[3] < 0.0 || (no_cruise && d[3] != 0.0)) return "cruise";
  if (std::abs(sum_of(d) - T) > 1e-9) return "sum";
  return {};
}

/// Re-simulates the plan's law as a client would; empty when the parser accepts it, else its
/// message.
std::string resimulation_refusal(const json& format, const json& plan, double min_ramp) {
  json body{{"format", format}, {"law", plan["law"]}, {"options", {{"min_ramp_s", min_ramp}}}};
  try {
    (void)api::parse_simulate_request(body);
  } catch (const api::ApiError& e) {
    return e.what();
  }
  return {};
}

// ---- close_sum ---------------------------------------------------------------------------------

// A 4-ramp law on min_ramp with a short cruise: the rounding of the partial sums often leaves no
// cruise value whose left-to-right sum is T, and the ulps used to go onto a ramp on its bound.
TEST(CloseSum, KeepsEverySegmentInsideItsBoundsAndTheSumExact) {
  std::mt19937_64 rng(2211);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int cruise_alone_fails = 0, inexact = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const double ramp = 0.03 + 0.05 * u(rng);
    const double T = 4.0 * ramp + 0.1 * u(rng);
    const Durations lower{ramp, 0.0, ramp, 0.0, ramp, 0.0, ramp};
    Durations upper;
    upper.fill(T);
    Durations d{ramp, 0.0, ramp, T - 4.0 * ramp, ramp, 0.0, ramp};
    // Whether any cruise within 64 ulps of the start closes the sum on its own.
    bool alone = false;
    double c = d[3];
    for (int k = 0; k < 64; ++k) c = std::nextafter(c, 0.0);
    for (int k = 0; k < 128 && !alone; ++k, c = std::nextafter(c, 1.0)) {
      alone = sum_of({ramp, 0.0, ramp, c, ramp, 0.0, ramp}) == T;
    }
    if (!alone) ++cruise_alone_fails;
    close_sum(d, T, 3, lower, upper);
    const std::vector<double> v(d.begin(), d.end());
    for (std::size_t i = 0; i < kSegments; ++i) {
      ASSERT_GE(d[i], lower[i]) << "trial " << trial << " segment " << i;
      ASSERT_LE(d[i], upper[i]) << "trial " << trial << " segment " << i;
    }
    EXPECT_EQ(d[1], 0.0);
    EXPECT_EQ(d[5], 0.0);
    // Exact but for a rare rounding no move of a few ulps closes: then within 2 ulps of T.
    EXPECT_LE(std::abs(sum_of(v) - T), 2.0 * (std::nextafter(T, 1.0) - T)) << "trial " << trial;
    inexact += sum_of(v) != T;
  }
  // The campaign meets the case the cruise alone cannot close, and closes nearly all of them.
  EXPECT_GT(cruise_alone_fails, 100);
  EXPECT_LE(inexact, 30);
}

// ---- every returned law re-simulates -----------------------------------------------------------

struct ShortMove {
  json format;
  double T{};
  json options = json::object();
  double min_ramp{0.05};
  std::array<double, 2> plateau_min{0.0, 0.0};
  bool no_cruise{false};
};

/// The reported cases: notch at 100 mm in 0.21 s gave a first ramp of 0.04999999999999999 s;
/// baseline with plateau minimums and no cruise gave 0.059999999999999984 s.
std::vector<ShortMove> reported_moves() {
  ShortMove a{format_json(48.5, 82, 100, 0.21), 0.21};
  ShortMove b{format_json(48.5, 82, 500, 0.41), 0.41};
  b.options = {
      {"plateau_min_s", {0.1, 0.07}}, {"fix_constant_velocity_zero", true}, {"min_ramp_s", 0.06}};
  b.min_ramp = 0.06;
  b.plateau_min = {0.1, 0.07};
  b.no_cruise = true;
  return {a, b};
}

/// Seeded short moves: T a little above what the ramp and plateau minimums need, so the optima
/// sit on those bounds.
std::vector<ShortMove> random_moves(int count) {
  std::mt19937_64 rng(4077);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<ShortMove> out;
  for (int k = 0; k < count; ++k) {
    ShortMove m;
    m.min_ramp = k % 3 == 0 ? 0.05 : (k % 3 == 1 ? 0.06 : 0.04);
    if (k % 4 == 1) m.plateau_min = {0.1 * u(rng), 0.1 * u(rng)};
    m.no_cruise = k % 5 == 2;
    const double floor = 4.0 * m.min_ramp + m.plateau_min[0] + m.plateau_min[1];
    const double room = 0.25 * u(rng) * u(rng);
    m.T = std::round((floor + room) * 1e4) / 1e4 + 1e-4;
    const double R = 20.0 + 60.0 * u(rng);
    m.format = format_json(std::round(R * 10) / 10, std::round(R * (0.5 + 1.5 * u(rng))),
                           std::round(50.0 + 750.0 * u(rng)), m.T);
    m.options = {{"min_ramp_s", m.min_ramp},
                 {"plateau_min_s", {m.plateau_min[0], m.plateau_min[1]}},
                 {"fix_constant_velocity_zero", m.no_cruise}};
    out.push_back(m);
  }
  return out;
}

TEST(AdmissiblePlans, EveryReturnedLawResimulatesOverRandomShortMoves) {
  std::vector<ShortMove> moves = reported_moves();
  const std::vector<ShortMove> random = random_moves(test::property_format_count(24));
  moves.insert(moves.end(), random.begin(), random.end());
  int on_min_ramp = 0;
  for (std::size_t k = 0; k < moves.size(); ++k) {
    const ShortMove& m = moves[k];
    std::vector<std::string> strategies{"baseline",  "notch", "multi_notch", "min_jerk_band",
                                        "fir_chain", "iir",   "shaper"};
    if (k % 4 == 0) strategies.emplace_back("time_domain");
    for (const std::string& strategy : strategies) {
      SCOPED_TRACE(strategy + " " + m.format.dump() + " " + m.options.dump());
      const json plan = plan_of(m.format, strategy, m.options);
      ASSERT_TRUE(plan.contains("law")) << plan.dump().substr(0, 300);
      if (plan["durations_s"].is_array()) {  // null for a general law
        const auto d = plan["durations_s"].get<std::vector<double>>();
        ASSERT_EQ(d.size(), 7U);
        EXPECT_EQ(broken_rule(d, m.T, m.min_ramp, m.plateau_min, m.no_cruise), "")
            << plan["status"] << " " << plan["durations_s"].dump();
        on_min_ramp += d[0] == m.min_ramp || d[6] == m.min_ramp;
      }
      EXPECT_EQ(resimulation_refusal(m.format, plan, m.min_ramp), "") << plan["status"];
    }
  }
  // The campaign exercises ramps on their bound, where the last ulps used to break them.
  EXPECT_GT(on_min_ramp, 20);
}

// A law an ulp outside the rules is refused with its value in enough digits to show why.
TEST(AdmissiblePlans, TheRefusalOfARampAnUlpShortQuotesTheValueThatBreaksTheRange) {
  const json body{
      {"format", format_json(48.5, 82, 100, 0.21)},
      {"law",
       {{"type", "seven_segment"},
        {"durations_s",
         {0.04999999999999999, 0.0, 0.05, 0.00999999999999999, 0.05, 0.0, 0.05000000000000001}}}}};
  try {
    (void)api::parse_simulate_request(body);
    ADD_FAILURE() << "accepted";
  } catch (const api::ApiError& e) {
    EXPECT_EQ(e.field(), "law.durations_s[0]");
    EXPECT_STREQ(e.what(),
                 "law.durations_s[0] = 0.04999999999999999 is out of range: allowed 0.05 to 0.21 "
                 "s (segment 1 is a jerk ramp: >= options.min_ramp_s)");
  }
}

// ---- a filter strategy without a law -----------------------------------------------------------

TEST(AdmissiblePlans, AFilterWithoutALawReturnsBaselinesAdmissibleLaw) {
  // T3 (0.326 s) > T = 0.21 s: no fir_chain; the iir's delay and the shaper's need more than T
  // in the second format. The uniform law's ramps (T/7 = 0.03 s) break min_ramp_s = 0.05 s.
  const json short_move = format_json(48.5, 82, 100, 0.21);
  const json long_stroke = format_json(82.7, 124.9, 803, 0.207);
  for (const auto& [format, strategy] : std::vector<std::pair<json, std::string>>{
           {short_move, "fir_chain"}, {short_move, "iir"}, {long_stroke, "shaper"}}) {
    SCOPED_TRACE(strategy);
    const json plan = plan_of(format, strategy, json::object());
    EXPECT_EQ(plan["status"], "infeasible");
    ASSERT_TRUE(plan["durations_s"].is_array()) << plan.dump().substr(0, 300);
    // Every segment at its minimum plus an equal share of what remains.
    const double T = format["motion_time_s"].get<double>();
    const double share = (T - 4.0 * 0.05) / 7.0;
    const auto d = plan["durations_s"].get<std::vector<double>>();
    for (std::size_t i = 0; i < 7; ++i) {
      EXPECT_NEAR(d[i], (i % 2 == 0 ? 0.05 : 0.0) + share, 1e-15) << i;
    }
    EXPECT_EQ(broken_rule(d, T, 0.05, {0.0, 0.0}, false), "");
    EXPECT_EQ(resimulation_refusal(format, plan, 0.05), "");
    EXPECT_NE(plan["message"].get<std::string>().find(
                  "; the law returned is baseline's (the uniform law breaks the options: every "
                  "segment at its minimum plus an equal share), not a solution"),
              std::string::npos)
        << plan["message"];
  }
}

// ---- the baseline guard ------------------------------------------------------------------------

bool above(const json& p, const json& b, const char* model, const char* figure) {
  const double v = p[model][figure].get<double>(), base = b[model][figure].get<double>();
  return v > 1.05 * base && v > base + 0.5;  // mm
}

bool worse_than(const json& p, const json& b) {
  return above(p, b, "nonlinear", "eta_motion_mm") || above(p, b, "nonlinear", "eta_rest_mm") ||
         above(p, b, "linear", "eta_motion_mm") || above(p, b, "linear", "eta_rest_mm");
}

bool has_worse_warning(const json& warnings) {
  for (const json& w : warnings) {
    if (w.get<std::string>().rfind("worse_than_baseline: ", 0) == 0) return true;
  }
  return false;
}

TEST(AdmissiblePlans, TheBaselineGuardComparesWithTheLawBaselineReturns) {
  // The uniform law (0.03 s ramps) breaks min_ramp_s: baseline returns another law, which
  // sloshes more than notch's here (80.2 vs 78.4 mm linear eta_motion).
  const json format = format_json(48.5, 82, 100, 0.21);
  const json baseline = plan_of(format, "baseline", json::object());
  // Its prediction as a client gets it: simulate of its law.
  const json simulated = api::run_simulate(
      api::parse_simulate_request({{"format", format}, {"law", baseline["law"]}}));
  const json& reference = simulated["prediction"];
  const json plan = plan_of(format, "auto", json::object());
  int flagged = 0, not_flagged = 0;
  for (const json& cand : plan["candidates"]) {
    SCOPED_TRACE(cand["strategy"].get<std::string>());
    const bool worse = worse_than(cand["prediction"], reference);
    EXPECT_EQ(has_worse_warning(cand["warnings"]), worse) << cand["warnings"].dump();
    (worse ? flagged : not_flagged) += 1;
    if (cand["strategy"] == "notch") {
      EXPECT_FALSE(worse);
      EXPECT_LT(cand["prediction"]["linear"]["eta_motion_mm"].get<double>(),
                reference["linear"]["eta_motion_mm"].get<double>());
    }
    if (worse) {
      EXPECT_NE(cand["warnings"].dump().find(
                    " for baseline's law (more than 5 % and 0.5 mm above it; the uniform law "
                    "breaks the options, so baseline's law is every segment at its minimum plus "
                    "an equal share); strategy baseline sloshes less there"),
                std::string::npos);
    }
  }
  EXPECT_GT(flagged, 0);
  EXPECT_GT(not_flagged, 2);
  // The sentence of the choice names baseline's law, unless no candidate reaches the default
  // eta_rest <= 3 mm (auto then returns the least infeasible law and says that instead).
  const std::string message = plan["message"];
  if (message.find("no candidate meets eta_rest <= 3 mm") == std::string::npos) {
    EXPECT_NE(message.find("none worse than baseline's law (the uniform law breaks the options))"),
              std::string::npos)
        << message;
  }
}

// ---- sentences that promise something ----------------------------------------------------------

TEST(AdmissiblePlans, TimeDomainNamesTheOptionsThatLeaveOneLawNotMachineLimits) {
  // No limits given; 4 x min_ramp_s = T: the only admissible law is the four ramps.
  const json plan = plan_of(format_json(50, 80, 100000, 0.2), "time_domain", json::object());
  EXPECT_EQ(plan["status"], "infeasible");
  const std::string message = plan["message"];
  EXPECT_EQ(
      message.rfind("no law found that meets eta_rest <= 3 mm in 0.2 s: the best found is ", 0), 0U)
      << message;
  EXPECT_NE(message.find(" starts) (4 x min_ramp_s = 0.2 s plus the plateau minimums fill the "
                         "motion time: one admissible law); lengthen the motion or relax the "
                         "limit; the durations returned are the least infeasible found, not a "
                         "solution."),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find("machine limits"), std::string::npos) << message;
  EXPECT_EQ(plan["durations_s"], json::parse("[0.05, 0.0, 0.05, 0.0, 0.05, 0.0, 0.05]"));
}

TEST(AdmissiblePlans, TimeDomainsLeastInfeasibleLawKeepsAReachableAccelerationLimit) {
  // notch meets a_max = 3.6 m/s^2 here (the least reachable is 3.56): the uniform law (A = 4.9)
  // is a start of time_domain's search but no candidate for its least infeasible law.
  const json format = format_json(48.5, 82, 800, 1.0);
  const json options = {{"limits", {{"a_max", 3.6}}}};
  const json notch = plan_of(format, "notch", options);
  // Its law keeps the limit but leaves more at rest than the uniform law: acceptable.
  ASSERT_EQ(notch["status"], "acceptable") << notch["message"];
  const json plan = plan_of(format, "time_domain", options);
  test::SevenDurations d;
  for (std::size_t i = 0; i < 7; ++i) d[i] = plan["durations_s"][i].get<double>();
  const test::Plateaus levels = test::reference_plateaus(d, 0.8);
  EXPECT_LE(std::max(levels.A, levels.B), 3.6 * (1.0 + 1e-6)) << plan["message"];
  EXPECT_EQ(plan["message"].get<std::string>().find("exceeds limits.a_max"), std::string::npos)
      << plan["message"];
}

TEST(AdmissiblePlans, NotchsDepthSentenceHoldsForTheModulus) {
  // |X(w1)| of the returned law in closed form (tests/support) over X_ref, the uniform law's
  // largest |X| on the band (1 +- 0.15) w1.
  std::mt19937_64 rng(913);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int exact = 0;
  for (int k = 0; k < 6; ++k) {
    const double R = std::round(30.0 + 40.0 * u(rng)), h = std::round(R * (0.8 + u(rng)));
    const double s = std::round(300.0 + 500.0 * u(rng)) * 1e-3;
    const double T = std::round((0.8 + 0.6 * u(rng)) * 1e3) / 1e3;
    const json plan = plan_of(format_json(R, h, s * 1e3, T), "notch", json::object());
    const std::string message = plan["message"];
    if (message.find("exact notch") == std::string::npos) continue;
    ++exact;
    EXPECT_NE(message.find("notch optimal: exact notch at f1 (|Re X(w1)|, |Im X(w1)| <= 1e-6 of "
                           "X_ref, so |X(w1)| <= 1.42e-6 of X_ref), the one with the least jerk "
                           "integral among the zeros ("),
              std::string::npos)
        << message;
    test::SevenDurations d;
    for (std::size_t i = 0; i < 7; ++i) d[i] = plan["durations_s"][i].get<double>();
    test::SpectralProblem p;
    p.stroke = s;
    p.T = T;
    p.omega1 = plan["model"]["omega_rad_s"][0].get<double>();
    const double x_ref = test::reference_x_ref(p);
    const double depth = std::abs(test::reference_spectrum(d, s, p.omega1)) / x_ref;
    EXPECT_LE(depth, 1.42e-6) << message;
  }
  EXPECT_GE(exact, 3);
}

}  // namespace test_admissible_plans
}  // namespace slosh
