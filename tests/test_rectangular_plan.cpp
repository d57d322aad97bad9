// Plans for rectangular containers (SPEC §15) against independent computations: the 2-D answer
// of a tank very wide across the motion, the symmetry of a square tank moved diagonally, a
// turned tank's plan re-simulated by the fine-step RK4 of the modal equations re-typed in
// tests/support, and the band of min_jerk_band over both directions' modes by quadrature.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "slosh/core/model/fluid.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/strategy/min_time.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "slosh/core/strategy/rectangular_plan.hpp"
#include "slosh/core/warning.hpp"
#include "support/hos_tank.hpp"
#include "support/rectangular_reference.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_rectangular_plan {

constexpr double kPi = std::numbers::pi;

/// A cup of a form-fill-seal line: L x W [mm] at `orientation` [deg], water h = 40 mm, moved
/// 200 mm in 1.2 s.
Format cup(double length_mm, double width_mm, double orientation, double fill_mm = 40.0) {
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{length_mm * 1e-3, width_mm * 1e-3, orientation};
  f.fill_height = fill_mm * 1e-3;
  f.stroke = 0.2;
  f.motion_time = 1.2;
  return f;
}

/// The uniform 7-segment law of cup().
MotionLaw uniform_law() {
  return SevenSegmentLaw(uniform_durations(1.2), 0.2).law();
}

PlanOptions quick_options() {
  PlanOptions o;
  o.robustness = false;
  o.time_limit = 60.0;
  return o;
}

/// The least linear eta_rest a law of duration T that moves `stroke` one way leaves, re-typed
/// from docs/models.md, as a share of `uniform_rest` (the uniform law's): each driven direction's
/// wall height u after a unit step of the position, s(u) = -sum_n eta_gain_n e^{-zeta w_n u}
/// (cos w_dn u - zeta w_n / w_dn sin w_dn u); at a time t of the rest window every such law
/// leaves a corner at least stroke min over u in [t - T, t] of |s_L +- s_W| (the same sign
/// throughout), the largest of those over t. Sampled T / 400 apart (u and t), without the
/// implementation's slope margin, over the whole rest window.
double too_short_share(const RectangularModel& m, double stroke, double T, double rest,
                       double uniform_rest) {
  const int per_motion = 400;
  const double h = T / per_motion;
  const int samples = per_motion + static_cast<int>(rest / h) + 1;
  std::vector<double> s_l(samples, 0.0), s_w(samples, 0.0);
  for (const DrivenDirection& d : driven_directions(m)) {
    std::vector<double>& s = d.axis == TankAxis::kLength ? s_l : s_w;
    const double z = d.model.zeta;
    for (int i = 0; i < samples; ++i) {
      const double u = i * h;
      for (std::size_t n = 0; n < d.model.omega.size(); ++n) {
        const double w = d.model.omega[n], wd = w * std::sqrt(1.0 - z * z);
        s[i] -= d.model.eta_gain[n] * std::exp(-z * w * u) *
                (std::cos(wd * u) - z * w / wd * std::sin(wd * u));
      }
    }
  }
  double best = 0.0;
  for (int end = per_motion; end < samples; ++end) {
    for (double sigma : {1.0, -1.0}) {
      double lo = 1e300, hi = -1e300;
      for (int i = end - per_motion; i <= end; ++i) {
        lo = std::min(lo, s_l[i] + sigma * s_w[i]);
        hi = std::max(hi, s_l[i] + sigma * s_w[i]);
      }
      best = std::max({best, lo, -hi});
    }
  }
  return stroke * best / uniform_rest;
}

/// The share a motion_too_short warning of `r` quotes ("... leaves an eta_rest of at least
/// 0.93 of the uniform law's ..."), or -1 when it has none.
double quoted_share(const PlanResult& r) {
  const std::string head = "leaves an eta_rest of at least ";
  for (const Warning& w : r.warnings) {
    if (w.kind != WarningKind::kMotionTooShort) continue;
    const std::size_t at = w.text.find(head);
    if (at == std::string::npos) return -1.0;
    return std::stod(w.text.substr(at + head.size(), 4));
  }
  return -1.0;
}

bool has_kind(const PlanResult& r, WarningKind kind) {
  return has_warning(r.warnings, kind);
}

double relative(double value, double reference) {
  return std::abs(value / reference - 1.0);
}

TEST(RectangularPlan, TankVeryWideAcrossTheMotionPlansAsTheTwoDimensionalTank) {
  // W a thousand metres: the W modes are not driven and the side walls' damping vanishes; the
  // plan's predictions are those of the 2-D tank of length L (RK4 of its modes, no side walls).
  const Format f = cup(120, 1e6, 0.0);
  const PlanResult r = plan(f, Strategy::kMultiNotch, quick_options());
  ASSERT_TRUE(r.usable()) << r.message;
  const test::Modes two_d = test::direction(0.12, 0.0, 0.04, 1.0, 3, false);
  EXPECT_LT(relative(r.model.omega1(), two_d.w[0]), 1e-12);
  for (const auto& [law, predicted] :
       {std::pair{r.law, r.prediction.linear}, {uniform_law(), r.baseline.linear}}) {
    const test::RefPeaks ref = test::rk4_peaks({two_d}, law, 1.0, 1e-5);
    EXPECT_LT(relative(predicted.motion.value, ref.motion), 1e-4);
    EXPECT_LT(relative(predicted.rest.value, ref.rest), 1e-3);
  }
  // The planned law is the same law as for the cylinder-free one-direction model: a notch at
  // the 2-D tank's omega_1 cuts its residual wave well below the uniform law's.
  EXPECT_LT(r.prediction.linear.rest.value, 0.5 * r.baseline.linear.rest.value);
}

TEST(RectangularPlan, ATankAHairOffAnAxisPlansAsOnTheAxis) {
  // A PLC's float gives 89.9999999 degrees for 90: the width direction is driven with a share of
  // 2e-9, so the design is the axis's own (no jump to the two-mode design) and the predictions
  // differ by that share at most.
  for (const auto& [axis, hair] : {std::pair{0.0, 1e-9}, {90.0, 89.9999999}, {0.0, -1e-300}}) {
    for (Strategy s : {Strategy::kNotch, Strategy::kMultiNotch, Strategy::kMinJerkBand}) {
      const PlanResult on = plan(cup(120, 80, axis), s, quick_options());
      const PlanResult off = plan(cup(120, 80, hair), s, quick_options());
      // The same answer, feasible or not (min_jerk_band's band is out of reach in 1.2 s here).
      EXPECT_EQ(on.status, off.status) << off.message;
      ASSERT_TRUE(on.durations && off.durations);
      for (std::size_t k = 0; k < on.durations->size(); ++k) {
        EXPECT_NEAR((*off.durations)[k], (*on.durations)[k], 1e-7) << hair << " " << k;
      }
      EXPECT_LT(relative(off.prediction.linear.rest.value, on.prediction.linear.rest.value), 1e-6)
          << hair;
    }
  }
}

