// The API side (SPEC §10): options.robustness and options.uncertainty through a real
// `slosh serve` on loopback, the plan's robustness, uncertainty and worst_case blocks, the compact
// view, the batch columns, and every refusal with its exact text and field.
//
// The numbers are checked against computations written here, never against the code under test:
//  - the sweep's points: the plan's law stretched in time by (1 + delta) (durations, motion time
//    and rest window x (1 + delta), same stroke) simulated on the nominal model through
//    POST /v1/simulate, which is the law on a model with every mode frequency x (1 + delta)
//    (t -> (1 + delta) t turns one equation into the other);
//  - the delta grid, f1 (sqrt(g xi1 / R tanh(xi1 h / R))), the holding interval (linear
//    interpolation of the margin between the last point that holds and the first that does not),
//    the worst values, the uncertainty's omega_1 and zeta ranges (the thesis correlation written
//    out) and the widened band's lower edge f_lo - band f_hi.

#include <httplib.h>
#include <limits>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/option_registry.hpp"
#include "slosh/api/plan.hpp"
#include "support/process.hpp"
#include "support/rfc4180.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_robustness_api {

using nlohmann::json;

constexpr double kPi = std::numbers::pi;
constexpr double kGravity = 9.81;     // [m/s^2], the model's
constexpr double kXi1 = 1.841184;     // first root of J1', as the model takes it
constexpr double kSlack = 1e-6;       // a limit met within the verification's round-off
constexpr double kStretchTol = 1e-4;  // relative agreement of the re-simulated points

// ---- requests ---------------------------------------------------------------------------------

json thesis_format() {
  return json::parse(R"({"container": {"radius_mm": 48.5, "height_mm": 150},
                         "fill_height_mm": 82, "fluid": "water",
                         "stroke_mm": 800, "motion_time_s": 1.0})");
}

json plan_body(const std::string& strategy, const json& options = json::object()) {
  return {{"format", thesis_format()}, {"strategy", strategy}, {"options", options}};
}

json with_uncertainty(const json& uncertainty, json options = json::object()) {
  options["uncertainty"] = uncertainty;
  return options;
}

// ---- the model, written out -------------------------------------------------------------------

/// omega_1 of a cylinder of radius R with fill h [rad/s].
double omega1(double radius_m, double fill_m) {
  return std::sqrt(kGravity * kXi1 / radius_m * std::tanh(kXi1 * fill_m / radius_m));
}

/// The thesis damping correlation (eq. 2.26): 0.79 sqrt(Re1) (1 + 0.318 / sinh(1.84 h/R) (1 +
/// (1 - h/R) / cosh(1.84 h/R))), Re1 = nu / sqrt(g R^3).
double thesis_zeta(double radius_m, double fill_m, double density, double viscosity) {
  const double hr = fill_m / radius_m;
  const double re = viscosity / density / std::sqrt(kGravity * radius_m * radius_m * radius_m);
  return 0.79 * std::sqrt(re) *
         (1.0 + 0.318 / std::sinh(1.84 * hr) * (1.0 + (1.0 - hr) / std::cosh(1.84 * hr)));
}

std::string g3(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string g10(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

void expect_rel(double expected, double got, double tol, const std::string& what) {
  EXPECT_LE(std::abs(got - expected), tol * std::max(std::abs(expected), 1e-9))
      << what << ": expected " << expected << ", got " << got;
}

// ---- a real server ----------------------------------------------------------------------------

/// One `slosh serve` for the whole suite (its plans are deterministic).
std::unique_ptr<test::Server>& server() {
  static std::unique_ptr<test::Server> instance;
  return instance;
}

struct Reply {
  int status{0};
  json body;
  std::string raw;
};

Reply request(const std::string& method, const std::string& path, const json& body = nullptr) {
  auto client = server()->client();
  const auto res =
      method == "GET" ? client.Get(path) : client.Post(path, body.dump(), "application/json");
  if (!res) {
    ADD_FAILURE() << "no answer to " << method << " " << path;
    return {};
  }
  return {res->status, json::parse(res->body), res->body};
}

Reply post(const std::string& path, const json& body) {
  return request("POST", path, body);
}

/// The plan of `body` (memoised: plans are deterministic and several tests share them).
const json& plan_of(const json& body) {
  static std::map<std::string, json> plans;
  const std::string text = body.dump();
  auto it = plans.find(text);
  if (it == plans.end()) {
    const Reply r = post("/v1/plans", body);
    EXPECT_EQ(r.status, 200) << r.raw;
    it = plans.emplace(text, r.body).first;
  }
  return it->second;
}

class RobustnessApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!server()) server() = std::make_unique<test::Server>();
  }
  static void TearDownTestSuite() { server().reset(); }
};

// ---- independent computations of the report ---------------------------------------------------

/// The peaks of the plan's 7-segment law stretched in time by (1 + delta) on the plan's format and
/// model (damping as simulate takes it), through POST /v1/simulate.
json stretched_prediction(const json& plan, double delta, const json& damping) {
  json format = plan["format"];
  format["motion_time_s"] = format["motion_time_s"].get<double>() * (1.0 + delta);
  json durations = json::array();
  for (const json& d : plan["durations_s"]) durations.push_back(d.get<double>() * (1.0 + delta));
  const json body{{"format", format},
                  {"law", {{"type", "seven_segment"}, {"durations_s", durations}}},
                  {"rest_time_s", plan["rest_time_s"].get<double>() * (1.0 + delta)},
                  {"options",
                   {{"modes", plan["model"]["f_hz"].size()},
                    {"damping", damping},
                    {"alpha", plan["model"]["alpha"]},
                    {"min_ramp_s", 0.001}}}};
  const Reply r = post("/v1/simulate", body);
  EXPECT_EQ(r.status, 200) << r.raw;
  return r.body["prediction"];
}

