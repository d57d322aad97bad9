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

/// The planar spherical-pendulum model (SPEC §14, docs/models.md), M q'' + C^2 |q'|^2 q +
/// 2 zeta w M q' + w^2 (1 + alpha |q|^2) q + a_h / R = 0 with M = I + C^2 q q^T, driven by the
/// 7-segment law (SPEC §3) along the path in the world frame (the container does not turn):
/// a_h = s'' T(psi) + kappa s'^2 N(psi). Classical RK4, 0.1 ms steps ending at every switch time,
/// with the tangential state (s, s') integrated alongside.
Peaks simulate(const SloshingModel& m, const Durations& d, const LineArcLine& g, double rest_time) {
  const double area_p = 0.5 * d[0] + d[1] + 0.5 * d[2];
  const double area_n = 0.5 * d[4] + d[5] + 0.5 * d[6];
  const test::TrapezoidAcceleration unit{d, 1.0, area_p / area_n};
  const auto knots = unit.knots();
  const double T = knots[7];
  using State = std::array<double, 6>;  // s, s', qx, qy, qx', qy'
  const double w = m.omega1(), c2 = m.C * m.C;
  auto run = [&](const test::TrapezoidAcceleration& a, bool drive, Peaks* out) {
    auto f = [&](double t, const State& y) {
      const double acc = t < T ? a(t) : 0.0;
      const double v = t < T ? y[1] : 0.0;
      const auto [psi, kappa] = g.at(y[0]);
      const double an = kappa * v * v;
      const double ax = drive ? acc * std::cos(psi) - an * std::sin(psi) : 0.0;
      const double ay = drive ? acc * std::sin(psi) + an * std::cos(psi) : 0.0;
      const double qx = y[2], qy = y[3], vx = y[4], vy = y[5];
      const double r2 = qx * qx + qy * qy, v2 = vx * vx + vy * vy, qv = qx * vx + qy * vy;
      const double k = w * w * (1.0 + m.alpha * r2);
      const double bx =
          -(c2 * v2 * qx + 2 * m.zeta * w * (vx + c2 * qx * qv) + k * qx + ax / m.radius);
      const double by =
          -(c2 * v2 * qy + 2 * m.zeta * w * (vy + c2 * qy * qv) + k * qy + ay / m.radius);
      const double lam = c2 * (qx * bx + qy * by) / (1.0 + c2 * r2);
      return State{y[1], acc, vx, vy, bx - lam * qx, by - lam * qy};
    };
    State y{};
    std::vector<double> cuts(knots.begin(), knots.end());
    cuts.push_back(T + rest_time);
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double L = cuts[k + 1] - cuts[k];
      if (!(L > 0.0)) continue;
      const int n = static_cast<int>(std::ceil(L / 1e-4));
      const double h = L / n;
      for (int i = 0; i < n; ++i) {
        const double t = cuts[k] + h * i;
        auto add = [](const State& base, const State& slope, double s) {
          State r;
          for (std::size_t j = 0; j < 6; ++j) r[j] = base[j] + s * slope[j];
          return r;
        };
        const double e = 1e-12;  // stages just inside the step: each sees its own piece
        const State k1 = f(t + e, y), k2 = f(t + h / 2, add(y, k1, h / 2));
        const State k3 = f(t + h / 2, add(y, k2, h / 2)), k4 = f(t + h - e, add(y, k3, h));
        for (std::size_t j = 0; j < 6; ++j) y[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
        if (out != nullptr) {
          const double eta = m.K * std::hypot(y[2], y[3]);
          double& peak = t + h <= T + 1e-12 ? out->motion : out->rest;
          peak = std::max(peak, eta);
        }
      }
    }
    return y[0];
  };
  const double A = g.length() / run(unit, false, nullptr);
  Peaks out;
  run(test::TrapezoidAcceleration{d, A, A * area_p / area_n}, true, &out);
  return out;
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
  EXPECT_TRUE(r.warnings.empty() ||
              std::none_of(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
                return w.find("worse_than_baseline") != std::string::npos;
              }));
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

}  // namespace
}  // namespace slosh