TEST(RectangularPlan, SquareTankAt45DegreesExcitesBothDirectionsEquallyAndPlansAsAtMinus45) {
  const MotionLaw law = uniform_law();
  SimulationOptions so;
  const SimulationResult diagonal = simulate(cup(80, 80, 45.0), law, so);
  const SimulationResult other = simulate(cup(80, 80, -45.0), law, so);
  const SimulationResult along = simulate(cup(80, 80, 0.0), law, so);
  ASSERT_FALSE(diagonal.invalid_input);
  ASSERT_TRUE(diagonal.rectangular_peaks);
  const RectangularPeaks& d = *diagonal.rectangular_peaks;
  EXPECT_EQ(d.along_length.motion.value, d.along_width.motion.value);
  EXPECT_EQ(d.along_length.rest.value, d.along_width.rest.value);
  EXPECT_LT(relative(other.nonlinear.motion.value, diagonal.nonlinear.motion.value), 1e-12);
  EXPECT_LT(relative(other.linear.rest.value, diagonal.linear.rest.value), 1e-12);
  // Linear theory: each direction takes a / sqrt(2), the corner adds both: sqrt(2) times the
  // wall height of the tank moved along a side.
  EXPECT_LT(relative(diagonal.linear.motion.value, std::sqrt(2.0) * along.linear.motion.value),
            1e-6);
  EXPECT_LT(relative(diagonal.linear.rest.value, std::sqrt(2.0) * along.linear.rest.value), 1e-6);

  const PlanResult p45 = plan(cup(80, 80, 45.0), Strategy::kMultiNotch, quick_options());
  const PlanResult m45 = plan(cup(80, 80, -45.0), Strategy::kMultiNotch, quick_options());
  ASSERT_TRUE(p45.usable()) << p45.message;
  ASSERT_TRUE(p45.durations && m45.durations);
  EXPECT_EQ(*p45.durations, *m45.durations);
  EXPECT_LT(relative(p45.prediction.nonlinear.motion.value, m45.prediction.nonlinear.motion.value),
            1e-12);
  EXPECT_LT(relative(p45.prediction.linear.rest.value, m45.prediction.linear.rest.value), 1e-12);
}

/// |X(w)| = |int a(t) e^{-j w t} dt| of a law by Gauss-Legendre quadrature (no core spectrum).
double amplitude(const MotionLaw& law, double w) {
  std::vector<double> knots = law.breakpoints();
  return std::abs(
      test::gauss_legendre_spectrum([&law](double t) { return law.at(t).acceleration; }, knots, w));
}

TEST(RectangularPlan, TurnedTankPlansAreVerifiedByAnIndependentIntegration) {
  // L = 120, W = 80 at 30 degrees: both directions move, f_L = 2.25 Hz, f_W = 2.99 Hz.
  const double phi = 30.0 * kPi / 180.0;
  const std::vector<test::Modes> modes{test::direction(0.12, 0.08, 0.04, std::cos(phi), 3),
                                       test::direction(0.08, 0.12, 0.04, std::sin(phi), 3)};
  for (Strategy s : {Strategy::kMultiNotch, Strategy::kMinJerkBand, Strategy::kTimeDomain}) {
    // (time_domain optimises the dominant modes; the verification adds the second mode, which
    // raises the crests: 3 mm is just out of reach in 1.2 s, 5 mm is not.)
    PlanOptions o = quick_options();
    o.eta_rest_max = 0.005;
    const PlanResult r = plan(cup(120, 80, 30.0), s, o);
    ASSERT_TRUE(r.usable()) << to_string(s) << ": " << r.message;
    ASSERT_TRUE(r.rectangular);
    const test::RefPeaks ref = test::rk4_peaks(modes, r.law, 1.0, 1e-5);
    EXPECT_LT(relative(r.prediction.linear.motion.value, ref.motion), 1e-4) << to_string(s);
    EXPECT_LT(relative(r.prediction.linear.rest.value, ref.rest), 1e-3) << to_string(s);
    if (s == Strategy::kTimeDomain) {
      // It minimises the wave during the motion; the residual is held by its bound.
      EXPECT_LE(r.prediction.nonlinear.rest.value, 0.005 * (1 + 1e-6));
    } else {
      // The spectral strategies cut the corners' residual wave, integrated, well below the
      // uniform law's.
      const test::RefPeaks base = test::rk4_peaks(modes, uniform_law(), 1.0, 1e-5);
      EXPECT_LT(ref.rest, 0.5 * base.rest) << to_string(s);
    }
  }
}

TEST(RectangularPlan, MinJerkBandCoversBothDirectionsModes) {
  const PlanResult r = plan(cup(120, 80, 30.0), Strategy::kMinJerkBand, quick_options());
  ASSERT_TRUE(r.usable()) << r.message;
  const double w_l = test::direction(0.12, 0.08, 0.04, 1.0, 1).w[0];
  const double w_w = test::direction(0.08, 0.12, 0.04, 1.0, 1).w[0];
  // The band reaches 15 % beyond both first modes...
  EXPECT_LE(r.band_omega[0], 0.85 * w_l * (1 + 1e-12));
  EXPECT_GE(r.band_omega[1], 1.15 * w_w * (1 - 1e-12));
  // ...and the law's spectrum stays within 20 % of the uniform law's largest |X| on it.
  const MotionLaw uniform = uniform_law();
  double x_ref = 0.0, x_max = 0.0;
  for (int k = 0; k <= 400; ++k) {
    const double w = r.band_omega[0] + (r.band_omega[1] - r.band_omega[0]) * k / 400.0;
    x_ref = std::max(x_ref, amplitude(uniform, w));
    x_max = std::max(x_max, amplitude(r.law, w));
  }
  EXPECT_LE(x_max, 0.2 * x_ref * (1 + 1e-4));
}

TEST(RectangularPlan, ShallowFillUsesTheLinearModelAndSaysSo) {
  // h / L = 10 / 120 < 0.24: outside the nonlinear model's range.
  const PlanResult r = plan(cup(120, 80, 0.0, 10.0), Strategy::kMultiNotch, quick_options());
  ASSERT_TRUE(r.usable()) << r.message;
  EXPECT_EQ(r.prediction.nonlinear.motion.value, r.prediction.linear.motion.value);
  EXPECT_EQ(r.prediction.nonlinear.rest.value, r.prediction.linear.rest.value);
  const std::vector<std::string> texts = warning_texts(r.warnings);
  const bool said = std::any_of(texts.begin(), texts.end(), [](const std::string& w) {
    return w.find("rectangular nonlinear model not valid along the length") != std::string::npos &&
           w.find("linear model used") != std::string::npos;
  });
  EXPECT_TRUE(said) << ::testing::PrintToString(warning_texts(r.warnings));
}

TEST(RectangularPlan, FillHeightRangeMovesTheExcitedDirectionsFrequency) {
  PlanOptions o = quick_options();
  o.uncertainty.fill_height = std::array<double, 2>{0.035, 0.045};
  const PlanResult r = plan(cup(120, 80, 90.0), Strategy::kMultiNotch, o);
  ASSERT_TRUE(r.usable()) << r.message;
  ASSERT_TRUE(r.uncertainty);
  // Moved along W: the W modes' omega_1 at both ends of the fill range (closed form).
  auto w1 = [](double h) { return test::direction(0.08, 0.12, h, 1.0, 1).w[0]; };
  EXPECT_LT(relative(r.uncertainty->omega_lo, w1(0.035)), 1e-12);
  EXPECT_LT(relative(r.uncertainty->omega_hi, w1(0.045)), 1e-12);
}

