// auto's candidates say why each one lost: the reason code of SPEC §5's rule and the figures that
// decided it, checked against the rule recomputed here from the candidates' own predictions (as a
// client would check the choice), on the real `slosh serve`.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/server.hpp"

namespace slosh {
namespace test_auto_reasons {

using nlohmann::json;

// A format where three candidates are worse than the uniform law (the light syrup of the plan
// honesty tests) and one where none is.
json syrup_request() {
  return json::parse(R"({"format": {"container": {"radius_mm": 54.6}, "fill_height_mm": 118,
      "fluid": "light_syrup", "stroke_mm": 500, "motion_time_s": 1.2}, "strategy": "auto"})");
}
json thesis_request() {
  return json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "strategy": "auto"})");
}

// SPEC §5 "Honest status": more than 5 % and 0.5 mm above the uniform law on any figure [mm].
bool worse(const json& p, const json& b) {
  auto above = [](double v, double base) { return v > 1.05 * base && v > base + 0.5; };
  for (const char* model : {"nonlinear", "linear"}) {
    for (const char* figure : {"eta_motion_mm", "eta_rest_mm"}) {
      if (above(p[model][figure].get<double>(), b[model][figure].get<double>())) return true;
    }
  }
  return false;
}

bool usable(const json& c) {
  const std::string s = c["status"];
  return s == "optimal" || s == "acceptable" || s == "time_limit";
}

// The reason of every candidate, recomputed from the plan into `out`: "" for the chosen one. The
// chosen candidate is derived here from the candidates' figures (eligible, eta_motion within 5 %
// of the best, the lowest eta_rest) and must be the one the server marks `chosen`.
void expected_reasons(const json& plan, std::vector<std::string>& out) {
  const json& cs = plan["candidates"];
  const json& base = plan["baseline"];
  // The eta bound first (the requests keep the default eta_rest_max_mm = 3): only the usable
  // candidates within it compete; none within, the lowest eta_rest of the usable ones and
  // time_domain's is returned and the others lost to the bound.
  auto within = [](const json& c) {
    return c["prediction"]["nonlinear"]["eta_rest_mm"].get<double>() <= 3.0 * (1.0 + 1e-6);
  };
  const bool any_within =
      std::any_of(cs.begin(), cs.end(), [&](const json& c) { return usable(c) && within(c); });
  if (!any_within) {
    out.clear();
    for (const json& c : cs) {
      if (c["chosen"] == true) {
        out.emplace_back();
      } else {
        out.emplace_back(usable(c) || c["strategy"] == "time_domain" ? "eta_above_limit"
                                                                     : "not_usable");
      }
    }
    return;
  }
  const bool any_not_worse = std::any_of(cs.begin(), cs.end(), [&](const json& c) {
    return usable(c) && within(c) && (c["strategy"] == "baseline" || !worse(c["prediction"], base));
  });
  auto eligible = [&](const json& c) {
    return usable(c) && within(c) &&
           (!any_not_worse || c["strategy"] == "baseline" || !worse(c["prediction"], base));
  };
  double best = INFINITY;
  for (const json& c : cs) {
    if (eligible(c))
      best = std::min(best, c["prediction"]["nonlinear"]["eta_motion_mm"].get<double>());
  }
  const json* by_rule = nullptr;
  for (const json& c : cs) {
    if (!eligible(c) || c["prediction"]["nonlinear"]["eta_motion_mm"].get<double>() > 1.05 * best)
      continue;
    const double rest = c["prediction"]["nonlinear"]["eta_rest_mm"];
    if (by_rule == nullptr || rest < (*by_rule)["prediction"]["nonlinear"]["eta_rest_mm"]) {
      by_rule = &c;
    }
  }
  const json* chosen = nullptr;
  for (const json& c : cs) {
    if (c["chosen"] == true) chosen = &c;
  }
  ASSERT_NE(chosen, nullptr) << "no candidate is marked chosen";
  ASSERT_NE(by_rule, nullptr) << "no candidate competes by the rule";
  EXPECT_EQ((*chosen)["strategy"], (*by_rule)["strategy"]);
  out.clear();
  for (const json& c : cs) {
    const double motion = c["prediction"]["nonlinear"]["eta_motion_mm"];
    const double rest = c["prediction"]["nonlinear"]["eta_rest_mm"];
    const double chosen_rest = (*chosen)["prediction"]["nonlinear"]["eta_rest_mm"];
    if (&c == chosen) {
      out.emplace_back();
    } else if (!usable(c)) {
      out.emplace_back("not_usable");
    } else if (!within(c)) {
      out.emplace_back("eta_above_limit");
    } else if (!eligible(c)) {
      out.emplace_back("worse_than_baseline");
    } else if (motion > 1.05 * best) {
      out.emplace_back("eta_motion_above_best");
    } else if (std::abs(rest - chosen_rest) <= 1e-6 * chosen_rest) {
      out.emplace_back("tie_on_eta_rest");
    } else {
      EXPECT_GT(rest, chosen_rest) << c["strategy"];
      out.emplace_back("higher_eta_rest");
    }
  }
}