/// Each of the point's four peaks equals the stretched law's within kStretchTol.
void expect_point_is_stretched_law(const json& plan, const json& point, const json& damping) {
  const double delta = point["delta_pct"].get<double>() / 100.0;
  const json sim = stretched_prediction(plan, delta, damping);
  for (const char* model : {"linear", "nonlinear"}) {
    for (const char* eta : {"eta_motion_mm", "eta_rest_mm"}) {
      expect_rel(sim[model][eta].get<double>(), point[model][eta].get<double>(), kStretchTol,
                 std::string(model) + " " + eta + " at delta " + point["delta_pct"].dump());
    }
  }
}

/// The largest eta / limit minus 1 of one model's peaks at a point.
double margin(const json& peaks, const json& sweep) {
  double m = peaks["eta_rest_mm"].get<double>() / sweep["eta_rest_max_mm"].get<double>() - 1.0;
  if (!sweep["eta_motion_max_mm"].is_null()) {
    m = std::max(
        m, peaks["eta_motion_mm"].get<double>() / sweep["eta_motion_max_mm"].get<double>() - 1.0);
  }
  return m;
}

/// The interval of delta [%] around 0 where the margins hold, its ends linearly interpolated
/// between the last point that holds and the first that does not (a sweep end when all hold).
json expected_interval(const json& points, const json& sweep, const char* model) {
  std::vector<double> d, m;
  std::size_t zero = 0;
  for (const json& p : points) {
    if (p["delta_pct"].get<double>() == 0.0) zero = d.size();
    d.push_back(p["delta_pct"].get<double>());
    m.push_back(margin(p[model], sweep));
  }
  if (m[zero] > kSlack) return nullptr;
  auto edge = [&](std::size_t in, std::size_t out) {
    const double t = std::clamp((kSlack - m[in]) / (m[out] - m[in]), 0.0, 1.0);
    return d[in] + t * (d[out] - d[in]);
  };
  std::size_t lo = zero, hi = zero;
  while (lo > 0 && m[lo - 1] <= kSlack) --lo;
  while (hi + 1 < d.size() && m[hi + 1] <= kSlack) ++hi;
  const bool lo_end = lo == 0, hi_end = hi + 1 == d.size();
  return {{"from_pct", lo_end ? d.front() : edge(lo, lo - 1)},
          {"to_pct", hi_end ? d.back() : edge(hi, hi + 1)},
          {"from_is_sweep_end", lo_end},
          {"to_is_sweep_end", hi_end}};
}

void expect_interval(const json& expected, const json& got, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(expected.is_null(), got.is_null()) << got;
  if (expected.is_null()) return;
  EXPECT_NEAR(got["from_pct"].get<double>(), expected["from_pct"].get<double>(), 1e-9);
  EXPECT_NEAR(got["to_pct"].get<double>(), expected["to_pct"].get<double>(), 1e-9);
  EXPECT_EQ(got["from_is_sweep_end"], expected["from_is_sweep_end"]);
  EXPECT_EQ(got["to_is_sweep_end"], expected["to_is_sweep_end"]);
}

/// The report's holds and worst against the points (the points themselves are checked apart).
void expect_holds_and_worst(const json& robustness) {
  const json& points = robustness["points"];
  const json& sweep = robustness["sweep"];
  for (const char* model : {"linear", "nonlinear"}) {
    expect_interval(expected_interval(points, sweep, model), robustness["holds"][model], model);
    double motion = 0.0, rest = 0.0;
    for (const json& p : points) {
      motion = std::max(motion, p[model]["eta_motion_mm"].get<double>());
      rest = std::max(rest, p[model]["eta_rest_mm"].get<double>());
      EXPECT_EQ(p[std::string("holds_") + model].get<bool>(), margin(p[model], sweep) <= kSlack);
    }
    EXPECT_EQ(robustness["worst"][model]["eta_motion_mm"].get<double>(), motion) << model;
    EXPECT_EQ(robustness["worst"][model]["eta_rest_mm"].get<double>(), rest) << model;
  }
}

// ---- the report ------------------------------------------------------------------------------