TEST(RectangularPlan, FillHeightRangeOnATurnedTankMovesBothDirectionsFrequencies) {
  // 120 x 80 at 30 degrees, fill 35 to 45 mm: each direction's omega_1 moves by its own factor.
  const std::array<double, 2> fills{0.035, 0.045};
  PlanOptions o = quick_options();
  o.robustness = true;
  o.uncertainty.fill_height = fills;
  const PlanResult r = plan(cup(120, 80, 30.0), Strategy::kMultiNotch, o);
  ASSERT_TRUE(r.usable()) << r.message;
  ASSERT_TRUE(r.uncertainty);
  auto w1 = [](double side, double across, double h) {
    return test::direction(side, across, h, 1.0, 1).w[0];
  };
  // The common factor range covers both directions' own ranges (closed forms).
  const double lo = std::min(w1(0.12, 0.08, fills[0]) / w1(0.12, 0.08, 0.04),
                             w1(0.08, 0.12, fills[0]) / w1(0.08, 0.12, 0.04));
  const double hi = std::max(w1(0.12, 0.08, fills[1]) / w1(0.12, 0.08, 0.04),
                             w1(0.08, 0.12, fills[1]) / w1(0.08, 0.12, 0.04));
  EXPECT_LT(relative(r.uncertainty->scale_lo, lo), 1e-12);
  EXPECT_LT(relative(r.uncertainty->scale_hi, hi), 1e-12);
  // The two directions' factors differ (else the test would not tell one range from two).
  EXPECT_GT(std::abs(w1(0.08, 0.12, fills[0]) / w1(0.08, 0.12, 0.04) -
                     w1(0.12, 0.08, fills[0]) / w1(0.12, 0.08, 0.04)),
            1e-3);
  // The sweep the plan is judged by, against the reference RK4 of both directions' modes
  // (re-typed in tests/support) with every frequency scaled by 1 + delta and both directions at
  // the range's least damping: each point, the corners' linear rest.
  ASSERT_TRUE(r.robustness);
  const double phi = 30.0 * kPi / 180.0;
  int checked = 0;
  for (const RobustnessPoint& p : r.robustness->points) {
    std::vector<test::Modes> modes{test::direction(0.12, 0.08, 0.04, std::cos(phi), 3),
                                   test::direction(0.08, 0.12, 0.04, std::sin(phi), 3)};
    for (test::Modes& m : modes) {
      for (double& w : m.w) w *= 1.0 + p.delta;
      m.zeta = r.uncertainty->zeta_lo;
    }
    const test::RefPeaks ref = test::rk4_peaks(modes, r.law, 1.0, 1e-5);
    EXPECT_LT(relative(p.linear.motion.value, ref.motion), 1e-4) << p.delta;
    EXPECT_LT(relative(p.linear.rest.value, ref.rest), 1e-3) << p.delta;
    ++checked;
  }
  EXPECT_GE(checked, 5);
  // The sweep reaches both ends of the range.
  EXPECT_LT(std::abs(r.robustness->points.front().delta - (lo - 1.0)), 1e-12);
  EXPECT_LT(std::abs(r.robustness->points.back().delta - (hi - 1.0)), 1e-12);
}

TEST(RectangularPlan, ShallowWideTankSaysTheLinearAnswerIsOutOfTheory) {
  // 4 x 4 m in 20 mm of water, moved diagonally 200 mm in 1 s: the first period is about 18 s,
  // but the higher modes (near 3 and 5 omega_1 in shallow water) are no impulses at 1 s, so a law
  // that moves one way can leave less than 0.9 of the uniform law's residual wave: the motion is
  // not called too short.
  Format f = cup(4000, 4000, 45.0, 20.0);
  f.motion_time = 1.0;
  const PlanResult r = plan(f, Strategy::kMultiNotch, quick_options());
  ASSERT_TRUE(r.usable()) << r.message;
  // omega_1 = sqrt(g k tanh(k h)), k = pi / 4 m (docs/models.md), the period 2 pi / omega_1.
  const double k = kPi / 4.0;
  const double period = 2 * kPi / std::sqrt(9.81 * k * std::tanh(k * 0.02));
  ASSERT_GT(period, 10.0);
  const double eta = r.prediction.linear.motion.value;
  ASSERT_GT(eta / 0.02, 0.5) << "the case must be beyond linear theory";
  char share[16];
  std::snprintf(share, sizeof share, "%.2f", eta / 0.02);
  char eta_mm[16];
  std::snprintf(eta_mm, sizeof eta_mm, "%.1f", eta * 1e3);
  const std::vector<std::string> texts = warning_texts(r.warnings);
  auto has = [&texts](const std::string& text) {
    return std::any_of(texts.begin(), texts.end(),
                       [&text](const std::string& w) { return w.find(text) != std::string::npos; });
  };
  EXPECT_TRUE(has(std::string("linear model beyond its theory: wall height ") + eta_mm + " mm is " +
                  share +
                  " of the fill height 20.0 mm (above 0.5), a wave not small against the depth"))
      << ::testing::PrintToString(warning_texts(r.warnings));
  EXPECT_LT(too_short_share(*r.rectangular, f.stroke, 1.0, 1.0, r.baseline.linear.rest.value),
            kMotionTooShortShare);
  EXPECT_FALSE(has("motion too short")) << ::testing::PrintToString(warning_texts(r.warnings));
  // Both directions out of the nonlinear model's range: one sentence names both.
  EXPECT_TRUE(has("not valid along the length: fill height / length = 0.005 is below 0.24 "))
      << ::testing::PrintToString(warning_texts(r.warnings));
  EXPECT_TRUE(
      has("; rectangular nonlinear model not valid along the width: fill height / width "
          "= 0.005 is below 0.24"))
      << ::testing::PrintToString(warning_texts(r.warnings));
  // The cup of the other tests has neither warning.
  const PlanResult cup_plan = plan(cup(120, 80, 30.0), Strategy::kMultiNotch, quick_options());
  for (const std::string& w : warning_texts(cup_plan.warnings)) {
    EXPECT_EQ(w.find("beyond its theory"), std::string::npos) << w;
    EXPECT_EQ(w.find("motion too short"), std::string::npos) << w;
  }
}

