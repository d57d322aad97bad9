// time_domain's honesty where it is hardest: at the edge of feasibility. Short motions near the
// minimum motion time (the rest bound barely reachable) and machine limits near the kinematic
// minimum (a_max just above what the stroke needs). Every figure is checked against an
// independent computation written here: the plateau levels A, B rebuilt from the durations alone
// (support/reference_seven_segment.hpp) and eta from a fine-step RK4 of eq. 2.35 re-typed from
// SPEC §2 (support/reference_integrators.hpp), never from the planner's own prediction.
// SLOSH_PROPERTY_FORMATS=N runs N seeded formats instead of 4 (for longer campaigns).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/strategy/min_time.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/random_format.hpp"
#include "support/reference_integrators.hpp"
#include "support/reference_seven_segment.hpp"

namespace slosh {
namespace test_time_domain_honesty {

/// A law keeps a machine limit to the solvers' feasibility tolerance (the verification allows
/// 1e-6) [-].
constexpr double kLimitSlack{1e-8};
/// The rest bound is met on the reference to this relative slack (RK4 vs the planner's DOP853:
/// ~1e-8 relative to the motion's peak, tens of times the bound on these short motions) [-].
constexpr double kMeets{1e-5};
/// A plan's least infeasible law is no worse than a start's to this relative slack (both on the
/// same reference, so only the reference's own round-off separates equal laws) [-].
constexpr double kNoWorse{1e-6};
/// A fresh plan at a T where min-time's search found a law meeting the rest bound, when it meets
/// the bound too, reaches the search's eta_motion to this factor. time_domain is a local method:
/// the search plans most T by continuation from a neighbour's law, a fresh plan from its own
/// starts, and the two can end at different local optima. Measured over 24 seeded formats
/// (SLOSH_PROPERTY_FORMATS=24, the thesis container first, 267 feasible T): the worst 3.9 % above;
/// before the least infeasible phase ran from every start, 4.8 % on the first 8 formats [-].
constexpr double kFreshVsSearch{1.05};

/// Largest |eta| of the nonlinear model over [t0, t1] of a 7-segment law, and over the motion.
struct ReferencePeaks {
  double motion{};
  double rest{};
};

// eq. 2.35 re-typed from SPEC §2 (tests/support), with this model's parameters.
double xbar_dd(const SloshingModel& m, double x, double v, double a) {
  return test::eq235_xbar_dd(m.omega[0], m.zeta, m.C, m.alpha, m.radius, x, v, a);
}

/// The nonlinear peaks of the 7-segment law `d` by a 20 us RK4 (the rest window from T, as the
/// planner's eta_rest).
ReferencePeaks reference_peaks(const SloshingModel& model, const Durations& d, double stroke,
                               double rest) {
  const test::ReferenceSevenSegment law(d, stroke);
  const test::TrapezoidAcceleration acc{d, law.A(), law.B()};
  const double T = law.T();
  const test::Rk4Trajectory r = test::rk4_solve(
      [&](double t, double x, double v) { return xbar_dd(model, x, v, t < T ? acc(t) : 0.0); },
      T + rest, 2e-5);
  return {test::parabola_peak(r, model.K, 0.0, T), test::parabola_peak(r, model.K, T, T + rest)};
}

/// max(A, B) of the durations, rebuilt from them alone [m/s^2].
double reference_a_peak(const Durations& d, double stroke) {
  return test::ReferenceSevenSegment(d, stroke).a_peak();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// The least max(A, B) of a 7-segment law of the stroke in T with ramps >= r: every ramp at r,
/// the rest in the two plateaus, no cruise (the bang-bang law with the shortest ramps) [m/s^2].
double kinematic_minimum(const Format& f, double r) {
  const double p = (f.motion_time - 4.0 * r) / 2.0;
  return reference_a_peak(Durations{r, p, r, 0.0, r, p, r}, f.stroke);
}

/// The symmetric family starts of the planner's least infeasible phase (uniform law, then short
/// ramps with long plateaus, long ramps, balanced with and without cruise), rebuilt from the
/// documented weights over the room above the lower bounds.
std::vector<Durations> family_starts(double T, double min_ramp) {
  const double weights[4][7] = {{1, 3, 1, 1, 1, 3, 1},
                                {3, 0.2, 3, 1, 3, 0.2, 3},
                                {2, 1, 2, 4, 2, 1, 2},
                                {1, 1, 1, 0.2, 1, 1, 1}};
  std::vector<Durations> out{uniform_durations(T)};
  const double lower[7] = {min_ramp, 0, min_ramp, 0, min_ramp, 0, min_ramp};
  const double room = T - 4.0 * min_ramp;
  for (const auto& w : weights) {
    double total = 0.0;
    for (double wi : w) total += wi;
    Durations d;
    for (int i = 0; i < 7; ++i) d[i] = lower[i] + room * w[i] / total;
    out.push_back(d);
  }
  return out;
}

/// Checks an infeasible time_domain plan of f: the honest sentence, and a law no worse at rest
/// (on the reference) than any of its own start points that keep a_max: the uniform law, the
/// symmetric families and the notch and multi_notch optima it is seeded with.
void expect_honest_least_infeasible(const Format& f, const PlanOptions& o, const PlanResult& r,
                                    const std::string& what) {
  ASSERT_TRUE(r.durations.has_value()) << what;
  EXPECT_TRUE(contains(r.message, "no law found that meets eta_rest <= 3 mm")) << what;
  EXPECT_FALSE(contains(r.message, "not reachable")) << what;
  const SloshingModel model = make_sloshing_model(f, o.model);
  const double best = reference_peaks(model, *r.durations, f.stroke, o.rest_time).rest;
  std::vector<Durations> starts = family_starts(f.motion_time, o.min_ramp);
  for (Strategy s : {Strategy::kNotch, Strategy::kMultiNotch}) {
    const PlanResult seed = plan(f, s, o);
    if (seed.usable() && seed.durations) starts.push_back(*seed.durations);
  }
  for (const Durations& d : starts) {
    // A start that breaks a_max is not admissible: the planner moves it onto the limit first.
    if (o.limits.a_max && reference_a_peak(d, f.stroke) > *o.limits.a_max * (1.0 + kLimitSlack)) {
      continue;
    }
    const double start = reference_peaks(model, d, f.stroke, o.rest_time).rest;
    EXPECT_LE(best, start * (1.0 + kNoWorse))
        << what << "; a start reaches " << start * 1e3 << " mm at rest";
  }
}

// The thesis container (800 mm) on the short motions where the old least infeasible phase
// answered "not reachable" (0.594 s: "the best is 61.8 mm") or ended just above the bound
// (0.556 s, accepted by the half-step sensitivities at 3.0006 mm): a law meeting eta_rest <= 3 mm
// exists at each (min-time's search finds one at 0.591 s and above), and the fresh plan finds it.
TEST(TimeDomainHonesty, ThesisShortMotionsMeetTheRestBoundOnTheReference) {
  for (double T : {0.556, 0.592, 0.594}) {
    Format f;
    f.container.height = 0.150;
    f.motion_time = T;
    const PlanOptions o;
    const PlanResult r = plan(f, Strategy::kTimeDomain, o);
    const std::string what = "T " + std::to_string(T) + ": " + r.message;
    ASSERT_TRUE(r.usable()) << what;
    const ReferencePeaks p =
        reference_peaks(make_sloshing_model(f, o.model), *r.durations, f.stroke, o.rest_time);
    EXPECT_LE(p.rest, o.eta_rest_max * (1.0 + kMeets)) << what;
  }
}

// Over seeded formats: min-time's search for time_domain (eta_rest <= 3 mm, eta_motion free)
// gives T_min and, at every T it found feasible (T_min and the curve above), a law that meets the
// bound. A fresh plan at each such T either meets the bound too, with an eta_motion within
// kFreshVsSearch of the search's law, or says honestly that it found none (its least infeasible
// law no worse than any of its own start points); a fresh plan 1 ms below T_min (where the
// search found none) is honest the same way.
TEST(TimeDomainHonesty, AtMinTimesBoundaryFreshPlansAreHonestAndNearTheSearchsLaw) {
  const int count = test::property_format_count(4);
  std::mt19937 rng(20261127u);
  int compared = 0;
  int flagged = 0;
  double worst = 0.0;
  for (int k = 0; k < count; ++k) {
    // The thesis container first (fresh plans there ended up to 11 % above the search's laws).
    const Format base = k == 0 ? Format{} : test::random_format(rng);
    MinTimeOptions mo;
    mo.eta_motion_max = 1.0;  // the rest bound alone decides T_min
    mo.plan.time_limit = 600.0;
    const MinTimeResult mt = min_time(base, Strategy::kTimeDomain, mo);
    char name[160];
    std::snprintf(name, sizeof name, "R %.4g mm, h %.4g mm, s %.4g mm", base.container.radius * 1e3,
                  base.fill_height * 1e3, base.stroke * 1e3);
    // acceptable: T_min found, its plan not optimal by its warnings (the rest bound alone decides
    // T_min, and the wave in motion may spill).
    const bool found = mt.status == SolveStatus::kOptimal ||
                       (mt.status == SolveStatus::kAcceptable && !mt.not_optimal.empty());
    if (!found || !mt.t_min || !mt.plan || !mt.plan->durations) {
      ADD_FAILURE() << name << ": min-time found no T_min: " << mt.message;
      continue;
    }
    PlanOptions o = mo.plan;
    o.eta_rest_max = mo.eta_rest_max;
    Format f = base;
    const SloshingModel model = make_sloshing_model(f, o.model);
    // Every T the search found feasible (T_min and the curve above it, most of them planned by
    // continuation from a neighbour's law), planned fresh.
    for (const MinTimePoint& point : mt.curve) {
      if (!point.feasible || !point.durations) continue;
      f.motion_time = point.motion_time;
      const ReferencePeaks search = reference_peaks(model, *point.durations, f.stroke, o.rest_time);
      ASSERT_LE(search.rest, o.eta_rest_max * (1.0 + kMeets)) << name;
      const PlanResult fresh = plan(f, Strategy::kTimeDomain, o);
      const std::string what = std::string(name) + ", T " + std::to_string(f.motion_time) +
                               " s (T_min " + std::to_string(*mt.t_min) + " s): " + fresh.message;
      if (fresh.usable()) {
        const ReferencePeaks p = reference_peaks(model, *fresh.durations, f.stroke, o.rest_time);
        EXPECT_LE(p.rest, o.eta_rest_max * (1.0 + kMeets)) << what;
        EXPECT_LE(p.motion, search.motion * kFreshVsSearch) << what;
        worst = std::max(worst, p.motion / search.motion);
        ++compared;
      } else {
        EXPECT_EQ(to_string(fresh.status), "infeasible") << what;
        expect_honest_least_infeasible(f, o, fresh, what);
        ++flagged;
      }
    }
    if (mt.infeasible_below) {
      f.motion_time = *mt.infeasible_below;
      const PlanResult below = plan(f, Strategy::kTimeDomain, o);
      const std::string at =
          std::string(name) + ", T " + std::to_string(f.motion_time) + " s: " + below.message;
      if (below.status == SolveStatus::kInfeasible) expect_honest_least_infeasible(f, o, below, at);
    }
  }
  std::printf(
      "[ property ] %d formats: %d fresh plans at feasible T of the search meet the bound "
      "(worst eta_motion %.6f x the search's law), %d say they found none\n",
      count, compared, worst, flagged);
}

// Over seeded a_max just above the kinematic minimum (the thesis format and seeded formats):
// wherever notch shows the limit reachable (its law keeps it), time_domain's law keeps it too,
// by A and B rebuilt from its durations, and an infeasible plan names the eta bound, not the
// limit. Below the minimum, the law carries the least reachable peak and the message names a_max.
TEST(TimeDomainHonesty, KeepsAReachableAccelerationLimitNearTheKinematicMinimum) {
  std::mt19937 rng(3556u);
  std::vector<Format> formats{Format{}};
  for (int k = 0; k < 2; ++k) formats.push_back(test::random_format(rng));
  std::uniform_real_distribution<double> exponent(-4.0, -1.3);
  int shown = 0;
  for (const Format& f : formats) {
    PlanOptions o;
    const double a_min = kinematic_minimum(f, o.min_ramp);
    for (int k = 0; k < 4; ++k) {
      const double a_max = a_min * (1.0 + std::pow(10.0, exponent(rng)));
      o.limits.a_max = a_max;
      char name[160];
      std::snprintf(name, sizeof name, "R %.4g mm, s %.4g mm, T %.4g s, a_max %.6g (min %.6g)",
                    f.container.radius * 1e3, f.stroke * 1e3, f.motion_time, a_max, a_min);
      const PlanResult notch = plan(f, Strategy::kNotch, o);
      ASSERT_TRUE(notch.durations.has_value()) << name;
      if (reference_a_peak(*notch.durations, f.stroke) > a_max * (1.0 + kLimitSlack)) continue;
      ++shown;
      const PlanResult r = plan(f, Strategy::kTimeDomain, o);
      const std::string what = std::string(name) + ": " + r.message;
      ASSERT_TRUE(r.durations.has_value()) << what;
      EXPECT_LE(reference_a_peak(*r.durations, f.stroke), a_max * (1.0 + kLimitSlack)) << what;
      double sum = 0.0;
      for (double d : *r.durations) sum += d;
      EXPECT_NEAR(sum, f.motion_time, 1e-9) << what;
      for (int i : {0, 2, 4, 6}) EXPECT_GE((*r.durations)[i], o.min_ramp - 1e-12) << what;
      if (r.status == SolveStatus::kInfeasible) {
        EXPECT_FALSE(contains(r.message, "a_max")) << what;
        expect_honest_least_infeasible(f, o, r, what);
      }
    }
    // Below the minimum: the least reachable peak, and the limit named.
    o.limits.a_max = 0.98 * a_min;
    const PlanResult r = plan(f, Strategy::kTimeDomain, o);
    ASSERT_TRUE(r.durations.has_value()) << r.message;
    EXPECT_EQ(to_string(r.status), "infeasible") << r.message;
    EXPECT_TRUE(contains(r.message, "a_max = ")) << r.message;
    EXPECT_LE(reference_a_peak(*r.durations, f.stroke), a_min * (1.0 + 1e-6)) << r.message;
  }
  EXPECT_GE(shown, 8);
}

}  // namespace test_time_domain_honesty
}  // namespace slosh