// SPEC §10: every plan carries its law swept over delta in [-10 %, +10 %] (21 points) on both
// models; each point is the law stretched in time on the nominal model, the interval and the
// worst values follow from the points.
TEST_F(RobustnessApi, APlanCarriesItsLawSweptOverTenPercent) {
  const double R = 48.5 * 1e-3, h = 82 * 1e-3;
  const double f1 = omega1(R, h) / (2.0 * kPi);
  for (const char* strategy : {"time_domain", "multi_notch"}) {
    SCOPED_TRACE(strategy);
    const json& plan = plan_of(plan_body(strategy));
    ASSERT_TRUE(plan.contains("robustness")) << plan.dump().substr(0, 300);
    EXPECT_FALSE(plan.contains("uncertainty"));
    EXPECT_FALSE(plan.contains("worst_case"));
    expect_rel(f1, plan["model"]["f_hz"][0].get<double>(), 1e-12, "f1");
    const json& r = plan["robustness"];
    const json& sweep = r["sweep"];
    EXPECT_EQ(sweep["delta_pct"], json::array({-10.0, 10.0}));
    EXPECT_EQ(sweep["points"], 21);
    EXPECT_EQ(sweep["zeta"], plan["model"]["zeta"]);
    EXPECT_EQ(sweep["eta_rest_max_mm"], 3.0);
    EXPECT_TRUE(sweep["eta_motion_max_mm"].is_null());
    EXPECT_EQ(sweep["rest_time_s"], 1.0);
    ASSERT_EQ(r["points"].size(), 21u);
    for (int k = 0; k < 21; ++k) {
      const json& p = r["points"][k];
      EXPECT_NEAR(p["delta_pct"].get<double>(), -10.0 + k, 1e-9) << k;
      expect_rel(f1 * (1.0 + (k - 10) / 100.0), p["f1_hz"].get<double>(), 1e-12,
                 "f1 at " + p.dump());
    }
    // delta = 0 is the plan's own prediction.
    const json& zero = r["points"][10];
    EXPECT_EQ(zero["delta_pct"], 0.0);
    for (const char* model : {"linear", "nonlinear"}) {
      for (const char* eta : {"eta_motion_mm", "eta_rest_mm"}) {
        EXPECT_EQ(zero[model][eta], plan["prediction"][model][eta]) << model << " " << eta;
      }
    }
    for (int k : {0, 4, 9, 10, 11, 16, 20}) {
      expect_point_is_stretched_law(plan, r["points"][k], plan["model"]["damping"]);
    }
    expect_holds_and_worst(r);
  }
  // What SPEC §10 says of the thesis time_domain plan: its eta_rest bound of 3 mm is lost below
  // omega_1 (above 5 mm at -10 %), so its nonlinear interval ends inside the sweep.
  const json& td = plan_of(plan_body("time_domain"))["robustness"];
  EXPECT_GT(td["points"][0]["nonlinear"]["eta_rest_mm"].get<double>(), 5.0);
  ASSERT_FALSE(td["holds"]["nonlinear"].is_null());
  EXPECT_FALSE(td["holds"]["nonlinear"]["from_is_sweep_end"].get<bool>());
  EXPECT_LT(td["holds"]["nonlinear"]["from_pct"].get<double>(), 0.0);
}

TEST_F(RobustnessApi, OptingOutLeavesTheBlockOutUnderAnotherKey) {
  const json& on = plan_of(plan_body("multi_notch"));
  const json& off = plan_of(plan_body("multi_notch", {{"robustness", false}}));
  const json& said_on = plan_of(plan_body("multi_notch", {{"robustness", true}}));
  EXPECT_TRUE(on.contains("robustness"));
  EXPECT_FALSE(off.contains("robustness"));
  EXPECT_NE(on["key"], off["key"]);
  EXPECT_EQ(on["key"], said_on["key"]);
  EXPECT_EQ(on["durations_s"], off["durations_s"]);  // the report changes no law
  // Each key answers its own plan, in both views.
  const std::string on_key = on["key"], off_key = off["key"];
  const Reply got_on = request("GET", "/v1/plans/" + on_key);
  const Reply got_off = request("GET", "/v1/plans/" + off_key);
  EXPECT_EQ(got_on.body["robustness"], on["robustness"]);
  EXPECT_FALSE(got_off.body.contains("robustness"));
  const Reply compact_on = request("GET", "/v1/plans/" + on_key + "?view=compact");
  const Reply compact_off = request("GET", "/v1/plans/" + off_key + "?view=compact");
  EXPECT_TRUE(compact_on.body.contains("robustness"));
  EXPECT_FALSE(compact_off.body.contains("robustness"));
}

/// The built-in registry without the robustness options: what keyed every plan before them.
api::OptionRegistry registry_before_issue_20() {
  std::vector<api::OptionSpec> options;
  for (const api::OptionSpec& o : api::plan_option_registry().options()) {
    if (o.name != "robustness" && o.group != "uncertainty") options.push_back(o);
  }
  return api::OptionRegistry(std::move(options), {api::OptionGroup{"limits", "MachineLimits", ""}});
}

TEST(RobustnessKeys, RequestsWithoutTheNewOptionsKeepTheirKeys) {
  const api::OptionRegistry before = registry_before_issue_20();
  const json many = json::parse(R"({"p_notch": 0.2, "band": 0.1, "eta_rest_max_mm": 2,
      "eta_motion_max_mm": 9, "objective": "rest", "limits": {"a_max": 9}, "damping": "paper",
      "modes": 2, "shaper": "ei", "drive_profile": "free"})");
  for (const json& body : {plan_body("notch"), plan_body("time_domain", many),
                           plan_body("shaper", {{"shaper", "zvd"}})}) {
    const api::PlanRequest r = api::parse_plan_request(body);
    EXPECT_EQ(api::recipe_key(r), api::recipe_key(r, before)) << body.dump();
  }
}