TEST(RectangularPlan, AShortMotionALawCanStillActOnIsNotCalledTooShort) {
  // 4 x 4 m filled 50 mm, 200 mm in 1 s: 0.09 of the first period (11.4 s), but the modes 3
  // and 5, near 3 and 5 omega_1 in shallow water, are no impulses at 1 s and carry much of the
  // uniform law's residual wave: time_domain leaves about half of it. No plan of this request
  // may then say that no plan can reduce it, and none is held from `optimal` by it.
  Format f = cup(4000, 4000, 0.0, 50.0);
  f.container.height = 0.2;
  f.motion_time = 1.0;
  const PlanResult b = plan(f, Strategy::kBaseline, quick_options());
  const PlanResult t = plan(f, Strategy::kTimeDomain, quick_options());
  ASSERT_TRUE(b.usable()) << b.message;
  ASSERT_FALSE(t.invalid_input) << t.message;
  EXPECT_LT(t.prediction.linear.rest.value, 0.7 * b.prediction.linear.rest.value) << t.message;
  EXPECT_LT(too_short_share(*b.rectangular, f.stroke, 1.0, 1.0, b.baseline.linear.rest.value),
            kMotionTooShortShare);
  for (const PlanResult* r : {&b, &t}) {
    EXPECT_FALSE(has_kind(*r, WarningKind::kMotionTooShort))
        << ::testing::PrintToString(warning_texts(r->warnings));
  }
  const PlanResult m = plan(f, Strategy::kMultiNotch, quick_options());
  EXPECT_EQ(m.status, SolveStatus::kOptimal) << m.message;
  EXPECT_EQ(b.status, SolveStatus::kOptimal) << b.message;
}

TEST(RectangularPlan, AMotionTooShortForEveryLawHoldsShapingPlansFromOptimalButNotBaseline) {
  // 4 x 4 m filled 2 m (deep water), 200 mm in 0.1 s: every mode is nearly an impulse, and on
  // the linear model every law of 0.1 s that moves one way leaves an eta_rest over 0.9 of the
  // uniform law's.
  Format f = cup(4000, 4000, 0.0, 2000.0);
  f.motion_time = 0.1;
  PlanOptions o = quick_options();
  o.min_ramp = 0.01;  // room for the laws to differ, the uniform law's ramps T/7 admissible
  const PlanResult b = plan(f, Strategy::kBaseline, o);
  ASSERT_TRUE(b.usable()) << b.message;
  const double share =
      too_short_share(*b.rectangular, f.stroke, 0.1, o.rest_time, b.baseline.linear.rest.value);
  ASSERT_GE(share, kMotionTooShortShare);
  const double k = kPi / 4.0;
  const double period = 2 * kPi / std::sqrt(9.81 * k * std::tanh(k * 2.0));
  char expected[1024];
  std::snprintf(expected, sizeof expected,
                "motion too short for the tank: motion time 0.1 s is %.3g of the first sloshing "
                "period %.3g s along the length; the move is an impulse to the tank's modes: "
                "on the linear model every law of this duration that moves one way leaves an "
                "eta_rest of at least ",
                0.1 / period, period);
  auto too_short = [&expected](const PlanResult& r) {
    for (const Warning& w : r.warnings) {
      if (w.kind == WarningKind::kMotionTooShort) return w.text.starts_with(expected);
    }
    return false;
  };
  // The uniform law promises no reduction: the warning stands beside its `optimal`.
  EXPECT_TRUE(too_short(b)) << ::testing::PrintToString(warning_texts(b.warnings));
  // The share quoted is the floor rounded down (the test's, sampled without a margin, is at most
  // a little above the implementation's).
  EXPECT_LE(quoted_share(b), share + 1e-9);
  EXPECT_GT(quoted_share(b), share - 0.015);
  EXPECT_EQ(b.status, SolveStatus::kOptimal) << b.message;
  for (Strategy s : {Strategy::kMultiNotch, Strategy::kTimeDomain}) {
    const PlanResult r = plan(f, s, o);
    ASSERT_FALSE(r.invalid_input) << r.message;
    EXPECT_TRUE(too_short(r)) << ::testing::PrintToString(warning_texts(r.warnings));
    if (r.usable()) {
      EXPECT_EQ(r.status, SolveStatus::kAcceptable) << r.message;
      EXPECT_NE(r.message.find(
                    "not optimal: the motion is too short for any law to act on the tank's modes"),
                std::string::npos)
          << r.message;
    }
    // What the warning claims: no law of the request leaves less than the share it quotes.
    EXPECT_GE(r.prediction.linear.rest.value / b.prediction.linear.rest.value, quoted_share(r))
        << to_string(s);
  }
}

TEST(RectangularPlan, AWaveDeeperThanTheFillHoldsEveryPlanFromOptimal) {
  // 300 x 80 mm filled 10 mm, 40 mm high, 200 mm in 1 s: the wave left after the motion is
  // about 1.5 times the fill, uncovering the bottom; the free board (30 mm) is not reached.
  Format f = cup(300, 80, 0.0, 10.0);
  f.container.height = 0.04;
  f.motion_time = 1.0;
  for (Strategy s : {Strategy::kBaseline, Strategy::kMultiNotch}) {
    const PlanResult r = plan(f, s, quick_options());
    ASSERT_TRUE(r.usable()) << r.message;
    const double eta = std::max({r.prediction.linear.motion.value, r.prediction.linear.rest.value,
                                 r.prediction.nonlinear.motion.value});
    ASSERT_GT(eta, f.fill_height) << to_string(s);
    EXPECT_FALSE(has_kind(r, WarningKind::kSpill)) << to_string(s);
    EXPECT_TRUE(has_kind(r, WarningKind::kWaveExceedsFill))
        << ::testing::PrintToString(warning_texts(r.warnings));
    EXPECT_EQ(r.status, SolveStatus::kAcceptable) << r.message;
    EXPECT_NE(r.message.find("not optimal: the predicted wave is deeper than the fill (the "
                             "liquid uncovers the bottom)"),
              std::string::npos)
        << r.message;
  }
}

TEST(RectangularPlan, OutOfItsRangeTheNonlinearModelIsNotCalledOnOrReliedOn) {
  // 100 x 100 at 45 deg in 50 mm, the uniform law: the walls' waves are steeper than k1 eta =
  // 0.3 along both sides, so the "nonlinear" figures are the linear model's.
  Format f = cup(100, 100, 45.0, 50.0);
  f.container.height = 0.06;
  f.stroke = 0.2;
  f.motion_time = 1.0;
  const SimulationResult s = simulate(f, SevenSegmentLaw(uniform_durations(1.0), 0.2).law(), {});
  ASSERT_FALSE(s.invalid_input);
  ASSERT_EQ(s.linear.motion.value, s.nonlinear.motion.value);
  bool spill = false, both = false;
  for (const std::string& w : warning_texts(s.warnings)) {
    EXPECT_EQ(w.find("rely on the nonlinear"), std::string::npos) << w;
    EXPECT_EQ(w.find("(nonlinear model;"), std::string::npos) << w;
    spill = spill || w.find(
                         "(linear model; the nonlinear model is out of its range) exceeds the "
                         "free board 10.0 mm") != std::string::npos;
    both = both || (w.find("along the length") != std::string::npos &&
                    w.find("along the width") != std::string::npos);
  }
  EXPECT_TRUE(spill) << ::testing::PrintToString(warning_texts(s.warnings));
  EXPECT_TRUE(both) << ::testing::PrintToString(warning_texts(s.warnings));
  // The acceleration warning: a 1 x 1 mm cup in 5 m of water moved 100 m in 0.2 s.
  Format tiny = cup(1, 1, 45.0, 5000.0);
  tiny.stroke = 100.0;
  tiny.motion_time = 0.2;
  const SimulationResult t =
      simulate(tiny, SevenSegmentLaw(uniform_durations(0.2), 100.0).law(), {});
  bool acceleration = false;
  for (const std::string& w : warning_texts(t.warnings)) {
    EXPECT_EQ(w.find("rely on the nonlinear"), std::string::npos) << w;
    acceleration = acceleration || w.find(
                                       "the nonlinear model is out of its range too, so no "
                                       "prediction is reliable") != std::string::npos;
  }
  EXPECT_TRUE(acceleration) << ::testing::PrintToString(warning_texts(t.warnings));
}

