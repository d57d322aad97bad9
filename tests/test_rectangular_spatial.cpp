// A rectangular tank along arcs, paths and trajectories (SPEC §14 with §15) against independent
// computations: the line's answer in the limits where the motion is a line, the steady state of
// the 2-D oscillator under a circular motion in closed form, and a fine-step RK4 of the
// per-direction modal equations driven by the rotated acceleration, re-typed here.

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/calibration_container.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/spatial_simulate.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/response/rectangular_nonlinear_direction.hpp"
#include "slosh/core/response/rectangular_planar.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "slosh/core/strategy/path_plan.hpp"
#include "support/rectangular_reference.hpp"

namespace slosh {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

Fluid water() {
  return thesis_format().fluid;
}

PlanarOptions no_spin() {
  PlanarOptions o;
  o.spin = SpinLag::kNone;
  return o;
}

TEST(RectangularSpatial, HugeRadiusArcTendsToTheLine) {
  const double L = 0.12, W = 0.08, h = 0.05, stroke = 0.3, rest = 1.0;
  const MotionLaw law = SevenSegmentLaw(uniform_durations(0.6), stroke).law();
  for (double phi : {0.0, 30.0, 90.0, -120.0}) {
    const RectangularModel model = make_rectangular_model({L, W, phi}, h, water());
    const RectangularPeaks line = RectangularLinearResponse(model, law, rest).peaks();
    const RectangularNonlinearPeaks line_nl = rectangular_nonlinear_peaks(model, law, rest);
    for (bool turns : {true, false}) {
      const double radius = 1e6;  // normal acceleration and turn O(1e-6) of the line's
      const PlanarDrive drive(PlanarPath::arc(radius, stroke / radius, turns), law);
      const RectangularPlanarPeaks arc =
          rectangular_planar_linear_peaks(model, drive, phi * kDeg, rest);
      EXPECT_NEAR(arc.highest.motion.value / line.highest.motion.value, 1.0, 1e-5) << phi;
      EXPECT_NEAR(arc.highest.rest.value / line.highest.rest.value, 1.0, 1e-5) << phi;
      EXPECT_NEAR(arc.along_length.rest.value, line.along_length.rest.value,
                  1e-5 * line.highest.rest.value)
          << phi;
      const RectangularPlanarNonlinearPeaks arc_nl =
          rectangular_planar_nonlinear_peaks(model, drive, phi * kDeg, rest);
      EXPECT_EQ(arc_nl.nonlinear, line_nl.nonlinear) << phi;
      EXPECT_NEAR(arc_nl.peaks.highest.motion.value / line_nl.peaks.highest.motion.value, 1.0, 1e-5)
          << phi;
      EXPECT_NEAR(arc_nl.peaks.highest.rest.value / line_nl.peaks.highest.rest.value, 1.0, 1e-5)
          << phi;
    }
  }
}

TEST(RectangularSpatial, TankKeepingItsOrientationOnATurnedLineIsTheLineAtMinusThatAngle) {
  // The tank's L axis along world x, the line at angle d: the motion is at -d from L.
  const double L = 0.12, W = 0.09, h = 0.06, stroke = 0.25, rest = 0.8;
  const MotionLaw law = make_poly5_law(stroke, 0.5);
  for (double d : {25.0, 90.0, 160.0, -70.0}) {
    const RectangularModel on_line = make_rectangular_model({L, W, -d}, h, water());
    const RectangularPeaks line = RectangularLinearResponse(on_line, law, rest).peaks();
    const RectangularNonlinearPeaks line_nl = rectangular_nonlinear_peaks(on_line, law, rest);
    const RectangularModel tank = make_rectangular_model({L, W, 0.0}, h, water());
    const PlanarDrive drive(PlanarPath::line(stroke, d * kDeg), law);
    const RectangularPlanarPeaks p = rectangular_planar_linear_peaks(tank, drive, 0.0, rest);
    EXPECT_NEAR(p.highest.motion.value / line.highest.motion.value, 1.0, 1e-7) << d;
    EXPECT_NEAR(p.highest.rest.value / line.highest.rest.value, 1.0, 1e-7) << d;
    const RectangularPlanarNonlinearPeaks nl =
        rectangular_planar_nonlinear_peaks(tank, drive, 0.0, rest);
    EXPECT_NEAR(nl.peaks.highest.motion.value / line_nl.peaks.highest.motion.value, 1.0, 1e-5) << d;
    EXPECT_NEAR(nl.peaks.highest.rest.value / line_nl.peaks.highest.rest.value, 1.0, 1e-5) << d;
  }
}

TEST(RectangularSpatial, SquareTankOnACircleAtConstantSpeedIsInvariantInItsOrientation) {
  // The centre on a circle of radius r at rate Om: the acceleration r Om^2 turns with it. In
  // the tank's frame each mode of either direction is driven by r Om^2 cos(Om t - b); the
  // steady waves are E cos(Om t - b - Phi) and E sin(...) with E = |sum_n G_n A_n e^{-i phi_n}|
  // (A_n, phi_n the oscillator's amplitude and lag), so the highest corner is sqrt(2) E
  // whatever the tank's orientation b.
  const double side = 0.1, h = 0.05, r = 0.05, om = 9.0;
  RectangularModelOptions mo;
  mo.explicit_zeta = 0.08;  // steady in a few seconds
  TrajectorySamples samples;
  const double dt = 1e-3, T = 8.0;
  for (int i = 0; i <= static_cast<int>(T / dt); ++i) {
    const double t = i * dt;
    samples.t.push_back(t);
    samples.x.push_back(r * std::cos(om * t));
    samples.y.push_back(r * std::sin(om * t));
  }
  const SampledTrajectory trajectory(samples);
  const PlanarDrive drive(trajectory);
  const test::Modes modes = test::direction(side, side, h, 1.0, 3);
  std::complex<double> e{};
  for (std::size_t n = 0; n < modes.w.size(); ++n) {
    const double w = modes.w[n];
    e += modes.g[n] * r * om * om /
         std::complex<double>(w * w - om * om, 2.0 * mo.explicit_zeta.value() * w * om);
  }
  const double expected = std::sqrt(2.0) * std::abs(e);
  for (double b : {0.0, 20.0, 45.0, -110.0}) {
    const RectangularModel model = make_rectangular_model({side, side, 0.0}, h, water(), mo);
    const RectangularPlanarResponse resp(model, drive, b * kDeg, 0.5,
                                         RectangularPlanarModel::kLinear);
    double peak = 0.0;
    for (double t = 6.5; t < 7.5; t += 1e-4) peak = std::max(peak, resp.eta_highest(t));
    EXPECT_NEAR(peak / expected, 1.0, 2e-4) << b;
  }
}

TEST(RectangularSpatial, ATankSpunInPlaceRisesAtTheCornersByTheLaggingVortex) {
  // The centre at rest, the tank turning at a constant Om: no wave, only the liquid's spin
  // w_l = Om (1 - exp(-k t)), k = sqrt(nu Om) / h (the Ekman lag, Om = max(|theta'|, |w_l|)),
  // raising the corners by (L^2 + W^2) w_l^2 / (12 g) over the mean level.
  const double L = 0.12, W = 0.08, h = 0.05, om = 3.0, nu = 1e-6;
  TrajectorySamples samples;
  for (int i = 0; i <= 2000; ++i) {
    const double t = i * 0.01;
    samples.t.push_back(t);
    samples.x.push_back(0.0);
    samples.y.push_back(0.0);
    samples.theta.push_back(om * t);
  }
  const PlanarDrive drive{SampledTrajectory(samples)};
  const RectangularModel model = make_rectangular_model({L, W, 0.0}, h, water());
  const RectangularPlanarResponse r(model, drive, 0.0, 0.0, RectangularPlanarModel::kLinear);
  const double k = std::sqrt(nu * om) / h;
  for (double t : {1.0, 7.5, 19.0}) {
    const double w = om * (1.0 - std::exp(-k * t));
    const double rise = (L * L + W * W) * w * w / (12.0 * 9.81);
    EXPECT_NEAR(r.spin_rise(t) / rise, 1.0, 1e-6) << t;
    EXPECT_NEAR(r.eta_highest(t) / rise, 1.0, 1e-6) << t;
  }
  EXPECT_NEAR(r.peaks().highest.motion.value / r.spin_rise(20.0), 1.0, 1e-9);
}

// ---- The linear tank along an arc against a fine-step RK4 of the rotated forcing ----

struct ArcCase {
  double radius, angle_deg, orientation_deg;
  bool turns;
};

/// Peaks of sum over directions |sum_n G_n x_n| with x_n'' + 2 zeta w_n x_n' + w_n^2 x_n = -a_d,
/// a_d the tank-frame component of the arc's acceleration s'' T + s'^2 / R N (left turn). With
/// `spin`, plus the forced vortex's corner rise (L^2 + W^2) w^2 / (12 g) of the liquid's spin w,
/// w' = sqrt(nu max(|theta'|, |w|)) / h (theta' - w), theta' = kappa s' (nu = 1e-6 m^2/s).
test::RefPeaks arc_reference(double L, double W, double h, const ArcCase& c, const MotionLaw& law,
                             double rest, double dt, bool spin = false) {
  const std::vector<test::Modes> dirs = {test::direction(L, W, h, 1.0, 3),
                                         test::direction(W, L, h, 1.0, 3)};
  const double T = law.duration(), phi = c.orientation_deg * kDeg;
  auto turn_rate = [&](double t) {
    if (t >= T || !c.turns) return 0.0;
    return (c.angle_deg > 0 ? 1.0 : -1.0) / c.radius * law.at(t).velocity;
  };
  auto spin_rate = [&](double t, double w) {
    const double th = turn_rate(t);
    return std::sqrt(1e-6 * std::max(std::abs(th), std::abs(w))) / h * (th - w);
  };
  double spin_w = 0.0;
  const double spin_gain = spin ? (L * L + W * W) / (12.0 * 9.81) : 0.0;
  auto forcing = [&](double t, double out[2]) {
    out[0] = out[1] = 0.0;
    if (t >= T) return;
    const KinematicState k = law.at(t);
    const double psi = (c.angle_deg > 0 ? 1.0 : -1.0) * k.position / c.radius;  // tangent
    const double kappa = (c.angle_deg > 0 ? 1.0 : -1.0) / c.radius;
    const double ax =
        k.acceleration * std::cos(psi) - kappa * k.velocity * k.velocity * std::sin(psi);
    const double ay =
        k.acceleration * std::sin(psi) + kappa * k.velocity * k.velocity * std::cos(psi);
    const double frame = phi + (c.turns ? psi : 0.0);
    out[0] = ax * std::cos(frame) + ay * std::sin(frame);
    out[1] = -ax * std::sin(frame) + ay * std::cos(frame);
  };
  struct State {
    double x{}, v{};
  };
  std::vector<std::vector<State>> s(2, std::vector<State>(3));
  test::RefPeaks p;
  const auto steps = static_cast<long>(std::llround((T + rest) / dt));
  for (long i = 0; i < steps; ++i) {
    const double t = static_cast<double>(i) * dt;
    double a0[2], am[2], a1[2];
    forcing(t, a0);
    forcing(t + dt / 2, am);
    forcing(t + dt, a1);
    double eta = 0.0;
    for (std::size_t d = 0; d < 2; ++d) {
      double eta_d = 0.0;
      for (std::size_t n = 0; n < 3; ++n) {
        const double w = dirs[d].w[n], z = dirs[d].zeta;
        auto f = [&](double x, double v, double a) { return -2 * z * w * v - w * w * x - a; };
        State& q = s[d][n];
        const double k1x = q.v, k1v = f(q.x, q.v, a0[d]);
        const double k2x = q.v + dt / 2 * k1v, k2v = f(q.x + dt / 2 * k1x, k2x, am[d]);
        const double k3x = q.v + dt / 2 * k2v, k3v = f(q.x + dt / 2 * k2x, k3x, am[d]);
        const double k4x = q.v + dt * k3v, k4v = f(q.x + dt * k3x, k4x, a1[d]);
        q.x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
        q.v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
        eta_d += dirs[d].g[n] * q.x;
      }
      eta += std::abs(eta_d);
    }
    if (spin) {
      const double k1 = spin_rate(t, spin_w), k2 = spin_rate(t + dt / 2, spin_w + dt / 2 * k1);
      const double k3 = spin_rate(t + dt / 2, spin_w + dt / 2 * k2);
      const double k4 = spin_rate(t + dt, spin_w + dt * k3);
      spin_w += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      eta += spin_gain * spin_w * spin_w;
    }
    const double t1 = static_cast<double>(i + 1) * dt;
    if (t1 <= T + 1e-12) {
      p.motion = std::max(p.motion, eta);
    } else {
      p.rest = std::max(p.rest, eta);
    }
  }
  return p;
}

TEST(RectangularSpatial, LinearTankOnAnArcMatchesAFineStepIntegrationOfTheRotatedForcing) {
  const double L = 0.12, W = 0.08, h = 0.05, rest = 1.0;
  for (const ArcCase& c : {ArcCase{0.3, 90.0, 0.0, true}, ArcCase{0.25, -120.0, 30.0, true},
                           ArcCase{0.4, 60.0, 90.0, false}, ArcCase{0.2, 180.0, -45.0, false}}) {
    const double stroke = c.radius * std::abs(c.angle_deg) * kDeg;
    const MotionLaw law = make_modified_trapezoid_law(stroke, 0.7);
    const RectangularModel model = make_rectangular_model({L, W, c.orientation_deg}, h, water());
    const PlanarDrive drive(PlanarPath::arc(c.radius, c.angle_deg * kDeg, c.turns), law);
    const RectangularPlanarPeaks p =
        rectangular_planar_linear_peaks(model, drive, c.orientation_deg * kDeg, rest, no_spin());
    const test::RefPeaks ref = arc_reference(L, W, h, c, law, rest, 2e-5);
    EXPECT_NEAR(p.highest.motion.value / ref.motion, 1.0, 1e-6) << c.angle_deg;
    EXPECT_NEAR(p.highest.rest.value / ref.rest, 1.0, 1e-6) << c.angle_deg;
  }
}

TEST(RectangularSpatial, PlanForATankOnANinetyDegreeTableIsVerifiedByAnIndependentSimulation) {
  // A 120 x 80 mm cup, 50 mm of water, on a 300 mm table indexing 90 degrees in 1.2 s, turning
  // with it: the plan's linear figures are those of the fine-step integration of its law, the
  // liquid's spin included, and the planned law sloshes less than the uniform one.
  const double L = 0.12, W = 0.08, h = 0.05;
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{L, W, 0.0};
  f.fill_height = h;
  f.motion_time = 1.2;
  const PlanarPath table = PlanarPath::arc(0.3, kPi / 2, true);
  for (Strategy s : {Strategy::kMultiNotch, Strategy::kTimeDomain, Strategy::kAuto}) {
    PlanOptions o;
    o.robustness = false;
    const PlanResult r = plan_on_path(f, table, s, o);
    ASSERT_FALSE(r.invalid_input) << r.message;
    ASSERT_TRUE(r.rectangular.has_value());
    const test::RefPeaks ref =
        arc_reference(L, W, h, {0.3, 90.0, 0.0, true}, r.law, o.rest_time, 2e-5, true);
    EXPECT_NEAR(r.prediction.linear.motion.value / ref.motion, 1.0, 1e-5) << to_string(s);
    EXPECT_NEAR(r.prediction.linear.rest.value / ref.rest, 1.0, 1e-5) << to_string(s);
    EXPECT_LT(r.prediction.nonlinear.rest.value, r.baseline.nonlinear.rest.value) << r.message;
    EXPECT_NE(r.message.find("the tank's models"), std::string::npos) << r.message;
  }
}

// time_domain for a tank on a table optimises the line's models and is verified along the arc;
// where that law breaks the bound (3.9 mm at rest here) while one of its own starts meets it, the
// plan is that start, never "infeasible" with a law worse than the uniform law. The returned law's
// linear figures are checked on the fine-step integration written here.
TEST(RectangularSpatial, TimeDomainOnATableIsNeverWorseThanItsOwnStarts) {
  const double L = 0.12, W = 0.08, h = 0.04;
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{L, W, 0.0};
  f.container.height = 0.1;
  f.fill_height = h;
  f.motion_time = 1.5;
  const PlanarPath table = PlanarPath::arc(0.3, kPi / 2, true);
  PlanOptions o;
  o.robustness = false;
  const PlanResult r = plan_on_path(f, table, Strategy::kTimeDomain, o);
  ASSERT_FALSE(r.invalid_input) << r.message;
  EXPECT_EQ(r.status, SolveStatus::kAcceptable) << r.message;
  EXPECT_LE(r.prediction.nonlinear.rest.value, o.eta_rest_max);
  EXPECT_LE(r.prediction.nonlinear.rest.value, r.baseline.nonlinear.rest.value);
  EXPECT_LE(r.prediction.nonlinear.motion.value, r.baseline.nonlinear.motion.value);
  const test::RefPeaks ref =
      arc_reference(L, W, h, {0.3, 90.0, 0.0, true}, r.law, o.rest_time, 2e-5, true);
  EXPECT_NEAR(r.prediction.linear.rest.value / ref.rest, 1.0, 1e-5);
  EXPECT_LE(ref.rest, o.eta_rest_max);
  EXPECT_EQ(r.message.substr(0, 94),
            "time_domain acceptable: notch's law, one of time_domain's starts, meets eta_rest <= 3 "
            "mm along");
  for (const std::string& w : warning_texts(r.warnings))
    EXPECT_EQ(w.find("worse_than_baseline"), std::string::npos);
}

/// The nonlinear model along an arc by RK4 at step dt, re-typed from docs/models.md: per
/// direction the dominant mode xbar'' = -2 zeta w1 xbar' - w1^2 xbar (1 + alpha xbar^2) - a/side,
/// the higher modes x_n'' = -2 zeta w_n x_n' - w_n^2 x_n - a, the second mode b'' = -2 zeta s2 b'
/// - s2^2 b - d4 beta beta'' - d5 beta'^2 with beta = G_1 side xbar; the corner
/// |K xbar_L + sum G x_L| + |K xbar_W + sum G x_W| + |b_L + b_W| (K = G_1 side, no gain).
test::RefPeaks nonlinear_arc_reference(const RectangularModel& m, const ArcCase& c,
                                       const MotionLaw& law, double rest, double dt) {
  const double T = law.duration(), phi = c.orientation_deg * kDeg;
  const double sign = c.angle_deg > 0 ? 1.0 : -1.0;
  auto forcing = [&](double t, double out[2]) {
    out[0] = out[1] = 0.0;
    if (t >= T) return;
    const KinematicState k = law.at(t);
    const double psi = sign * k.position / c.radius, kappa = sign / c.radius;
    const double an = kappa * k.velocity * k.velocity;
    const double ax = k.acceleration * std::cos(psi) - an * std::sin(psi);
    const double ay = k.acceleration * std::sin(psi) + an * std::cos(psi);
    const double frame = phi + (c.turns ? psi : 0.0);
    out[0] = ax * std::cos(frame) + ay * std::sin(frame);
    out[1] = -ax * std::sin(frame) + ay * std::cos(frame);
  };
  const SloshingModel* dirs[2] = {&m.along_length, &m.along_width};
  const std::size_t M = m.along_length.omega.size();
  const std::size_t n_state = 2 * (M + 1);
  // State per direction: xbar, x_2..x_M, b; rates alike.
  auto rhs = [&](const std::vector<double>& x, const std::vector<double>& v, const double a[2],
                 std::vector<double>& out) {
    for (std::size_t d = 0; d < 2; ++d) {
      const SloshingModel& sm = *dirs[d];
      const RectangularSecondMode s2 = rectangular_second_mode(sm);
      const std::size_t o = d * (M + 1);
      const double w1 = sm.omega[0], z = sm.zeta;
      const double xdd =
          -2 * z * w1 * v[o] - w1 * w1 * x[o] * (1 + sm.alpha * x[o] * x[o]) - a[d] / sm.radius;
      out[o] = xdd;
      for (std::size_t n = 1; n < M; ++n) {
        const double w = sm.omega[n];
        out[o + n] = -2 * z * w * v[o + n] - w * w * x[o + n] - a[d];
      }
      const double kr = sm.K;  // G_1 side
      const double b = kr * x[o], bd = kr * v[o], bdd = kr * xdd;
      out[o + M] = -2 * z * s2.sigma2 * v[o + M] - s2.sigma2 * s2.sigma2 * x[o + M] -
                   s2.d4 * b * bdd - s2.d5 * bd * bd;
    }
  };
  auto corner = [&](const std::vector<double>& x) {
    double odd[2], even = 0.0;
    for (std::size_t d = 0; d < 2; ++d) {
      const std::size_t o = d * (M + 1);
      odd[d] = dirs[d]->K * x[o];
      for (std::size_t n = 1; n < M; ++n) odd[d] += dirs[d]->eta_gain[n] * x[o + n];
      even += x[o + M];
    }
    return std::abs(odd[0]) + std::abs(odd[1]) + std::abs(even);
  };
  std::vector<double> x(n_state, 0.0), v(n_state, 0.0), k1x, k1v(n_state), k2x, k2v(n_state), k3x,
      k3v(n_state), k4x, k4v(n_state), tx(n_state), tv(n_state);
  test::RefPeaks p;
  const auto steps = static_cast<long>(std::llround((T + rest) / dt));
  for (long i = 0; i < steps; ++i) {
    const double t = static_cast<double>(i) * dt;
    double a0[2], am[2], a1[2];
    forcing(t, a0);
    forcing(t + dt / 2, am);
    forcing(t + dt, a1);
    rhs(x, v, a0, k1v);
    k1x = v;
    for (std::size_t j = 0; j < n_state; ++j) {
      tx[j] = x[j] + dt / 2 * k1x[j];
      tv[j] = v[j] + dt / 2 * k1v[j];
    }
    rhs(tx, tv, am, k2v);
    k2x = tv;
    for (std::size_t j = 0; j < n_state; ++j) {
      tx[j] = x[j] + dt / 2 * k2x[j];
      tv[j] = v[j] + dt / 2 * k2v[j];
    }
    rhs(tx, tv, am, k3v);
    k3x = tv;
    for (std::size_t j = 0; j < n_state; ++j) {
      tx[j] = x[j] + dt * k3x[j];
      tv[j] = v[j] + dt * k3v[j];
    }
    rhs(tx, tv, a1, k4v);
    k4x = tv;
    for (std::size_t j = 0; j < n_state; ++j) {
      x[j] += dt / 6 * (k1x[j] + 2 * k2x[j] + 2 * k3x[j] + k4x[j]);
      v[j] += dt / 6 * (k1v[j] + 2 * k2v[j] + 2 * k3v[j] + k4v[j]);
    }
    const double eta = corner(x);
    if (static_cast<double>(i + 1) * dt <= T + 1e-12) {
      p.motion = std::max(p.motion, eta);
    } else {
      p.rest = std::max(p.rest, eta);
    }
  }
  return p;
}

TEST(RectangularSpatial, NonlinearTankOnAnArcMatchesAFineStepIntegrationOfTheRotatedForcing) {
  // A deep fill (h / side >= 0.4 both ways) and a gentle index: inside the model's range.
  const double L = 0.1, W = 0.08, h = 0.05, rest = 1.0;
  for (const ArcCase& c : {ArcCase{0.3, 90.0, 0.0, true}, ArcCase{0.25, -60.0, 40.0, false}}) {
    const double stroke = c.radius * std::abs(c.angle_deg) * kDeg;
    const MotionLaw law = make_poly5_law(stroke, 1.6);
    const RectangularModel model = make_rectangular_model({L, W, c.orientation_deg}, h, water());
    const PlanarDrive drive(PlanarPath::arc(c.radius, c.angle_deg * kDeg, c.turns), law);
    const RectangularPlanarNonlinearPeaks p =
        rectangular_planar_nonlinear_peaks(model, drive, c.orientation_deg * kDeg, rest, no_spin());
    ASSERT_TRUE(p.nonlinear) << p.warning;
    const test::RefPeaks ref = nonlinear_arc_reference(model, c, law, rest, 2e-5);
    EXPECT_NEAR(p.peaks.highest.motion.value / ref.motion, 1.0, 1e-5) << c.angle_deg;
    EXPECT_NEAR(p.peaks.highest.rest.value / ref.rest, 1.0, 1e-5) << c.angle_deg;
    // And it is not the linear model's answer.
    const RectangularPlanarPeaks lin =
        rectangular_planar_linear_peaks(model, drive, c.orientation_deg * kDeg, rest, no_spin());
    EXPECT_GT(std::abs(lin.highest.rest.value / ref.rest - 1.0), 1e-3) << c.angle_deg;
  }
}

TEST(RectangularSpatial, TheRobustnessSweepAlongAPathIsTheTanksModels) {
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{0.12, 0.08, 20.0};
  f.fill_height = 0.05;
  f.motion_time = 1.2;
  const PlanarPath table = PlanarPath::arc(0.3, kPi / 2, true);
  PlanOptions o;
  o.robustness = true;
  const PlanResult r = plan_on_path(f, table, Strategy::kNotch, o);
  ASSERT_TRUE(r.robustness.has_value()) << r.message;
  bool zero = false;
  for (const RobustnessPoint& p : r.robustness->points) {
    if (p.delta != 0.0) continue;
    zero = true;
    EXPECT_DOUBLE_EQ(p.nonlinear.rest.value, r.prediction.nonlinear.rest.value);
    EXPECT_DOUBLE_EQ(p.linear.motion.value, r.prediction.linear.motion.value);
  }
  EXPECT_TRUE(zero);
}

// ---- The answers of the API ----

nlohmann::json cup_format(double orientation_deg) {
  return {{"container",
           {{"shape", "rectangular"},
            {"length_mm", 120},
            {"width_mm", 80},
            {"height_mm", 150},
            {"orientation_deg", orientation_deg}}},
          {"fill_height_mm", 50},
          {"fluid", "water"},
          {"motion_time_s", 0.9}};
}

TEST(RectangularSpatialApi, ALineOrAStraightPathAtAnyHeadingIsTheStraightStroke) {
  // orientation_deg is measured from the motion's own direction: the heading of the line (or
  // of a path's start) does not change the answer; the straight stroke is the line model.
  for (double orientation : {0.0, 35.0, -90.0}) {
    nlohmann::json stroke = {{"format", cup_format(orientation)},
                             {"law", {{"type", "seven_segment_uniform"}}}};
    stroke["format"]["stroke_mm"] = 250;
    const nlohmann::json line_answer = api::simulate_response(stroke);
    for (const nlohmann::json& motion :
         {nlohmann::json{{"type", "line"}, {"length_mm", 250}, {"direction_deg", 70}},
          nlohmann::json{{"type", "path"},
                         {"segments", {{{"line_mm", 250}}}},
                         {"start_heading_deg", -130},
                         {"container_turns", false}}}) {
      nlohmann::json body = {{"format", cup_format(orientation)},
                             {"law", {{"type", "seven_segment_uniform"}}}};
      body["format"]["motion"] = motion;
      const nlohmann::json out = api::simulate_response(body);
      for (const char* model : {"linear", "nonlinear"}) {
        for (const char* peak : {"eta_motion_mm", "eta_rest_mm"}) {
          EXPECT_NEAR(out["prediction"][model][peak].get<double>() /
                          line_answer["prediction"][model][peak].get<double>(),
                      1.0, 1e-5)
              << orientation << " " << motion.dump() << " " << model << " " << peak;
        }
      }
    }
  }
}

TEST(RectangularSpatialApi, ACalibrationAlongOneSideDoesNotCoverATurningMotion) {
  Format measured = thesis_format();
  measured.container.rectangular = RectangularTank{0.12, 0.08, 0.0};
  const nlohmann::json stored = {{"container", api::fitted_container_json(measured)}};
  nlohmann::json body = {{"format", cup_format(0.0)}, {"strategy", "baseline"}};
  body["format"]["motion"] = {{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}};
  std::string message;
  try {
    api::check_calibrated_container(stored, body, "cup");
  } catch (const api::ApiError& e) {
    message = e.field() + " | " + e.what();
  }
  EXPECT_EQ(message,
            "options.model | options.model = \"cup\" was fitted on a rectangular container 120 x "
            "80 mm moved along its length; this request's container is a rectangular container "
            "120 x 80 mm moved along both of its sides: a calibration applies only to the "
            "container and the directions it was measured on (calibrate this one, or give its "
            "numbers as an options.model object)");
  // Along a line at the calibrated orientation it applies.
  body["format"]["motion"] = {{"type", "line"}, {"length_mm", 200}, {"direction_deg", 40}};
  EXPECT_NO_THROW(api::check_calibrated_container(stored, body, "cup"));
}

// A tank spun about its own axis (a robot turning it in place, 4 rad/s^2 up to 6 rad/s and back):
// the yaw-driven modes the model leaves out are all that moves the liquid, so the answer (the
// spin rise alone) says it is a lower bound; a tank on a 300 mm table (yaw share 0.24) does not.
TEST(RectangularSpatialApi, ATankTurnedInPlaceSaysTheYawModesAreLeftOut) {
  nlohmann::json t = nlohmann::json::array(), x = nlohmann::json::array(),
                 th = nlohmann::json::array();
  for (int i = 0; i <= 600; ++i) {
    const double time = i * 0.005;
    const double u = time - 1.5;
    const double theta = time <= 1.5 ? 2.0 * time * time : 4.5 + 6.0 * u - 2.0 * u * u;
    t.push_back(time);
    x.push_back(0.0);
    th.push_back(theta * 180.0 / kPi);
  }
  nlohmann::json body = {{"format", cup_format(0.0)}};
  body["format"].erase("motion_time_s");
  body["format"]["motion"] = {
      {"type", "trajectory"}, {"t_s", t}, {"x_mm", x}, {"y_mm", x}, {"theta_deg", th}};
  const nlohmann::json out = api::simulate_response(body);
  // The lowest yaw mode, (1, 1): k = pi sqrt(1/L^2 + 1/W^2), w^2 = g k tanh(k h).
  const double k = kPi * std::sqrt(1.0 / (0.12 * 0.12) + 1.0 / (0.08 * 0.08));
  char f11[16];
  std::snprintf(f11, sizeof f11, "%.3g", std::sqrt(9.81 * k * std::tanh(k * 0.05)) / (2 * kPi));
  std::string yaw;
  for (const auto& w : out["warnings"]) {
    if (w.get<std::string>().rfind("yaw modes", 0) == 0) yaw = w.get<std::string>();
  }
  const std::string head =
      "yaw modes not modelled: the tank turns with an angular acceleration up to ";
  ASSERT_EQ(yaw.substr(0, head.size()), head) << out["warnings"].dump();
  EXPECT_NE(yaw.find(" m/s^2 at its corners, against a peak horizontal acceleration of 0 m/s^2), "
                     "which drives the modes odd in both directions (the lowest at " +
                     std::string(f11) +
                     " Hz) that the model leaves out: the prediction is a lower bound"),
            std::string::npos)
      << yaw;
  nlohmann::json table = {{"format", cup_format(0.0)},
                          {"law", {{"type", "seven_segment_uniform"}}}};
  table["format"]["motion_time_s"] = 1.2;
  table["format"]["motion"] = {
      {"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}, {"container_turns", true}};
  for (const auto& w : api::simulate_response(table)["warnings"]) {
    EXPECT_NE(w.get<std::string>().rfind("yaw modes", 0), 0u) << w;
  }
}

// A tank turned twice round a table: every wall angle it reports is in (-180, 180], as the
// cylinder's (it gave -246.5 deg and series up to 866 deg), the same direction as the raw sum.
TEST(RectangularSpatialApi, WallAnglesOfATankTurnedTwiceAreInOneTurn) {
  nlohmann::json body = {{"format", cup_format(170.0)},
                         {"law", {{"type", "seven_segment_uniform"}}},
                         {"sample_period_s", 0.01}};
  body["format"]["motion_time_s"] = 6.0;
  body["format"]["motion"] = {{"type", "arc"},
                              {"radius_mm", 300},
                              {"angle_deg", -720},
                              {"container_turns", true},
                              {"start_heading_deg", -170}};
  const nlohmann::json out = api::simulate_response(body);
  std::vector<double> angles;
  for (const char* model : {"linear", "nonlinear"}) {
    for (const char* key : {"direction_motion_deg", "direction_rest_deg"}) {
      angles.push_back(out["prediction"][model][key].get<double>());
    }
  }
  for (const char* key : {"direction_linear_deg", "direction_nonlinear_deg"}) {
    for (const auto& a : out["series"][key]) angles.push_back(a.get<double>());
  }
  ASSERT_GT(angles.size(), 100u);
  for (double a : angles) {
    EXPECT_GT(a, -180.0);
    EXPECT_LE(a, 180.0);
  }
}

}  // namespace
}  // namespace slosh