// An option a strategy does not read stays out of its key: requests differing only there share one
// plan (the cached one answers the second), and the echo of the option is null; the strategies
// that read it (time_domain, auto) still key it.
TEST_F(RobustnessApi, SamplePointsSplitsOnlyTheKeysOfTheStrategiesThatReadIt) {
  const json five = with_uncertainty({{"omega_error_pct", 5}, {"sample_points", 5}});
  const json nine = with_uncertainty({{"omega_error_pct", 5}, {"sample_points", 9}});
  auto key = [](const std::string& strategy, const json& options) {
    return api::recipe_key(api::parse_plan_request(plan_body(strategy, options)));
  };
  for (const std::string strategy : {"notch", "multi_notch", "min_jerk_band", "shaper"}) {
    EXPECT_EQ(key(strategy, five), key(strategy, nine)) << strategy;
  }
  for (const std::string strategy : {"time_domain", "auto"}) {
    EXPECT_NE(key(strategy, five), key(strategy, nine)) << strategy;
  }
  const std::string hits = R"(slosh_cache_hits_total{level="memory"})";
  const double hits_before = test::metric_of(*server(), hits);
  const Reply first = post("/v1/plans", plan_body("notch", five));
  const Reply second = post("/v1/plans", plan_body("notch", nine));
  ASSERT_EQ(first.status, 200) << first.raw;
  ASSERT_EQ(second.status, 200) << second.raw;
  EXPECT_EQ(second.body["key"], first.body["key"]);
  EXPECT_EQ(second.body["key"], key("notch", nine));
  EXPECT_EQ(second.body["cached"], true);
  json stored = first.body, served = second.body;
  stored.erase("cached");
  served.erase("cached");
  EXPECT_EQ(served, stored);  // the same plan
  EXPECT_EQ(test::metric_of(*server(), hits), std::max(hits_before, 0.0) + 1.0);
  EXPECT_EQ(first.body["uncertainty"]["sample_points"], nullptr);
  EXPECT_EQ(first.body["uncertainty"]["omega_error_pct"], 5.0);
}

TEST(RobustnessKeys, TheUncertaintyIsKeyedOnlyWhenItSaysSomething) {
  auto key = [](const json& options) {
    return api::recipe_key(api::parse_plan_request(plan_body("shaper", options)));
  };
  const std::string none = key(json::object());
  for (const json& same :
       {with_uncertainty(nullptr), with_uncertainty(json::object()),
        with_uncertainty({{"omega_error_pct", 0}}), with_uncertainty({{"sample_points", 9}}),
        json{{"robustness", true}}, json{{"shaper", "zv"}}}) {
    EXPECT_EQ(key(same), none) << same.dump();
  }
  const std::string five = key(with_uncertainty({{"omega_error_pct", 5}}));
  EXPECT_NE(five, none);
  EXPECT_EQ(key(with_uncertainty({{"omega_error_pct", 5}, {"sample_points", 5}})), five);
  // The shaper does not read sample_points: it stays out of the key (time_domain's below).
  EXPECT_EQ(key(with_uncertainty({{"omega_error_pct", 5}, {"sample_points", 9}})), five);
  EXPECT_NE(key(with_uncertainty({{"omega_error_pct", 6}})), five);
  const std::string fill = key(with_uncertainty({{"fill_height_mm", {75, 90}}}));
  EXPECT_NE(fill, none);
  EXPECT_NE(fill, five);
  EXPECT_NE(key(with_uncertainty({{"fill_height_mm", {75, 91}}})), fill);
  EXPECT_NE(key(with_uncertainty({{"viscosity_pa_s", {0.0008, 0.0015}}})), none);
  EXPECT_NE(key({{"robustness", false}}), none);
  // A shaper named under a range is the caller's choice of family: its own key.
  EXPECT_NE(key(with_uncertainty({{"omega_error_pct", 5}}, {{"shaper", "zv"}})), five);

  // The values in core units, the shaper's choice left to the planner unless named.
  const api::PlanRequest r = api::parse_plan_request(
      plan_body("shaper", with_uncertainty({{"omega_error_pct", 5},
                                            {"fill_height_mm", {75, 90}},
                                            {"viscosity_pa_s", {0.0008, 0.0015}},
                                            {"sample_points", 7}},
                                           {{"shaper", "zvd"}})));
  const Uncertainty& u = r.options.uncertainty;
  EXPECT_DOUBLE_EQ(u.omega_error, 0.05);
  ASSERT_TRUE(u.fill_height && u.viscosity);
  EXPECT_DOUBLE_EQ((*u.fill_height)[0], 0.075);
  EXPECT_DOUBLE_EQ((*u.fill_height)[1], 0.090);
  EXPECT_EQ(*u.viscosity, (std::array<double, 2>{0.0008, 0.0015}));
  EXPECT_EQ(u.sample_points, 7);
  EXPECT_FALSE(r.options.shaper_for_range);
  EXPECT_TRUE(api::parse_plan_request(plan_body("shaper")).options.shaper_for_range);
  EXPECT_TRUE(api::parse_plan_request(plan_body("shaper")).options.robustness);
  EXPECT_FALSE(
      api::parse_plan_request(plan_body("shaper", {{"robustness", false}})).options.robustness);
}

// ---- refusals ----------------------------------------------------------------------------------

struct Refusal {
  json options;
  std::string field;
  std::string message;
  bool without_height{false};
};

/// The widened-band refusal as the API words it, from f1's range [f_lo, f_hi] (scale_lo/hi).
std::string widened_band_message(const std::string& member, double w1, double scale_lo,
                                 double scale_hi, double band, const std::string& band_text) {
  const double f_lo = w1 * scale_lo / (2.0 * kPi), f_hi = w1 * scale_hi / (2.0 * kPi);
  return "options.uncertainty." + member + " spreads f1 over " + g3(f_lo) + " to " + g3(f_hi) +
         " Hz: min_jerk_band's options.band = " + band_text +
         " widened to cover it (centred on the range's middle) reaches 0 Hz at its lower "
         "edge (" +
         g3(f_lo) + " - " + band_text + " x " + g3(f_hi) + " = " + g3(f_lo - band * f_hi) +
         " Hz); allowed options.band < " + g10(scale_lo / scale_hi) +
         " with this range: narrow the band or the range";
}