TEST(RectangularPlan, ShaperOnATurnedTankCancelsBothDirectionsFirstModes) {
  const PlanResult r = plan(cup(120, 80, 30.0), Strategy::kShaper, quick_options());
  ASSERT_TRUE(r.usable()) << r.message;
  // One ZV per direction (closed-form frequencies, h = 40 mm), convolved.
  auto f1 = [](double side) {
    const double k = kPi / side;
    return std::sqrt(9.81 * k * std::tanh(k * 0.04)) / (2 * kPi);
  };
  char tuned[64];
  std::snprintf(tuned, sizeof tuned, "one per direction, at %.3g and %.3g Hz, convolved", f1(0.12),
                f1(0.08));
  EXPECT_NE(r.message.find(tuned), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("4 impulses"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("no residual at both directions' first modes"), std::string::npos)
      << r.message;
  // The reference RK4 of both directions' first modes (at the tank's own damping): the law
  // leaves them at rest, where the uniform law does not.
  const double phi = 30.0 * kPi / 180.0;
  std::vector<test::Modes> modes{test::direction(0.12, 0.08, 0.04, std::cos(phi), 1),
                                 test::direction(0.08, 0.12, 0.04, std::sin(phi), 1)};
  modes[0].zeta = r.rectangular->along_length.zeta;
  modes[1].zeta = r.rectangular->along_width.zeta;
  const double shaped = test::rk4_peaks(modes, r.law, 1.0, 1e-5).rest;
  const double uniform = test::rk4_peaks(modes, uniform_law(), 1.0, 1e-5).rest;
  EXPECT_LT(shaped, 1e-4 * uniform) << shaped << " vs " << uniform;
  // Just past the orientation where the second direction joins the design, the residual is no
  // worse than just before it (a shaper at the middle frequency made it 59 % worse).
  Format below = cup(120, 80, 4.28, 50.0), above = cup(120, 80, 4.29, 50.0);
  below.motion_time = above.motion_time = 1.0;
  const PlanResult before = plan(below, Strategy::kShaper, quick_options());
  const PlanResult after = plan(above, Strategy::kShaper, quick_options());
  ASSERT_TRUE(before.usable() && after.usable()) << before.message << after.message;
  EXPECT_LE(after.prediction.nonlinear.rest.value,
            before.prediction.nonlinear.rest.value + 0.05e-3);
}

TEST(RectangularPlan, RobustnessPointsAreTheTankSimulatedWithItsFrequenciesScaled) {
  // Each point of the sweep must be simulate() of the tank with omega_scale 1 + delta: the same
  // nonlinear model (second mode, higher modes) and the same range checks as the nominal point,
  // inside the range (100 mm) and where the model leaves it at some points (CUP along W, 200 mm).
  struct Case {
    double orientation, stroke, time;
    Strategy strategy;
  };
  for (const Case& k :
       {Case{0.0, 0.1, 1.0, Strategy::kNotch}, Case{90.0, 0.2, 0.73, Strategy::kShaper},
        Case{30.0, 0.2, 1.0, Strategy::kMultiNotch}}) {
    Format f = cup(120, 80, k.orientation, 50.0);
    f.stroke = k.stroke;
    f.motion_time = k.time;
    PlanOptions o = quick_options();
    o.robustness = true;
    const PlanResult r = plan(f, k.strategy, o);
    ASSERT_TRUE(r.usable()) << r.message;
    ASSERT_TRUE(r.robustness);
    ASSERT_GE(r.robustness->points.size(), 5u);
    for (const RobustnessPoint& p : r.robustness->points) {
      SimulationOptions so;
      so.rest_time = o.rest_time;
      so.model.omega_scale = 1.0 + p.delta;
      const SimulationResult sim = simulate(f, r.law, so);
      ASSERT_FALSE(sim.invalid_input);
      const std::string where =
          "orientation " + std::to_string(k.orientation) + ", delta " + std::to_string(p.delta);
      EXPECT_LT(relative(p.nonlinear.motion.value, sim.nonlinear.motion.value), 1e-6) << where;
      EXPECT_LT(relative(p.nonlinear.rest.value, sim.nonlinear.rest.value), 1e-6) << where;
      EXPECT_LT(relative(p.linear.rest.value, sim.linear.rest.value), 1e-6) << where;
    }
  }
}

// The floor motion_too_short quotes bounds what the engineer reads, eta_rest on the linear
// model, for every law of the duration that moves one way: time_domain minimising eta_rest never
// goes below it. The hostile tester's deep tanks (4 x 4 m, 1 m of water, 100 mm in 0.2 s and
// 0.24 s, where the modes' summed amplitudes gave a floor time_domain beat), a deeper one moved
// in 0.1 s whose warning stands, then seeded random deep tanks, turned, moved in 5 to 12 % of
// their first period.
TEST(RectangularPlan, NoTimeDomainLawLeavesLessThanTheFloorOfMotionTooShort) {
  struct Case {
    double length_mm, width_mm, fill_mm, orientation, stroke, time;
  };
  std::vector<Case> cases{{4000, 4000, 1000, 0.0, 0.1, 0.2},
                          {4000, 4000, 1000, 0.0, 0.1, 0.24},
                          {4000, 4000, 2000, 0.0, 0.2, 0.1}};
  std::mt19937 rng(20261128);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 4; ++i) {
    Case c;
    c.length_mm = 1500.0 + 2500.0 * unit(rng);
    c.width_mm = 1500.0 + 2500.0 * unit(rng);
    c.fill_mm = (0.3 + 0.4 * unit(rng)) * std::max(c.length_mm, c.width_mm);
    c.orientation = 90.0 * unit(rng);
    c.stroke = 0.05 + 0.25 * unit(rng);
    const double k = kPi / (1e-3 * std::max(c.length_mm, c.width_mm));
    const double period = 2 * kPi / std::sqrt(9.81 * k * std::tanh(k * 1e-3 * c.fill_mm));
    c.time = (0.05 + 0.07 * unit(rng)) * period;
    cases.push_back(c);
  }
  int quoted = 0;
  for (const Case& c : cases) {
    Format f = cup(c.length_mm, c.width_mm, c.orientation, c.fill_mm);
    f.container.height = 2.0 * c.fill_mm * 1e-3;
    f.stroke = c.stroke;
    f.motion_time = c.time;
    PlanOptions o = quick_options();
    o.min_ramp = c.time / 20.0;
    o.objective = TimeDomainObjective::kRest;
    const PlanResult t = plan(f, Strategy::kTimeDomain, o);
    ASSERT_FALSE(t.invalid_input) << t.message;
    const std::string where = "L " + std::to_string(c.length_mm) + " W " +
                              std::to_string(c.width_mm) + " h " + std::to_string(c.fill_mm) +
                              " at " + std::to_string(c.orientation) + " deg, T " +
                              std::to_string(c.time) + " s";
    const double ratio = t.prediction.linear.rest.value / t.baseline.linear.rest.value;
    const double floor = too_short_share(*t.rectangular, c.stroke, c.time, o.rest_time,
                                         t.baseline.linear.rest.value);
    EXPECT_GT(floor, 0.5) << where;  // the floor is no empty claim on these impulses
    EXPECT_GE(ratio, floor - 2e-3) << where;
    if (quoted_share(t) >= 0.0) {
      ++quoted;
      EXPECT_GE(ratio, quoted_share(t)) << where;
    }
  }
  // The third case's floor is above 0.9: its warning stands.
  EXPECT_GE(quoted, 1);
}

