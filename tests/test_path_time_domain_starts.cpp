// time_domain along a line-arc-line path reaches the laws a plain search finds: at 1.55 s and
// 1.7 s on a 200 mm / 90 deg r 100 mm / 200 mm path it said "no law found ... lengthen the
// motion" (12.9 and 6.5 mm at rest) although laws at 1.1 and 2.9 mm exist, and on a U-turn track
// in 2.2 s it returned "optimal" at twice the wave in motion a law meeting the bound has (more
// than the uniform law). Every figure is checked on an RK4 simulation written here.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/strategy/path_plan.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace {

constexpr double kPi = std::numbers::pi;

/// A line, a left arc and a line, as the test's simulation reads it.
struct LineArcLine {
  double line{};    ///< each line's length [m]
  double radius{};  ///< [m]
  double angle{};   ///< [rad], left
  [[nodiscard]] PlanarPath path() const {
    return PlanarPath(
        {PathElement::line(line), PathElement::arc(radius, angle), PathElement::line(line)}, 0.0,
        false);
  }
  [[nodiscard]] double length() const { return 2.0 * line + radius * angle; }
  /// Heading and curvature at arc length s (re-derived from the geometry, not the library's).
  [[nodiscard]] std::pair<double, double> at(double s) const {
    if (s < line) return {0.0, 0.0};
    if (s < line + radius * angle) return {(s - line) / radius, 1.0 / radius};
    return {angle, 0.0};
  }
};

struct Peaks {
  double motion{}, rest{};
};

/// The planar model along the path (test::planar_pendulum_peaks: SPEC §14's equations on the
/// test's own RK4, 0.1 ms steps ending at every switch time).
Peaks simulate(const SloshingModel& m, const Durations& d, const LineArcLine& g, double rest_time) {
  const test::PlanarPendulumPeaks p = test::planar_pendulum_peaks(
      {m.omega1(), m.zeta, m.C, m.alpha, m.K, m.radius}, d, g.length(),
      [&g](double s) { return g.at(s); }, rest_time, 1e-4);
  return {p.motion, p.rest};
}

/// The thesis format of the service's requests (R 48.5 mm, 150 mm high, 82 mm of water).
Format format_for(const LineArcLine& g, double motion_time) {
  Format f;
  f.container.height = 0.150;
  f.stroke = g.length();
  f.motion_time = motion_time;
  return f;
}

PlanOptions quiet_options() {
  PlanOptions o;
  o.robustness = false;
  o.time_limit = 60.0;
  return o;
}

// Feasible at 1.45-1.65 s and 1.8 s, the plan said infeasible at 1.55 s (best 12.9 mm) and 1.7 s
// (best 6.48 mm) and told the user to lengthen the motion.
TEST(PathTimeDomainStarts, LineArcLineMeetsTheBoundWhereALawExists) {
  const LineArcLine g{0.2, 0.1, kPi / 2};
  for (double T : {1.55, 1.7}) {
    const PlanOptions o = quiet_options();
    const PlanResult r = plan_on_path(format_for(g, T), g.path(), Strategy::kTimeDomain, o);
    ASSERT_EQ(r.status, SolveStatus::kOptimal) << T << ": " << r.message;
    ASSERT_TRUE(r.durations.has_value());
    EXPECT_EQ(r.message.find("lengthen the motion"), std::string::npos) << r.message;
    const Peaks sim = simulate(r.model, *r.durations, g, o.rest_time);
    EXPECT_LE(sim.rest, o.eta_rest_max * (1.0 + 1e-3)) << T;
    EXPECT_NEAR(r.prediction.nonlinear.rest.value, sim.rest, 1e-3 * sim.rest) << T;
    EXPECT_NEAR(r.prediction.nonlinear.motion.value, sim.motion, 1e-3 * sim.motion) << T;
  }
}

// U-turn track (300 mm, 180 deg r 200 mm, 300 mm) in 2.2 s: "optimal" at 42.2 mm in motion, more
// than the uniform law's 38.2 mm, where a law at 21.9 / 2.99 mm exists; infeasible at 1.9 s.
TEST(PathTimeDomainStarts, UTurnBeatsTheUniformLaw) {
  const LineArcLine g{0.3, 0.2, kPi};
  const PlanOptions o = quiet_options();
  const PlanResult r = plan_on_path(format_for(g, 2.2), g.path(), Strategy::kTimeDomain, o);
  ASSERT_EQ(r.status, SolveStatus::kOptimal) << r.message;
  ASSERT_TRUE(r.durations.has_value());
  const Peaks sim = simulate(r.model, *r.durations, g, o.rest_time);
  const Peaks uniform = simulate(r.model, uniform_durations(2.2), g, o.rest_time);
  EXPECT_LE(sim.rest, o.eta_rest_max * (1.0 + 1e-3));
  EXPECT_LT(sim.motion, uniform.motion);
  EXPECT_LT(sim.motion, 0.0225);  // the law found by a plain search: 21.95 mm
  EXPECT_FALSE(has_warning(r.warnings, WarningKind::kWorseThanBaseline));
  // At 1.9 s (min-time's T_min was 1.983 s: "infeasible, best 6.34 mm" here) a law meets both
  // of min-time's limits, eta_rest <= 3 mm and eta_motion <= 63 mm.
  const PlanResult fast = plan_on_path(format_for(g, 1.9), g.path(), Strategy::kTimeDomain, o);
  // The linear model's wave in motion reaches the free board there: acceptable, a law min-time
  // counts as meeting its limits.
  ASSERT_EQ(fast.status, SolveStatus::kAcceptable) << fast.message;
  const Peaks at_19 = simulate(fast.model, *fast.durations, g, o.rest_time);
  EXPECT_LE(at_19.rest, o.eta_rest_max * (1.0 + 1e-3));
  EXPECT_LE(at_19.motion, 0.063);
}

// Objective rest with eta_motion <= 63 mm on the line-arc-line path said "optimal" at 7.11 mm at
// rest at 1.65 s and 4.91 mm at 1.7 s, while the default objective's law (min eta_motion s.t.
// eta_rest <= 3 mm) rests at 3.00 mm with eta_motion far below 63 mm there: a law the rest
// problem admits (at 1.7 s the default objective reaches it only through its families and its
// least infeasible phase). Its answer is now at least as good, on the test's simulation.
TEST(PathTimeDomainStarts, RestObjectiveIsNeverAboveTheDefaultObjectivesLaw) {
  const LineArcLine g{0.2, 0.1, kPi / 2};
  PlanOptions o = quiet_options();
  o.objective = TimeDomainObjective::kRest;
  o.eta_motion_max = 0.063;
  for (double T : {1.65, 1.7}) {
    const PlanResult r = plan_on_path(format_for(g, T), g.path(), Strategy::kTimeDomain, o);
    ASSERT_TRUE(r.status == SolveStatus::kOptimal || r.status == SolveStatus::kAcceptable)
        << T << ": " << r.message;
    ASSERT_TRUE(r.durations.has_value());
    const Peaks sim = simulate(r.model, *r.durations, g, o.rest_time);
    EXPECT_LE(sim.motion, 0.063 * (1.0 + 1e-3)) << T;
    EXPECT_LE(sim.rest, o.eta_rest_max * (1.0 + 1e-3)) << T << ": " << r.message;
    EXPECT_NEAR(r.prediction.nonlinear.rest.value, sim.rest, 1e-3 * sim.rest) << T;
  }
}

}  // namespace
}  // namespace slosh