void check_reasons(const json& plan, const std::string& what) {
  std::vector<std::string> expected;
  ASSERT_NO_FATAL_FAILURE(expected_reasons(plan, expected));
  const json& cs = plan["candidates"];
  ASSERT_EQ(cs.size(), expected.size());
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const json& c = cs[k];
    const std::string name = what + " " + c["strategy"].get<std::string>();
    if (expected[k].empty()) {
      EXPECT_TRUE(c.at("reason").is_null()) << name;
      EXPECT_TRUE(c.at("reason_detail").is_null()) << name;
    } else {
      EXPECT_EQ(c.at("reason"), expected[k]) << name;
      EXPECT_TRUE(c.at("reason_detail").is_string() &&
                  !c["reason_detail"].get<std::string>().empty())
          << name;
    }
    // The worse_than_baseline warning exactly when the candidate is worse than the uniform law.
    const bool is_worse = c["strategy"] != "baseline" && worse(c["prediction"], plan["baseline"]);
    ASSERT_TRUE(c.at("warnings").is_array()) << name;
    EXPECT_EQ(c["warnings"].size(), is_worse ? 1u : 0u) << name << ": " << c["warnings"];
    if (is_worse) {
      EXPECT_TRUE(c["warnings"][0].get<std::string>().starts_with("worse_than_baseline: ")) << name;
    }
  }
}

TEST(AutoReasons, EveryLosingCandidateSaysWhyByTheRule) {
  test::Server server;
  auto client = server.client();
  const auto syrup = client.Post("/v1/plans", syrup_request().dump(), "application/json");
  ASSERT_TRUE(syrup && syrup->status == 200) << (syrup ? syrup->body : "");
  const json a = json::parse(syrup->body);
  ASSERT_NO_FATAL_FAILURE(check_reasons(a, "syrup"));
  std::vector<std::string> reasons;
  ASSERT_NO_FATAL_FAILURE(expected_reasons(a, reasons));
  EXPECT_GE(std::count(reasons.begin(), reasons.end(), "worse_than_baseline"), 1)
      << "the case no longer exercises a worse candidate";
  // The figures behind a rest comparison, naming the chosen candidate.
  std::string chosen;
  for (const json& c : a["candidates"]) {
    if (c["chosen"] == true) chosen = c["strategy"];
  }
  for (const json& c : a["candidates"]) {
    if (c["reason"] == "worse_than_baseline") {
      EXPECT_EQ(c["reason_detail"],
                "worse than the uniform law (its worse_than_baseline warning) while a candidate "
                "that is not competes");
    }
    if (c["reason"] == "higher_eta_rest") {
      const std::string detail = c["reason_detail"];
      EXPECT_TRUE(detail.starts_with("eta_rest ")) << detail;
      EXPECT_TRUE(detail.ends_with(" of the chosen " + chosen)) << detail;
    }
  }
  const auto thesis = client.Post("/v1/plans", thesis_request().dump(), "application/json");
  ASSERT_TRUE(thesis && thesis->status == 200);
  check_reasons(json::parse(thesis->body), "thesis");
}

}  // namespace test_auto_reasons
}  // namespace slosh