std::vector<Refusal> refusals() {
  const std::string u = "options.uncertainty.";
  const std::string fill = u + "fill_height_mm", visc = u + "viscosity_pa_s";
  const std::string samples = u + "sample_points", omega = u + "omega_error_pct";
  const std::string height_range = "allowed >= 1 and < 150 mm";
  const std::string integer_range = "allowed an integer from 2 to 21";
  return {
      {{{"uncertainty", 5}},
       "options.uncertainty",
       "options.uncertainty must be a JSON object, got 5"},
      {with_uncertainty({{"omega_error", 5}}), u + "omega_error",
       u + "omega_error is not a known field; allowed here: omega_error_pct, fill_height_mm, "
           "viscosity_pa_s, sample_points"},
      {with_uncertainty({{"omega_error_pct", 60}}), omega,
       omega + " = 60 is out of range: allowed 0 to 50 %"},
      {with_uncertainty({{"omega_error_pct", -1}}), omega,
       omega + " = -1 is out of range: allowed 0 to 50 %"},
      // 5e-324 % x 0.01 underflows to 0 ("none"): refused, with the smallest normal double / 0.01.
      {with_uncertainty({{"omega_error_pct", 5e-324}}), omega,
       omega + " = 4.940656458e-324 % is too small to be told from 0: give 0 or at least " +
           g10(std::numeric_limits<double>::min() / 0.01) + " %"},
      {with_uncertainty({{"omega_error_pct", 1e-310}}), omega,
       omega + " = 1e-310 % is too small to be told from 0: give 0 or at least " +
           g10(std::numeric_limits<double>::min() / 0.01) + " %"},
      {with_uncertainty({{"omega_error_pct", "5"}}), omega,
       omega + " must be a number, got \"5\"; allowed 0 to 50 %"},
      {with_uncertainty({{"fill_height_mm", 80}}), fill,
       fill + " must be an array of 2 numbers, got 80"},
      {with_uncertainty({{"fill_height_mm", {80}}}), fill,
       fill + " must be an array of 2 numbers, got [80]"},
      {with_uncertainty({{"fill_height_mm", {80, "90"}}}), fill + "[1]",
       fill + "[1] must be a number, got \"90\"; " + height_range},
      {with_uncertainty({{"fill_height_mm", {80, 150}}}), fill + "[1]",
       fill + "[1] = 150 is out of range: " + height_range},
      {with_uncertainty({{"fill_height_mm", {0.5, 90}}}), fill + "[0]",
       fill + "[0] = 0.5 is out of range: " + height_range},
      {with_uncertainty({{"fill_height_mm", {80, 6000}}}), fill + "[1]",
       fill + "[1] = 6000 is out of range: allowed 1 to 5000 mm", true},
      {with_uncertainty({{"fill_height_mm", {90, 70}}}), fill,
       fill + " = [90, 70] mm is empty: the maximum must be >= the minimum"},
      {with_uncertainty({{"fill_height_mm", {85, 90}}}), fill,
       fill + " = [85, 90] mm must contain the nominal fill height 82 mm"},
      {with_uncertainty({{"fill_height_mm", {70, 80.5}}}), fill,
       fill + " = [70, 80.5] mm must contain the nominal fill height 82 mm"},
      {with_uncertainty({{"viscosity_pa_s", {0.002, 0.003}}}), visc,
       visc + " = [0.002, 0.003] Pa·s must contain the nominal viscosity 0.0010016 Pa·s"},
      {with_uncertainty({{"viscosity_pa_s", {0.003, 0.002}}}), visc,
       visc + " = [0.003, 0.002] Pa·s is empty: the maximum must be >= the minimum"},
      {with_uncertainty({{"viscosity_pa_s", {-1, 0.002}}}), visc + "[0]",
       visc + "[0] = -1 is out of range: allowed 0 to 1000000 Pa·s"},
      {with_uncertainty({{"viscosity_pa_s", {0.0008, 0.0015}}}, {{"damping", {{"zeta", 0.01}}}}),
       visc,
       visc + " = [0.0008, 0.0015] Pa·s is not allowed with an explicit damping "
              "(options.damping = {\"zeta\": 0.01}): a viscosity range acts through the damping "
              "correlation; give a correlation (thesis, paper, eq227, eq228) or no viscosity "
              "range"},
      {with_uncertainty({{"sample_points", 1}}), samples,
       samples + " = 1 is out of range: " + integer_range},
      {with_uncertainty({{"sample_points", 22}}), samples,
       samples + " = 22 is out of range: " + integer_range},
      {with_uncertainty({{"sample_points", 2.5}}), samples,
       samples + " = 2.5 is not an integer: " + integer_range},
      {{{"robustness", "yes"}},
       "options.robustness",
       "options.robustness must be true or false, got \"yes\""},
  };
}