TEST(RectangularPlan, AReferenceOutOfTheNonlinearRangeIsSaid) {
  // 120 x 80 at 30 deg, 200 mm in 1 s: the uniform law's wave leaves the nonlinear model's range
  // (k1 eta = 0.50 along the length), the shaper's does not.
  Format f = cup(120, 80, 30.0, 50.0);
  f.motion_time = 1.0;
  const PlanResult r = plan(f, Strategy::kShaper, quick_options());
  ASSERT_TRUE(r.usable()) << r.message;
  const RectangularNonlinearPeaks uniform = rectangular_nonlinear_peaks(
      *r.rectangular, SevenSegmentLaw(uniform_durations(1.0), 0.2).law(), 1.0);
  ASSERT_FALSE(uniform.nonlinear);
  ASSERT_TRUE(rectangular_nonlinear_peaks(*r.rectangular, r.law, 1.0).nonlinear);
  const std::string expected =
      "the uniform law's nonlinear figures (the reference of the reductions) are the linear "
      "model's: " +
      uniform.warning;
  const std::vector<std::string> texts = warning_texts(r.warnings);
  EXPECT_NE(std::find(texts.begin(), texts.end(), expected), texts.end())
      << ::testing::PrintToString(warning_texts(r.warnings));
}

TEST(RectangularPlan, TimeDomainNeverCallsABoundUnreachableThatNotchMeets) {
  // The 120 x 80 x 50 mm cup moved 100 mm in 1 s along L.
  Format f = cup(120, 80, 0.0, 50.0);
  f.stroke = 0.1;
  f.motion_time = 1.0;
  const PlanOptions o = quick_options();
  const PlanResult notch = plan(f, Strategy::kNotch, o);
  ASSERT_TRUE(notch.usable()) << notch.message;
  ASSERT_LE(notch.prediction.nonlinear.rest.value, o.eta_rest_max);
  const PlanResult td = plan(f, Strategy::kTimeDomain, o);
  EXPECT_EQ(td.message.find("not reachable"), std::string::npos) << td.message;
  if (td.usable()) {
    EXPECT_LE(td.prediction.nonlinear.rest.value, o.eta_rest_max * (1 + 1e-6));
  } else {
    EXPECT_NE(td.message.find("eta_rest <= 3 mm is not met in 1 s: time_domain's law, bounded on "
                              "each direction's oscillator model corrected by its gap to the "
                              "tank's model, verifies at "),
              std::string::npos)
        << td.message;
    EXPECT_NE(td.message.find("try notch or multi_notch"), std::string::npos) << td.message;
  }
}

/// The rest window's highest wall of the 2-D tank L x h moved by `law`, by the fully nonlinear
/// Euler solution of tests/support/hos_tank.hpp (24 cosine modes, order 4, RK4 at 1 ms) [m].
double hos_rest_peak(double L, double h, const MotionLaw& law, double rest) {
  const int modes = 24;
  const testing::HosTank hos(L, h, modes, 4);
  testing::HosTank::State s{std::vector<double>(modes, 0.0), std::vector<double>(modes, 0.0)};
  const double T = law.duration(), dt = 1e-3;
  auto acc = [&law, T](double t) { return t < T ? law.at(t).acceleration : 0.0; };
  double t = 0, peak = 0;
  while (t < T + rest - 1e-12) {
    double step = std::min(dt, T + rest - t);
    if (t < T && t + step > T) step = T - t;  // no step across the end of the motion
    hos.step(s, t, step, acc);
    t += step;
    if (t > T) {
      peak = std::max({peak, std::abs(testing::HosTank::wall_left(s)),
                       std::abs(testing::HosTank::wall_right(s))});
    }
  }
  return peak;
}

TEST(RectangularPlan, TimeDomainMeetsTheRestBoundOnTheCupVerifiedIndependently) {
  // The docs' cup, 120 x 80 x 50 mm moved 100 mm in 1 s along L: time_domain's oscillator misses
  // the second mode the tank's model adds, and its bound is corrected by that gap.
  Format f = cup(120, 80, 0.0, 50.0);
  f.stroke = 0.1;
  f.motion_time = 1.0;
  const PlanOptions o = quick_options();
  const PlanResult r = plan(f, Strategy::kTimeDomain, o);
  ASSERT_TRUE(r.usable()) << r.message;
  EXPECT_LE(r.prediction.nonlinear.rest.value, o.eta_rest_max * (1 + 1e-6));
  // The law re-integrated: the linear modes by RK4 (re-typed from docs/models.md), and the
  // fully nonlinear 2-D tank (W is not driven) by the Euler equations.
  const test::RefPeaks linear =
      test::rk4_peaks({test::direction(0.12, 0.08, 0.05, 1.0, 3)}, r.law, o.rest_time, 1e-5);
  EXPECT_LT(relative(r.prediction.linear.rest.value, linear.rest), 1e-3);
  EXPECT_LE(linear.rest, o.eta_rest_max);
  // Within the 4 % the model keeps to the Euler solution's peaks (the nonlinear reference test;
  // measured here 1.3 % above, the Euler tank being inviscid).
  const double euler = hos_rest_peak(0.12, 0.05, r.law, o.rest_time);
  EXPECT_LT(relative(euler, r.prediction.nonlinear.rest.value), 0.04) << euler;
  // Never worse than notch's law on what it minimises, notch's law being a point of its search.
  const PlanResult notch = plan(f, Strategy::kNotch, o);
  ASSERT_TRUE(notch.usable()) << notch.message;
  EXPECT_LE(r.prediction.nonlinear.motion.value, notch.prediction.nonlinear.motion.value);
}

