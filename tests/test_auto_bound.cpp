// `auto` and the eta bound of the options (time_domain's eta_rest <= eta_rest_max): only the
// usable candidates that meet it compete; when none does, auto returns the least infeasible law
// (the lowest verified eta_rest among the candidates whose only fault is the bound) as
// infeasible, never as optimal. On the straight line and along an arc.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "slosh/core/strategy/path_plan.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh {
namespace test_auto_bound {

bool usable(SolveStatus s) {
  return s == SolveStatus::kOptimal || s == SolveStatus::kAcceptable ||
         s == SolveStatus::kTimeLimit;
}

PlanOptions options_with_bound(double eta_rest_max) {
  PlanOptions o;
  o.robustness = false;
  o.time_limit = 60.0;
  o.eta_rest_max = eta_rest_max;
  return o;
}

// What the rule promises, checked on the answer's own candidates: a usable plan meets the bound
// and every usable candidate above it lost for it; an infeasible one is the lowest eta_rest of
// the candidates that are usable or time_domain's (its fault the bound alone here: no limits).
void expect_bound_rule(const PlanResult& r, double bound) {
  ASSERT_FALSE(r.candidates.empty()) << r.message;
  const double rest = r.prediction.nonlinear.rest.value;
  if (usable(r.status)) {
    EXPECT_LE(rest, bound * (1.0 + 1e-6)) << r.message;
    for (const PlanCandidate& k : r.candidates) {
      if (usable(k.status) && k.prediction.nonlinear.rest.value > bound * (1.0 + 1e-6)) {
        EXPECT_EQ(k.lost, CandidateLoss::kAboveBound) << to_string(k.strategy);
      }
    }
    return;
  }
  EXPECT_EQ(r.status, SolveStatus::kInfeasible) << r.message;
  double lowest = std::numeric_limits<double>::infinity();
  for (const PlanCandidate& k : r.candidates) {
    if (usable(k.status) || k.strategy == Strategy::kTimeDomain) {
      lowest = std::min(lowest, k.prediction.nonlinear.rest.value);
    }
  }
  EXPECT_DOUBLE_EQ(rest, lowest) << r.message;
  EXPECT_NE(r.message.find("no candidate meets eta_rest <= "), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("(eta_rest_max_mm): the lowest is "), std::string::npos) << r.message;
}

// The straight line, with time_domain's other objective: min eta_rest s.t. eta_motion <= 1 mm,
// which no candidate reaches for 471 mm in 0.6 s (all are near 50 mm). Before, auto answered
// optimal with a law far above the bound; now the lowest eta_motion, infeasible. (eta_rest_max
// is no test here: time_domain reaches a micrometre of residual wave on this line.)
TEST(AutoBound, NoCandidateMeetsTheBoundOnALineIsInfeasibleWithTheLeastInfeasibleLaw) {
  Format f = thesis_format();
  f.stroke = 0.471;
  f.motion_time = 0.6;
  PlanOptions o = options_with_bound(3e-3);
  o.objective = TimeDomainObjective::kRest;
  o.eta_motion_max = 1e-3;
  const PlanResult r = plan(f, Strategy::kAuto, o);
  EXPECT_EQ(r.status, SolveStatus::kInfeasible) << r.message;
  // The lowest among those whose one fault is the bound, not worse than the uniform law while one
  // of them is not (SPEC §5).
  auto bound_only = [&](const PlanCandidate& k) {
    return usable(k.status) || k.strategy == Strategy::kTimeDomain;
  };
  const bool any_not_worse = std::any_of(r.candidates.begin(), r.candidates.end(), [&](auto& k) {
    return bound_only(k) && k.worse_than_baseline.empty();
  });
  double lowest = std::numeric_limits<double>::infinity();
  for (const PlanCandidate& k : r.candidates) {
    if (bound_only(k) && (!any_not_worse || k.worse_than_baseline.empty())) {
      lowest = std::min(lowest, k.prediction.nonlinear.motion.value);
    }
  }
  EXPECT_DOUBLE_EQ(r.prediction.nonlinear.motion.value, lowest) << r.message;
  EXPECT_EQ(r.message.rfind("no candidate meets eta_motion <= 1 mm (eta_motion_max_mm): the "
                            "lowest is ",
                            0),
            0U)
      << r.message;
}

TEST(AutoBound, NoCandidateMeetsTheBoundAlongAnArcIsInfeasibleWithTheLeastInfeasibleLaw) {
  const PlanarPath arc = PlanarPath::arc(0.3, std::numbers::pi / 2.0, true);
  Format f = thesis_format();
  f.stroke = arc.length();
  f.motion_time = 0.6;
  const PlanResult r = plan_on_path(f, arc, Strategy::kAuto, options_with_bound(0.5e-3));
  EXPECT_EQ(r.status, SolveStatus::kInfeasible) << r.message;
  expect_bound_rule(r, 0.5e-3);
}

// Over motion times and bounds on the line, reachable or not, the rule holds.
TEST(AutoBound, AutoNeverAnswersUsableAboveTheBoundOnALine) {
  for (double T : {0.5, 0.8, 1.2}) {
    for (double bound_mm : {0.3, 1.0, 3.0}) {
      Format f = thesis_format();
      f.stroke = 0.3;
      f.motion_time = T;
      SCOPED_TRACE("T " + std::to_string(T) + " s, eta_rest_max " + std::to_string(bound_mm));
      expect_bound_rule(plan(f, Strategy::kAuto, options_with_bound(bound_mm * 1e-3)),
                        bound_mm * 1e-3);
    }
  }
}

// choose_auto alone: a usable candidate above the bound loses to one within it, whatever its
// eta_motion, and says why.
TEST(AutoBound, AUsableCandidateAboveTheBoundLosesToOneWithin) {
  auto candidate = [](Strategy s, double motion, double rest) {
    PlanCandidate k;
    k.strategy = s;
    k.status = SolveStatus::kOptimal;
    k.prediction.nonlinear.motion.value = motion;
    k.prediction.nonlinear.rest.value = rest;
    return k;
  };
  const std::vector<PlanCandidate> candidates{candidate(Strategy::kBaseline, 0.020, 0.004),
                                              candidate(Strategy::kNotch, 0.010, 0.0035),
                                              candidate(Strategy::kTimeDomain, 0.015, 0.0029)};
  std::vector<BoundVerdict> bounds;
  for (const PlanCandidate& k : candidates) {
    bounds.push_back({k.prediction.nonlinear.rest.value, 0.003, true, true});
  }
  const AutoChoice choice = choose_auto(candidates, {false, false, false}, bounds);
  EXPECT_EQ(choice.index, 2U);
  EXPECT_FALSE(choice.bound_missed);
  EXPECT_EQ(choice.lost[1], CandidateLoss::kAboveBound);
  EXPECT_EQ(choice.lost_detail[1],
            "eta_rest 3.5 mm is above eta_rest_max_mm = 3 mm, which another candidate meets");
  // Without the bound, notch's lower eta_motion decides (time_domain is more than 5 % above).
  EXPECT_EQ(choose_auto(candidates, {false, false, false}).index, 1U);
  // All above: the lowest eta_rest, infeasible, with the sentence.
  for (BoundVerdict& b : bounds) b.bound = 0.001;
  const AutoChoice missed = choose_auto(candidates, {false, false, false}, bounds);
  EXPECT_TRUE(missed.bound_missed);
  EXPECT_EQ(missed.index, 2U);
  EXPECT_EQ(missed.bound_sentence,
            "no candidate meets eta_rest <= 1 mm (eta_rest_max_mm): the lowest is 2.9 mm "
            "(time_domain), which auto returns; lengthen the motion or relax the limit");
  EXPECT_EQ(missed.lost[0], CandidateLoss::kAboveBound);
  EXPECT_EQ(missed.lost_detail[0],
            "eta_rest 4 mm vs 2.9 mm of the chosen time_domain; no candidate meets eta_rest <= 1 "
            "mm");
}

}  // namespace test_auto_bound
}  // namespace slosh
