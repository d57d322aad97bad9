// Planning along planar paths (SPEC §14): a time_domain plan on an arc checked by a simulation of
// the spherical-pendulum model written here, the limit to the straight line (a huge radius, a
// line in any direction), and the path's machine limits on seeded random arcs.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/strategy/path_plan.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace {

constexpr double kPi = std::numbers::pi;

/// The 90-degree index of a 300 mm rotary table in 1.2 s (SPEC §14's example).
PlanarPath table_arc(double angle_deg = 90.0, double radius = 0.3, bool turns = true) {
  return PlanarPath::arc(radius, angle_deg * kPi / 180.0, turns);
}

Format format_for(const PlanarPath& path, double motion_time) {
  Format f = thesis_format();
  f.stroke = path.length();
  f.motion_time = motion_time;
  return f;
}

PlanOptions quiet_options() {
  PlanOptions o;
  o.robustness = false;
  o.time_limit = 60.0;
  return o;
}

/// Independent simulation of the planar spherical-pendulum model, re-typed from SPEC §14 and
/// docs/models.md: M q'' + C^2 |q'|^2 q + 2 zeta w M q' + w^2 (1 + alpha |q|^2) q + a_h / R = 0,
/// M = I + C^2 q q^T, driven by the 7-segment law (rebuilt from SPEC §3) moved along an arc of
/// radius rho from heading 0, turning left: a_h = s'' T + s'^2 / rho N. Classical RK4 with the
/// tangential state (s, s') integrated alongside, on steps that end at every switch time.
struct ArcSimulation {
  double eta_motion{}, eta_rest{}, t_rest{};
};

ArcSimulation simulate_on_arc(const SloshingModel& m, const Durations& d, double length, double rho,
                              double rest_time) {
  // A and B from the two lobes' balance and the stroke: B = A area_p / area_n, then A by the
  // stroke reached with A = 1 (computed by the same integration, the law linear in A).
  const double area_p = 0.5 * d[0] + d[1] + 0.5 * d[2];
  const double area_n = 0.5 * d[4] + d[5] + 0.5 * d[6];
  test::TrapezoidAcceleration unit{d, 1.0, area_p / area_n};
  const auto knots = unit.knots();
  const double T = knots[7];
  using State = std::array<double, 6>;  // s, s', qx, qy, qx', qy'
  const double w = m.omega1(), c2 = m.C * m.C;
  auto run = [&](const test::TrapezoidAcceleration& a, bool drive, ArcSimulation* out) {
    auto f = [&](double t, const State& y) {
      const double acc = t < T ? a(t) : 0.0;
      const double v = t < T ? y[1] : 0.0;
      const double psi = y[0] / rho;
      const double ax = drive ? acc * std::cos(psi) - v * v / rho * std::sin(psi) : 0.0;
      const double ay = drive ? acc * std::sin(psi) + v * v / rho * std::cos(psi) : 0.0;
      const double qx = y[2], qy = y[3], vx = y[4], vy = y[5];
      const double r2 = qx * qx + qy * qy, v2 = vx * vx + vy * vy, qv = qx * vx + qy * vy;
      // b = -(C^2 |q'|^2 q + 2 zeta w M q' + w^2 (1 + alpha r2) q + a / R); q'' = M^-1 b.
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
      const int n = static_cast<int>(std::ceil(L / 2e-4));
      const double h = L / n;
      for (int i = 0; i < n; ++i) {
        const double t = cuts[k] + h * i;
        auto add = [](const State& a, const State& b, double s) {
          State r;
          for (std::size_t j = 0; j < 6; ++j) r[j] = a[j] + s * b[j];
          return r;
        };
        // Stages just inside the step, so each sees the piece it belongs to.
        const double e = 1e-12;
        const State k1 = f(t + e, y), k2 = f(t + h / 2, add(y, k1, h / 2));
        const State k3 = f(t + h / 2, add(y, k2, h / 2)), k4 = f(t + h - e, add(y, k3, h));
        for (std::size_t j = 0; j < 6; ++j) y[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
        if (out != nullptr) {
          const double eta = m.K * std::hypot(y[2], y[3]);
          if (t + h <= T + 1e-12) {
            out->eta_motion = std::max(out->eta_motion, eta);
          } else if (eta > out->eta_rest) {
            out->eta_rest = eta;
            out->t_rest = t + h;
          }
        }
      }
    }
    return y[0];
  };
  const double unit_stroke = run(unit, false, nullptr);
  const double A = length / unit_stroke;
  ArcSimulation out;
  run(test::TrapezoidAcceleration{d, A, A * area_p / area_n}, true, &out);
  return out;
}

TEST(PathPlan, TimeDomainOnAnArcHoldsOnAnIndependentSimulation) {
  const PlanarPath arc = table_arc();
  const Format f = format_for(arc, 1.2);
  const PlanOptions o = quiet_options();
  const PlanResult r = plan_on_path(f, arc, Strategy::kTimeDomain, o);
  ASSERT_EQ(r.status, SolveStatus::kOptimal) << r.message;
  ASSERT_TRUE(r.durations.has_value());
  const ArcSimulation sim = simulate_on_arc(r.model, *r.durations, arc.length(), 0.3, o.rest_time);
  // The bound holds on the independent simulation (its 0.2 ms steps sample the peak to ~1e-4).
  EXPECT_LE(sim.eta_rest, o.eta_rest_max * (1.0 + 1e-3));
  // The plan's verified peaks are the simulation's (the liquid's spin adds < 1e-7 mm here).
  EXPECT_NEAR(r.prediction.nonlinear.rest.value, sim.eta_rest, 2e-4 * sim.eta_rest);
  EXPECT_NEAR(r.prediction.nonlinear.motion.value, sim.eta_motion, 2e-4 * sim.eta_motion);
  // It beats the uniform law, which the same simulation checks too.
  const ArcSimulation uniform =
      simulate_on_arc(r.model, uniform_durations(1.2), arc.length(), 0.3, o.rest_time);
  EXPECT_NEAR(r.baseline.nonlinear.motion.value, uniform.eta_motion, 2e-4 * uniform.eta_motion);
  EXPECT_LT(sim.eta_motion, uniform.eta_motion);
  // The straight line's time_domain plan of the same length does not hold the bound on the arc:
  // the normal acceleration matters, and this test would see a plan that ignored it.
  const PlanResult line = plan(f, Strategy::kTimeDomain, o);
  ASSERT_TRUE(line.durations.has_value());
  const ArcSimulation line_on_arc =
      simulate_on_arc(r.model, *line.durations, arc.length(), 0.3, o.rest_time);
  EXPECT_GT(line_on_arc.eta_rest, o.eta_rest_max * 1.05);
  EXPECT_NE(r.message.find("time_domain optimised the planar nonlinear model along the path"),
            std::string::npos)
      << r.message;
}

}  // namespace
}  // namespace slosh