TEST(RectangularPlan, MinTimeFindsATimeForTimeDomainOnTheCup) {
  // The same cup, 200 mm (the hostile review's format): the shaper's T_min is 0.817 s, and
  // time_domain, which starts from the spectral optima, finds one too.
  Format f = cup(120, 80, 0.0, 50.0);
  f.container.height = 0.07;
  MinTimeOptions o;
  o.plan = quick_options();
  o.motion_time_max = 1.5;
  const MinTimeResult r = min_time(f, Strategy::kTimeDomain, o);
  // At its T_min (0.790 s) the nonlinear model is out of its range and the linear figures stand
  // in, where 0.789 s misses eta_motion on the nonlinear model: found, but not optimal.
  ASSERT_EQ(r.status, SolveStatus::kAcceptable) << r.message;
  ASSERT_TRUE(r.t_min);
  ASSERT_TRUE(r.plan);
  EXPECT_EQ(r.message.rfind("not optimal: the plan at T_min is not (its eta bound was met on the "
                            "linear figures standing in for the nonlinear model",
                            0),
            0U)
      << r.message;
  EXPECT_LT(*r.t_min, 1.0);
  EXPECT_LE(r.plan->prediction.nonlinear.rest.value, 0.003 * (1 + 1e-6));
}

/// The README's first-plan cup of a form-fill-seal line: 120 x 80 mm, 70 mm high, 50 mm of
/// catalogue water, 200 mm in 1 s, its length turned `orientation_deg` from the motion.
Format readme_cup(double orientation_deg) {
  Format f;
  f.container.rectangular = RectangularTank{0.12, 0.08, orientation_deg};
  f.container.height = 0.07;
  f.fill_height = 0.05;
  f.fluid = *find_fluid("water");
  f.stroke = 0.2;
  f.motion_time = 1.0;
  return f;
}

TEST(RectangularPlan, TimeDomainMeetsTheRestLimitOnTheReadmeCupVerifiedIndependently) {
  // The README's cup with the default limit eta_rest <= 3 mm: time_domain optimises each
  // direction's oscillator, and its bound is corrected by the gap to the tank's model (second
  // mode included), so the law meets the limit on the model the plan is judged by.
  const Format f = readme_cup(0.0);
  const PlanOptions o = quick_options();
  const PlanResult r = plan(f, Strategy::kTimeDomain, o);
  ASSERT_TRUE(r.usable()) << r.message;
  EXPECT_EQ(r.status, SolveStatus::kOptimal) << r.message;
  EXPECT_EQ(r.message.find("not met"), std::string::npos) << r.message;
  EXPECT_LE(r.prediction.nonlinear.rest.value, o.eta_rest_max * (1 + 1e-6));
  // The limit is what binds (the law is not merely far inside it): within 0.1 % of it.
  EXPECT_GT(r.prediction.nonlinear.rest.value, o.eta_rest_max * (1 - 1e-3));
  // The law re-integrated independently: the linear modes by RK4 (re-typed from docs/models.md,
  // water's nu = 1e-6 m^2/s where the catalogue's is 1.003e-6: 2e-4 of the rest peak) ...
  const test::RefPeaks linear =
      test::rk4_peaks({test::direction(0.12, 0.08, 0.05, 1.0, 3)}, r.law, o.rest_time, 1e-5);
  EXPECT_LT(relative(r.prediction.linear.rest.value, linear.rest), 1e-3);
  EXPECT_LE(linear.rest, o.eta_rest_max);
  // ... and the fully nonlinear 2-D tank (W is not driven) by the Euler equations: the limit
  // holds on it. (Measured 2.40 mm: at 10.3 mm during the motion, k1 eta = 0.27, near the end of
  // the third-order range, the model's rest peak is 25 % above the Euler tank's, on the safe
  // side; the linear model alone says 1.54 mm.)
  const double euler = hos_rest_peak(0.12, 0.05, r.law, o.rest_time);
  EXPECT_LE(euler, o.eta_rest_max) << euler;
  EXPECT_GT(euler, linear.rest) << euler;
  // notch's law is a point of time_domain's search space that meets the limit here: time_domain
  // does not move more.
  const PlanResult notch = plan(f, Strategy::kNotch, o);
  ASSERT_TRUE(notch.usable()) << notch.message;
  ASSERT_LE(notch.prediction.nonlinear.rest.value, o.eta_rest_max);
  EXPECT_LE(r.prediction.nonlinear.motion.value, notch.prediction.nonlinear.motion.value);
}

TEST(RectangularPlan, TimeDomainOnTheReadmeCupAHairOffAnAxisPlansAsOnTheAxis) {
  // The gap-corrected bound of time_domain must not make the plan turn on the last digits of
  // the data: a hair off the axis (a PLC's float) gives the axis's law.
  for (const auto& [axis, hair] : {std::pair{0.0, 1e-9}, {90.0, 89.9999999}, {0.0, -1e-300}}) {
    const PlanResult on = plan(readme_cup(axis), Strategy::kTimeDomain, quick_options());
    const PlanResult off = plan(readme_cup(hair), Strategy::kTimeDomain, quick_options());
    ASSERT_TRUE(on.usable() && off.usable()) << on.message << " / " << off.message;
    EXPECT_EQ(on.status, off.status) << off.message;
    ASSERT_TRUE(on.durations && off.durations);
    for (std::size_t k = 0; k < on.durations->size(); ++k) {
      EXPECT_NEAR((*off.durations)[k], (*on.durations)[k], 1e-9) << hair << " " << k;
    }
    // The figures are the tank's own: the hair's direction adds its share at most.
    EXPECT_LT(relative(off.prediction.nonlinear.rest.value, on.prediction.nonlinear.rest.value),
              1e-7)
        << hair;
    EXPECT_LT(relative(off.prediction.nonlinear.motion.value, on.prediction.nonlinear.motion.value),
              1e-7)
        << hair;
  }
}

TEST(RectangularPlan, AutoAndTheFiltersPlanATurnedTank) {
  for (Strategy s : {Strategy::kAuto, Strategy::kFirChain, Strategy::kShaper}) {
    const PlanResult r = plan(cup(120, 80, 60.0), s, quick_options());
    EXPECT_TRUE(r.usable() || r.status == SolveStatus::kInfeasible) << r.message;
    ASSERT_FALSE(r.invalid_input) << r.message;
    const RectangularNonlinearPeaks check = rectangular_nonlinear_peaks(*r.rectangular, r.law, 1.0);
    EXPECT_EQ(r.prediction.nonlinear.motion.value, check.peaks.highest.motion.value)
        << to_string(s);
  }
}

// The plan's budget covers its robustness report (SPEC §10): a report that would run past it is
// left out and the plan says time_limit, with the verified law. (A 1 x 1 mm tank moved for 60 s,
// about 1700 of its periods, took 25 s for the report alone against a 10 s budget.)
TEST(RectangularPlan, ARobustnessReportPastTheBudgetIsLeftOutAsTimeLimit) {
  const Format f = cup(120, 80, 30.0);
  PlanOptions o;
  o.robustness = true;
  o.time_limit = 1e-9;
  const PlanResult r = plan(f, Strategy::kBaseline, o);
  EXPECT_EQ(r.status, SolveStatus::kTimeLimit) << r.message;
  EXPECT_FALSE(r.robustness.has_value());
  char periods[32];
  std::snprintf(periods, sizeof periods, "%.3g", 1.2 * r.model.omega1() / (2 * kPi));
  EXPECT_EQ(r.message.rfind(std::string("the time budget of 1e-09 s ran out; returning the best "
                                        "admissible point found: the robustness report was left "
                                        "unfinished (each of its points simulates the whole "
                                        "motion, ") +
                                periods +
                                " first-mode periods here); the law is returned without it, "
                                "verified at the nominal model: raise time_limit_s or set "
                                "robustness to false. ",
                            0),
            0u)
      << r.message;
  // With the budget the report is made.
  o.time_limit = 60.0;
  const PlanResult full = plan(f, Strategy::kBaseline, o);
  EXPECT_EQ(full.status, SolveStatus::kOptimal) << full.message;
  EXPECT_TRUE(full.robustness.has_value());
}