TEST_F(RobustnessApi, EveryRefusalNamesTheFieldTheValueAndTheRange) {
  std::vector<Refusal> cases = refusals();
  // The band widened over the range must keep its lower edge above 0 Hz: band < f_lo / f_hi.
  const double R = 48.5 * 1e-3, h = 82 * 1e-3;
  const double w1 = omega1(R, h);
  cases.push_back(
      {with_uncertainty({{"omega_error_pct", 10}}, {{"band", 0.82}}), "options.band",
       widened_band_message("omega_error_pct = 10 %", w1, 1.0 - 0.1, 1.0 + 0.1, 0.82, "0.82")});
  const double s_lo = omega1(R, 2 * 1e-3) / w1, s_hi = omega1(R, 140 * 1e-3) / w1;
  cases.push_back(
      {with_uncertainty({{"fill_height_mm", {2, 140}}}, {{"band", 0.5}}), "options.band",
       widened_band_message("fill_height_mm = [2, 140] mm", w1, s_lo, s_hi, 0.5, "0.5")});
  const std::size_t band_cases = 2;  // the last two: only the strategies holding the band
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const Refusal& c = cases[k];
    const bool band = k + band_cases >= cases.size();
    for (const char* strategy : {"min_jerk_band", "auto", "multi_notch"}) {
      if (!band && std::string(strategy) != "multi_notch") continue;
      SCOPED_TRACE(c.options.dump() + " " + strategy);
      json body = plan_body(strategy, c.options);
      if (c.without_height) body["format"]["container"].erase("height_mm");
      const Reply r = post("/v1/plans", body);
      if (band && std::string(strategy) == "multi_notch") {
        // multi_notch has no band: the same band and range are no reason to refuse it.
        EXPECT_EQ(r.status, 200) << r.raw.substr(0, 300);
        EXPECT_GE(r.body["spectrum"]["markers"]["band_hz"][0].get<double>(), 0.0);
        continue;
      }
      EXPECT_EQ(r.status, 422) << r.raw;
      EXPECT_EQ(r.body["error"]["field"], c.field);
      EXPECT_EQ(r.body["error"]["message"], c.message);
    }
  }
  // Just inside those bounds the plans are made: 0.9 / 1.1 = 0.8181..., s_lo / s_hi = 0.27...
  for (const json& options :
       {with_uncertainty({{"omega_error_pct", 10}}, {{"band", 0.81}}),
        with_uncertainty({{"fill_height_mm", {2, 140}}}, {{"band", 0.99 * s_lo / s_hi}})}) {
    const Reply r = post("/v1/plans", plan_body("multi_notch", options));
    EXPECT_EQ(r.status, 200) << options.dump() << ": " << r.raw.substr(0, 300);
  }
  // A min-time search reads its options as a plan does.
  json search{{"format", thesis_format()},
              {"strategies", {"fir_chain"}},
              {"options", with_uncertainty({{"fill_height_mm", {90, 70}}})}};
  search["format"].erase("motion_time_s");
  const Reply r = post("/v1/min-time", search);
  EXPECT_EQ(r.status, 422) << r.raw;
  EXPECT_EQ(r.body["error"]["field"], "options.uncertainty.fill_height_mm");
  EXPECT_EQ(r.body["error"]["message"],
            "options.uncertainty.fill_height_mm = [90, 70] mm is empty: the maximum must be >= "
            "the minimum");
}

// ---- the uncertainty ---------------------------------------------------------------------------

TEST_F(RobustnessApi, TheUncertaintyBlockIsTheRangeTheModelImpliesAndTheSweepCoversIt) {
  const json options = with_uncertainty(
      {{"omega_error_pct", 5}, {"fill_height_mm", {75, 90}}, {"viscosity_pa_s", {0.0008, 0.0015}}});
  const json& plan = plan_of(plan_body("multi_notch", options));
  EXPECT_EQ(plan["key"],
            api::recipe_key(api::parse_plan_request(plan_body("multi_notch", options))));
  ASSERT_TRUE(plan.contains("uncertainty") && plan.contains("worst_case"));
  const json& u = plan["uncertainty"];
  EXPECT_EQ(u["omega_error_pct"], 5.0);
  EXPECT_EQ(u["fill_height_mm"], json::array({75.0, 90.0}));
  EXPECT_EQ(u["viscosity_pa_s"], json::array({0.0008, 0.0015}));
  EXPECT_EQ(u["sample_points"], nullptr);  // multi_notch does not read it

  const double R = 48.5 * 1e-3, h = 82 * 1e-3, rho = 998.2, mu = 0.0010016;
  ASSERT_EQ(plan["format"]["fluid"]["density_kg_m3"], rho);
  ASSERT_EQ(plan["format"]["fluid"]["viscosity_pa_s"], mu);
  const double w1 = omega1(R, h);
  const double scale_lo = omega1(R, 75 * 1e-3) / w1 * (1.0 - 0.05),
               scale_hi = omega1(R, 90 * 1e-3) / w1 * (1.0 + 0.05);
  double zeta_lo = INFINITY, zeta_hi = -INFINITY;
  for (int k = 0; k < 5; ++k) {
    for (double viscosity : {0.0008, 0.0015}) {
      const double z = thesis_zeta(R, 75e-3 + (90e-3 - 75e-3) * k / 4.0, rho, viscosity);
      zeta_lo = std::min(zeta_lo, z);
      zeta_hi = std::max(zeta_hi, z);
    }
  }
  EXPECT_LT(zeta_lo, thesis_zeta(R, h, rho, mu));
  const std::vector<std::pair<std::string, std::array<double, 2>>> ranges{
      {"scale", {scale_lo, scale_hi}},
      {"omega1_rad_s", {w1 * scale_lo, w1 * scale_hi}},
      {"f1_hz", {w1 * scale_lo / (2.0 * kPi), w1 * scale_hi / (2.0 * kPi)}},
      {"zeta", {zeta_lo, zeta_hi}}};
  for (const auto& [name, range] : ranges) {
    for (int i = 0; i < 2; ++i) {
      expect_rel(range[i], u[name][i].get<double>(), 1e-12, name);
    }
  }
  // The sweep covers the range at its least damping: 21 points, and delta = 0 added.
  const json& r = plan["robustness"];
  EXPECT_NEAR(r["sweep"]["delta_pct"][0].get<double>(), 100.0 * (scale_lo - 1.0), 1e-9);
  EXPECT_NEAR(r["sweep"]["delta_pct"][1].get<double>(), 100.0 * (scale_hi - 1.0), 1e-9);
  expect_rel(zeta_lo, r["sweep"]["zeta"].get<double>(), 1e-12, "sweep zeta");
  ASSERT_EQ(r["points"].size(), 22u);
  const json damping{{"zeta", zeta_lo}};
  double worst_motion = 0.0, worst_rest = 0.0;
  std::size_t evenly = 0;
  for (const json& p : r["points"]) {
    const double d = p["delta_pct"].get<double>() / 100.0;
    if (d == 0.0) {  // added: not one of the 21
      expect_point_is_stretched_law(plan, p, damping);
      continue;
    }
    EXPECT_NEAR(d, scale_lo - 1.0 + (scale_hi - scale_lo) * static_cast<double>(evenly) / 20.0,
                1e-12);
    ++evenly;
    const json sim = stretched_prediction(plan, d, damping);
    worst_motion = std::max(worst_motion, sim["nonlinear"]["eta_motion_mm"].get<double>());
    worst_rest = std::max(worst_rest, sim["nonlinear"]["eta_rest_mm"].get<double>());
    for (const char* eta : {"eta_motion_mm", "eta_rest_mm"}) {
      expect_rel(sim["nonlinear"][eta].get<double>(), p["nonlinear"][eta].get<double>(),
                 kStretchTol, eta);
      expect_rel(sim["linear"][eta].get<double>(), p["linear"][eta].get<double>(), kStretchTol,
                 eta);
    }
  }
  EXPECT_EQ(evenly, 21u);
  expect_holds_and_worst(r);
  // The worst case the plan was judged by: the 21 models of the range at its least damping.
  expect_rel(worst_motion, plan["worst_case"]["nonlinear"]["eta_motion_mm"].get<double>(),
             kStretchTol, "worst eta_motion");
  expect_rel(worst_rest, plan["worst_case"]["nonlinear"]["eta_rest_mm"].get<double>(), kStretchTol,
             "worst eta_rest");
}

TEST_F(RobustnessApi, AutosCandidatesCarryTheWorstCaseTheyAreComparedBy) {
  const json& plan = plan_of(plan_body("auto", with_uncertainty({{"omega_error_pct", 5}})));
  ASSERT_TRUE(plan.contains("candidates") && plan.contains("worst_case"));
  ASSERT_GE(plan["candidates"].size(), 5u);
  int chosen = 0;
  for (const json& c : plan["candidates"]) {
    SCOPED_TRACE(c["strategy"].dump());
    ASSERT_TRUE(c.contains("worst_case"));
    for (const char* model : {"linear", "nonlinear"}) {
      for (const char* eta : {"eta_motion_mm", "eta_rest_mm"}) {
        // The range (+-5 % at the nominal damping) holds the nominal model.
        EXPECT_GE(c["worst_case"][model][eta].get<double>(),
                  c["prediction"][model][eta].get<double>() * (1.0 - 1e-9))
            << model << " " << eta;
      }
    }
    if (c["chosen"].get<bool>()) {
      ++chosen;
      EXPECT_EQ(c["worst_case"], plan["worst_case"]);
    }
  }
  EXPECT_EQ(chosen, 1);
}

// ---- views and tables ------------------------------------------------------------------------

double hundredths(const json& v) {
  return std::round(v.get<double>() * 100.0) / 100.0;
}

TEST_F(RobustnessApi, TheCompactViewKeepsTheNonlinearIntervalAndWorstUnder1kB) {
  const json& plan = plan_of(plan_body("time_domain"));
  const std::string key = plan["key"];
  const Reply compact = request("GET", "/v1/plans/" + key + "?view=compact");
  ASSERT_EQ(compact.status, 200) << compact.raw;
  EXPECT_LT(compact.raw.size(), 1024u) << compact.raw;
  const json& holds = plan["robustness"]["holds"]["nonlinear"];
  const json& worst = plan["robustness"]["worst"]["nonlinear"];
  ASSERT_FALSE(holds.is_null());
  const json expected{
      {"holds_pct", {hundredths(holds["from_pct"]), hundredths(holds["to_pct"])}},
      {"worst_mm", {hundredths(worst["eta_motion_mm"]), hundredths(worst["eta_rest_mm"])}}};
  EXPECT_EQ(compact.body["robustness"], expected);
  // A batch in the compact view carries the same.
  const Reply batch =
      post("/v1/plans/batch", {{"requests", {plan_body("time_domain")}}, {"view", "compact"}});
  ASSERT_EQ(batch.status, 200) << batch.raw;
  EXPECT_EQ(batch.body["results"][0]["plan"]["robustness"], expected);
}