// With the default plan budget (40) min-time finds multi_notch's T_min on the README cup: the
// scan's near misses below it where eta_motion still exceeds its limit (0.64 and 0.72 s) are not
// refined, since the refinement looks for the residual wave's narrow zeros.
TEST(RectangularPlan, MinTimeFindsMultiNotchOnTheReadmeCupWithinTheDefaultBudget) {
  Format f = readme_cup(0.0);
  MinTimeOptions o;
  o.plan.robustness = false;
  o.plan.time_limit = 60.0;
  o.motion_time_max = 3.0;
  const MinTimeResult r = min_time(f, Strategy::kMultiNotch, o);
  ASSERT_EQ(r.status, SolveStatus::kOptimal) << r.message;
  ASSERT_TRUE(r.t_min) << r.message;
  EXPECT_LE(r.plans, 40);
  EXPECT_NEAR(*r.t_min, 1.041, 0.0005) << r.message;
  // The returned plan meets the limits on the nonlinear model: eta_motion within the free board
  // 20 mm less the default 5 mm margin, eta_rest within the default 3 mm.
  ASSERT_TRUE(r.plan);
  EXPECT_LE(r.plan->prediction.nonlinear.motion.value, 0.015 * (1 + 1e-6));
  EXPECT_LE(r.plan->prediction.nonlinear.rest.value, 0.003 * (1 + 1e-6));
  // The nonlinear model holds for that plan: the message names it alone.
  EXPECT_FALSE(has_warning(r.plan->warnings, WarningKind::kNonlinearModelNotValid));
  EXPECT_EQ(r.message.find("does not hold"), std::string::npos) << r.message;
}

// A shallow cup, its fill 0.2 of its length, below the 0.24 the nonlinear model needs: the plan
// at T_min has no nonlinear figures of its own, its linear ones stand in for them, and the
// message says so instead of naming the nonlinear model alone.
TEST(RectangularPlan, MinTimeSaysWhenTheLinearFiguresStoodInAtTMin) {
  Format f = cup(200, 80, 0.0, 40.0);
  f.container.height = 0.1;
  MinTimeOptions o;
  o.plan = quick_options();
  o.motion_time_max = 3.0;
  const MinTimeResult r = min_time(f, Strategy::kMultiNotch, o);
  ASSERT_TRUE(r.t_min) << r.message;
  ASSERT_TRUE(r.plan);
  ASSERT_TRUE(has_warning(r.plan->warnings, WarningKind::kNonlinearModelNotValid));
  EXPECT_EQ(r.plan->prediction.nonlinear.rest.value, r.plan->prediction.linear.rest.value);
  EXPECT_NE(r.message.find("; the nonlinear model does not hold for the plan at T_min, so its "
                           "linear figures stood in for the nonlinear ones there "
                           "(nonlinear_model_not_valid)"),
            std::string::npos)
      << r.message;
  // The limits were met on those figures, not on the nonlinear model: not optimal.
  EXPECT_EQ(r.status, SolveStatus::kAcceptable) << r.message;
}

// The README cup moved 200 mm with eta_motion <= 11.3 mm: at baseline's T_min 1.204 s the
// nonlinear model is out of its range and the linear 11.297 mm stands in, while 1.222-1.226 s,
// where the nonlinear model holds again, reach 11.33-11.45 mm (checked here with plans at those
// times). The T_min stands, but it is acceptable and says why first.
TEST(RectangularPlan, ATMinMetOnTheLinearStandInIsAcceptable) {
  const Format f = readme_cup(0.0);
  MinTimeOptions o;
  o.plan = quick_options();
  o.eta_motion_max = 0.0113;
  o.eta_rest_max = 0.010;
  o.motion_time_max = 3.0;
  const MinTimeResult r = min_time(f, Strategy::kBaseline, o);
  ASSERT_TRUE(r.t_min) << r.message;
  EXPECT_NEAR(*r.t_min, 1.204, 0.0005) << r.message;
  EXPECT_EQ(r.status, SolveStatus::kAcceptable) << r.message;
  EXPECT_EQ(r.message.rfind("not optimal: the plan at T_min is not (its nonlinear figures are the "
                            "linear model's standing in (nonlinear_model_not_valid), which "
                            "under-predict the steep waves that put the nonlinear model out of "
                            "its range: the limits were met on them, not on the nonlinear "
                            "model); T_min = 1.204 s",
                            0),
            0U)
      << r.message;
  // Nor is a claim made about the T above it (1.222-1.226 s fail, between the curve's points).
  EXPECT_FALSE(r.feasible_above.has_value());
  EXPECT_NE(r.message.find("; feasibility above T_min is not established: where the nonlinear "
                           "model's range begins, its figures can miss the limits the linear "
                           "ones met"),
            std::string::npos)
      << r.message;
  // Why: a little longer, the nonlinear model holds and its figure misses the limit.
  Format later = f;
  later.motion_time = 1.224;
  const PlanResult p = plan(later, Strategy::kBaseline, quick_options());
  EXPECT_FALSE(has_warning(p.warnings, WarningKind::kNonlinearModelNotValid)) << p.message;
  EXPECT_GT(p.prediction.nonlinear.motion.value, 0.0113);
}

// The same when no motion time meets the limits: the best reached quotes the linear figures
// that stood in for the nonlinear model there, and says so.
TEST(RectangularPlan, MinTimeSaysWhenTheBestReachedQuotesLinearFigures) {
  Format f = cup(120, 80, 0.0, 20.0);
  f.container.height = 0.07;
  MinTimeOptions o;
  o.plan = quick_options();
  o.eta_rest_max = 1e-5;
  o.motion_time_max = 1.0;
  const MinTimeResult r = min_time(f, Strategy::kBaseline, o);
  ASSERT_EQ(r.status, SolveStatus::kInfeasible) << r.message;
  ASSERT_TRUE(r.best);
  EXPECT_TRUE(r.best->linear_stood_in);
  EXPECT_NE(r.message.find("; the nonlinear model does not hold for the plan at T = " +
                           std::string(r.best->motion_time == 1.0 ? "1.000" : "?") +
                           " s, so its linear figures stood in for the nonlinear ones "
                           "(nonlinear_model_not_valid)"),
            std::string::npos)
      << r.message;
}

}  // namespace test_rectangular_plan
}  // namespace slosh