TEST_F(RobustnessApi, BatchRowsCarryTheIntervalAndReadTheUncertaintyColumns) {
  const test::TempDir dir;
  test::write_file(dir / "in.csv",
                   "recipe_id,radius_mm,container_height_mm,fill_height_mm,fluid,stroke_mm,"
                   "motion_time_s,strategy,robustness,uncertainty_omega_error_pct,"
                   "uncertainty_fill_height_mm\n"
                   "plain,48.5,150,82,water,800,1.0,time_domain,,,\n"
                   "omega,48.5,150,82,water,800,1.0,multi_notch,,5,\n"
                   "fill,48.5,150,82,water,800,1.0,multi_notch,,,75;90\n"
                   "off,48.5,150,82,water,800,1.0,multi_notch,false,,\n"
                   "empty,48.5,150,82,water,800,1.0,multi_notch,,,90;70\n");
  const test::RunResult run =
      test::run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out",
                       (dir / "out.csv").string(), "--cache", "", "--progress", "never"});
  ASSERT_EQ(run.exit_code, 3) << run.err;  // 3: some rows could not be planned
  const auto records = test::csv_texts(test::read_file(dir / "out.csv"));
  ASSERT_EQ(records.size(), 6u);
  const std::vector<std::string>& header = records[0];
  auto cell = [&](std::size_t row, const std::string& column) {
    const auto it = std::find(header.begin(), header.end(), column);
    EXPECT_NE(it, header.end()) << column;
    return it == header.end() ? std::string() : records[row][it - header.begin()];
  };
  const std::vector<json> same_as{
      plan_body("time_domain"),
      plan_body("multi_notch", with_uncertainty({{"omega_error_pct", 5}})),
      plan_body("multi_notch", with_uncertainty({{"fill_height_mm", {75, 90}}})),
      plan_body("multi_notch", {{"robustness", false}})};
  for (std::size_t row = 1; row <= same_as.size(); ++row) {
    SCOPED_TRACE(cell(row, "recipe_id"));
    const json& plan = plan_of(same_as[row - 1]);
    EXPECT_EQ(cell(row, "key"), plan["key"].get<std::string>());
    if (!plan.contains("robustness")) {
      for (const char* c : {"holds_from_pct", "holds_to_pct", "worst_eta_rest_mm"}) {
        EXPECT_EQ(cell(row, c), "") << c;
      }
      continue;
    }
    const json& r = plan["robustness"];
    EXPECT_EQ(std::stod(cell(row, "worst_eta_rest_mm")),
              r["worst"]["nonlinear"]["eta_rest_mm"].get<double>());
    const json& holds = r["holds"]["nonlinear"];
    if (holds.is_null()) {
      EXPECT_EQ(cell(row, "holds_from_pct"), "");
      EXPECT_EQ(cell(row, "holds_to_pct"), "");
    } else {
      EXPECT_EQ(std::stod(cell(row, "holds_from_pct")), holds["from_pct"].get<double>());
      EXPECT_EQ(std::stod(cell(row, "holds_to_pct")), holds["to_pct"].get<double>());
    }
  }
  // A bad range names its column.
  EXPECT_EQ(cell(5, "status"), "error");
  EXPECT_EQ(cell(5, "error_field"), "uncertainty_fill_height_mm");
  EXPECT_EQ(cell(5, "message"),
            "uncertainty_fill_height_mm = [90, 70] mm is empty: the maximum must be >= the "
            "minimum");
}

// ---- models that diverge ------------------------------------------------------------------------

// Far outside the models' validity the nonlinear model diverges at some delta: the report says so
// with null (no number to give), where it answered 500 (a non-finite number in the response).
TEST_F(RobustnessApi, WhereTheNonlinearModelDivergesTheReportSaysNull) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 5}, "fill_height_mm": 6,
      "fluid": "water", "stroke_mm": 5000, "motion_time_s": 0.05}, "strategy": "fir_chain",
      "options": {"min_ramp_s": 0.007, "limits": {"a_max": 0.001}}})");
  // Over an uncertainty range the plan promises the range: a law the models cannot follow
  // somewhere in it is refused, as one they cannot follow at the nominal model is.
  json uncertain = body;
  uncertain["options"]["uncertainty"] = {{"omega_error_pct", 10}};
  const Reply refused = post("/v1/plans", uncertain);
  ASSERT_EQ(refused.status, 422) << refused.raw.substr(0, 400);
  EXPECT_NE(refused.body["error"]["message"].get<std::string>().find(
                "diverge for the planned fir_chain law somewhere in the uncertainty range"),
            std::string::npos)
      << refused.raw;
  // Without a range the report alone says where the model diverges: null points and worst.
  const Reply r = post("/v1/plans", body);
  ASSERT_EQ(r.status, 200) << r.raw.substr(0, 400);
  const json& plan = r.body;
  const json& rob = plan["robustness"];
  EXPECT_TRUE(rob["worst"]["nonlinear"].is_null());
  EXPECT_FALSE(rob["worst"]["linear"].is_null());
  int diverged = 0;
  for (const json& p : rob["points"]) {
    EXPECT_FALSE(p["linear"].is_null());
    if (p["nonlinear"].is_null()) {
      ++diverged;
      EXPECT_FALSE(p["holds_nonlinear"].get<bool>());
    }
  }
  EXPECT_GT(diverged, 0);
  const std::string key = plan["key"];
  const Reply compact = request("GET", "/v1/plans/" + key + "?view=compact");
  ASSERT_EQ(compact.status, 200) << compact.raw;  // infeasible plans are kept (cam tables)
  EXPECT_TRUE(compact.body["robustness"]["worst_mm"].is_null());
}

// Found by the API work: auto with an uncertainty range on a format where the models diverge
// for every candidate somewhere in the range left no candidate, and run_auto indexed the empty
// list (SIGSEGV, a server too). It is now a refusal.
TEST(RobustnessCore, AutoWhereEveryCandidateDivergesOverTheRangeAnswers) {
  const test::TempDir dir;
  test::write_file(dir / "request.json",
                   R"({"format": {"container": {"radius_mm": 5}, "fill_height_mm": 6,
      "fluid": "water", "stroke_mm": 5000, "motion_time_s": 0.05}, "strategy": "auto",
      "options": {"min_ramp_s": 0.0125, "limits": {"a_max": 0.001},
                  "uncertainty": {"omega_error_pct": 10}}})");
  const test::RunResult r = test::run_slosh({"plan", "--request", (dir / "request.json").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE((r.out + r.err).find("the sloshing models diverge"), std::string::npos)
      << r.out << r.err;
}

}  // namespace test_robustness_api
}  // namespace slosh
