// Plans for a rectangular tank turned to the motion (SPEC §15): both directions slosh, each at
// its own first frequency, and every strategy acts on both (a notch between them cancels
// neither). Checked against a fine-step RK4 of the linear modes re-typed in tests/support and
// closed-form frequencies; the plan must move continuously with the orientation (no cut-off at
// which the second direction joins the design).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "slosh/core/model/format.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "slosh/core/strategy/min_time.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/rectangular_reference.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_rectangular_turned {

constexpr double kPi = std::numbers::pi;

/// A 120 x 80 mm cup of water, fill `fill_mm`, at `orientation` [deg], moved 200 mm in `T` s.
Format cup(double orientation, double fill_mm = 40.0, double T = 1.2) {
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{0.12, 0.08, orientation};
  f.fill_height = fill_mm * 1e-3;
  f.stroke = 0.2;
  f.motion_time = T;
  return f;
}

PlanOptions quick_options() {
  PlanOptions o;
  o.robustness = false;
  o.time_limit = 60.0;
  return o;
}

/// The closed-form first frequency along `side` at fill h [rad/s].
double omega1(double side, double h) {
  const double k = kPi / side;
  return std::sqrt(9.81 * k * std::tanh(k * h));
}

/// "2.25 Hz" as the plans write frequencies (3 significant digits).
std::string hz(double omega) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g Hz", omega / (2 * kPi));
  return text;
}

/// The first modes of both directions at 30 degrees, at the tank's own damping: the residual
/// wave a law leaves on the corners, integrated independently of the product.
double corner_rest(const PlanResult& r, const MotionLaw& law, double phi_deg) {
  const double phi = phi_deg * kPi / 180.0;
  std::vector<test::Modes> modes{test::direction(0.12, 0.08, 0.04, std::cos(phi), 1),
                                 test::direction(0.08, 0.12, 0.04, std::sin(phi), 1)};
  modes[0].zeta = r.rectangular->along_length.zeta;
  modes[1].zeta = r.rectangular->along_width.zeta;
  return test::rk4_peaks(modes, law, 1.0, 1e-5).rest;
}

TEST(RectangularTurned, NotchFirChainAndIirCancelBothDirectionsFirstModes) {
  const double w_l = omega1(0.12, 0.04), w_w = omega1(0.08, 0.04);
  const MotionLaw uniform = SevenSegmentLaw(uniform_durations(1.2), 0.2).law();
  for (Strategy s : {Strategy::kNotch, Strategy::kFirChain, Strategy::kIir}) {
    const PlanResult r = plan(cup(30.0), s, quick_options());
    ASSERT_TRUE(r.usable()) << to_string(s) << ": " << r.message;
    // The message names both modes the law acts on, and no longer claims one "f1".
    EXPECT_NE(r.message.find("the length's f1 = " + hz(w_l)), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("the width's f1 = " + hz(w_w)), std::string::npos) << r.message;
    EXPECT_EQ(r.message.find("exact notch at f1 "), std::string::npos) << r.message;
    // Both directions' first modes are left (almost) at rest: a notch at the middle of the two
    // frequencies left 31 % of the uniform law's corner wave here.
    const double shaped = corner_rest(r, r.law, 30.0);
    const double base = corner_rest(r, uniform, 30.0);
    EXPECT_LT(shaped, 0.05 * base) << to_string(s) << ": " << shaped << " vs " << base;
  }
}

TEST(RectangularTurned, PlansMoveContinuouslyAcrossTheOldCutOff) {
  // A 5 % share of the width's static wall height used to decide whether the strategies
  // designed for it: on this cup (fill 50 mm, 1 s) the notch's rest jumped from 0.32 to 7.29 mm
  // between 4.28 and 4.29 degrees. Weighed by the share, the law and its figures move smoothly.
  for (Strategy s : {Strategy::kNotch, Strategy::kMultiNotch}) {
    std::vector<PlanResult> sweep;
    for (double phi : {4.1, 4.2, 4.28, 4.29, 4.3, 4.4, 4.5}) {
      sweep.push_back(plan(cup(phi, 50.0, 1.0), s, quick_options()));
      ASSERT_TRUE(sweep.back().usable()) << sweep.back().message;
    }
    for (std::size_t k = 1; k < sweep.size(); ++k) {
      const PlanResult &a = sweep[k - 1], &b = sweep[k];
      // 0.1 degree moves the figures by well under 1 % (the step was 2200 %).
      EXPECT_LT(std::abs(b.prediction.nonlinear.rest.value - a.prediction.nonlinear.rest.value),
                0.01 * a.prediction.nonlinear.rest.value + 1e-6)
          << to_string(s) << " " << k;
      EXPECT_LT(std::abs(b.prediction.nonlinear.motion.value - a.prediction.nonlinear.motion.value),
                0.01 * a.prediction.nonlinear.motion.value)
          << to_string(s) << " " << k;
      for (std::size_t i = 0; i < 7; ++i) {
        EXPECT_NEAR((*b.durations)[i], (*a.durations)[i], 1e-3) << to_string(s) << " " << k;
      }
    }
  }
}

TEST(RectangularTurned, NotchMarkersAreWhereTheLawNotches) {
  const PlanOptions o = quick_options();
  const Format f = cup(30.0);
  const double w_l = omega1(0.12, 0.04), w_w = omega1(0.08, 0.04);
  const PlanResult r = plan(f, Strategy::kNotch, o);
  ASSERT_TRUE(r.usable()) << r.message;
  const std::vector<double> notched = notched_frequencies(f, o, r);
  ASSERT_EQ(notched.size(), 2u);
  EXPECT_NEAR(notched[0], w_l, 1e-9 * w_l);
  EXPECT_NEAR(notched[1], w_w, 1e-9 * w_w);
  // The law's spectrum vanishes there (the weight of the width is about 0.5: <= 4e-6 X_ref).
  const MotionLaw uniform = SevenSegmentLaw(uniform_durations(1.2), 0.2).law();
  for (double w : notched) {
    const double x = std::abs(seven_segment_spectrum(*r.durations, 0.2, w));
    EXPECT_LT(x, 1e-5 * std::abs(seven_segment_spectrum(uniform_durations(1.2), 0.2, w_l))) << w;
  }
  // multi_notch: three around each direction's first mode; the other strategies none.
  const PlanResult m = plan(f, Strategy::kMultiNotch, o);
  const std::vector<double> three = notched_frequencies(f, o, m);
  ASSERT_EQ(three.size(), 6u);
  EXPECT_NEAR(three[1], w_l, 1e-9 * w_l);
  EXPECT_NEAR(three[4], w_w, 1e-9 * w_w);
  EXPECT_NEAR(three[0], 0.85 * w_l, 1e-9 * w_l);
  EXPECT_NEAR(three[5], 1.15 * w_w, 1e-9 * w_w);
  EXPECT_TRUE(notched_frequencies(f, o, plan(f, Strategy::kShaper, o)).empty());
}

TEST(RectangularTurned, AutoKeepsItsChoiceAcrossTheOldCutOff) {
  // auto chose the shaper at 4.28 degrees and time_domain at 4.29 when the 5 % share decided
  // the design; now every candidate moves continuously and the choice with them.
  const PlanResult below = plan(cup(4.28, 50.0, 1.0), Strategy::kAuto, quick_options());
  const PlanResult above = plan(cup(4.29, 50.0, 1.0), Strategy::kAuto, quick_options());
  ASSERT_TRUE(below.usable() && above.usable()) << below.message << above.message;
  auto chosen = [](const PlanResult& r) {
    for (const PlanCandidate& k : r.candidates) {
      if (k.chosen) return k.strategy;
    }
    return Strategy::kAuto;
  };
  EXPECT_EQ(chosen(below), chosen(above)) << below.message << "\n" << above.message;
  EXPECT_LT(std::abs(above.prediction.nonlinear.rest.value - below.prediction.nonlinear.rest.value),
            0.01 * below.prediction.nonlinear.rest.value + 1e-6);
}

TEST(RectangularTurned, FiltersAndTheBandDoNotJumpOffAnAxis) {
  // A tank 1e-6 degree off an axis drives its second direction at a share of about 1e-8: these
  // four used to design for both directions in full there, and for one at 1e-7 degree (below
  // the 1e-8 share that puts the tank on its axis). On the README's cup eta_rest jumped by 40 %
  // (min_jerk_band), 19 % (shaper), 26 % (fir_chain) and 57 % (iir) next to 0 degrees, and by up
  // to 360 % next to 90. The second direction now enters by its share: the plans meet.
  const PlanOptions o = quick_options();
  for (Strategy s :
       {Strategy::kMinJerkBand, Strategy::kShaper, Strategy::kFirChain, Strategy::kIir}) {
    for (double axis : {0.0, 90.0}) {
      const PlanResult on = plan(cup(axis), s, o);
      const PlanResult off = plan(cup(axis == 0.0 ? 1e-6 : 90.0 - 1e-6), s, o);
      // (min_jerk_band's band is out of reach at 90 degrees: both are its least infeasible law;
      // next to 0 its solver may end the same law as optimal or acceptable.)
      EXPECT_EQ(off.usable(), on.usable()) << to_string(s) << " " << axis << ": " << off.message;
      // iir's delay compensation keeps whole samples of its filter: a small change of the tank
      // can move its law by one (0.5 % of the peaks here).
      const double tol = s == Strategy::kIir ? 1e-2 : 1e-4;
      const SloshPeaks &a = on.prediction.nonlinear, &b = off.prediction.nonlinear;
      EXPECT_NEAR(b.rest.value, a.rest.value, tol * a.rest.value) << to_string(s) << " " << axis;
      EXPECT_NEAR(b.motion.value, a.motion.value, tol * a.motion.value)
          << to_string(s) << " " << axis;
    }
  }
}

TEST(RectangularTurned, ShaperTimesTheWeakDirectionsShaperByItsShare) {
  // At 0.02 degree the width's share of the residual wave (first-mode wall gain times its
  // component, over omega_1, relative to the length's) is below kFullDirectionShare = 1e-3:
  // its ZV shaper is timed at e = share / 1e-3 of its delay. The law rebuilt here: the poly5
  // base law of T minus the delay, convolved with both two-impulse ZV shapers.
  const double phi = 0.02, h = 0.04, T = 1.2, S = 0.2;
  const PlanResult r = plan(cup(phi), Strategy::kShaper, quick_options());
  ASSERT_TRUE(r.usable()) << r.message;
  const double c = std::cos(phi * kPi / 180), s = std::sin(phi * kPi / 180);
  const double w_l = omega1(0.12, h), w_w = omega1(0.08, h);
  const double g_l = 4 * std::tanh(kPi / 0.12 * h) / kPi, g_w = 4 * std::tanh(kPi / 0.08 * h) / kPi;
  const double e = (g_w * s / w_w) / (g_l * c / w_l) / 1e-3;
  ASSERT_GT(e, 0.2);
  ASSERT_LT(e, 0.8);
  struct Impulse {
    double t, a;
  };
  auto zv = [](double w, double zeta, double scale) {
    const double K = std::exp(-zeta * kPi / std::sqrt(1 - zeta * zeta));
    return std::vector<Impulse>{{0.0, 1 / (1 + K)},
                                {scale * kPi / (w * std::sqrt(1 - zeta * zeta)), K / (1 + K)}};
  };
  const std::vector<Impulse> a = zv(w_l, r.rectangular->along_length.zeta, 1.0);
  const std::vector<Impulse> b = zv(w_w, r.rectangular->along_width.zeta, e);
  const double Tb = T - a[1].t - b[1].t;
  auto base = [&](double t) {
    if (t <= 0 || t >= Tb) return 0.0;
    const double x = t / Tb;
    return S / (Tb * Tb) * (60 * x - 180 * x * x + 120 * x * x * x);
  };
  double peak = 0.0, worst = 0.0;
  for (int k = 0; k <= 1200; ++k) {
    const double t = T * k / 1200.0;
    double acc = 0.0;
    for (const Impulse& i : a) {
      for (const Impulse& j : b) acc += i.a * j.a * base(t - i.t - j.t);
    }
    peak = std::max(peak, std::abs(acc));
    worst = std::max(worst, std::abs(r.law.at(t).acceleration - acc));
  }
  EXPECT_LT(worst, 1e-9 * peak) << worst << " of " << peak;
  char text[64];
  std::snprintf(text, sizeof text, "timed at %.3g %% of its delay", 100 * e);
  EXPECT_NE(r.message.find(text), std::string::npos) << r.message << "\n" << text;
}

TEST(RectangularTurned, TimeDomainMovesContinuouslyWithTheOrientation) {
  // The README's cup (120 x 80 mm, 40 mm of water, 200 mm in 1.2 s) over 0-10 and 85-90
  // degrees in half degrees: time_domain's verified figures move by little between neighbours
  // (its bound eta_rest <= 3 mm holds throughout, eta_motion moves with the corners' bound), and
  // its linear rest peak is that of the modes integrated independently.
  const PlanOptions o = quick_options();
  std::vector<double> phis;
  for (int k = 0; k <= 20; ++k) phis.push_back(0.5 * k);
  for (int k = 0; k <= 10; ++k) phis.push_back(85.0 + 0.5 * k);
  std::vector<PlanResult> sweep;
  for (double phi : phis) {
    sweep.push_back(plan(cup(phi), Strategy::kTimeDomain, o));
    ASSERT_TRUE(sweep.back().usable()) << phi << ": " << sweep.back().message;
    EXPECT_LE(sweep.back().prediction.nonlinear.rest.value, o.eta_rest_max * (1 + 1e-6)) << phi;
  }
  for (std::size_t k = 1; k < sweep.size(); ++k) {
    if (phis[k] - phis[k - 1] > 1.0) continue;  // from 10 to 85 degrees: not neighbours
    const SloshPeaks &a = sweep[k - 1].prediction.nonlinear, &b = sweep[k].prediction.nonlinear;
    EXPECT_LT(std::abs(b.rest.value - a.rest.value), 0.05 * a.rest.value) << phis[k];
    // Its local search ends in one of neighbouring optima, whose eta_motion differ by up to 8 %
    // (measured: 5.92 mm at 0.4 degree, 6.39 mm at 0.5; 6.05 mm at 2 degrees between 6.44 and
    // 6.48 mm at 1.5 and 2.5): the bound holds at each, and no orientation changes the problem
    // in kind.
    EXPECT_LT(std::abs(b.motion.value - a.motion.value), 0.1 * a.motion.value) << phis[k];
  }
  for (std::size_t k : {std::size_t{1}, std::size_t{10}, std::size_t{25}}) {
    const double phi = phis[k] * kPi / 180;
    std::vector<test::Modes> modes{test::direction(0.12, 0.08, 0.04, std::cos(phi), 3),
                                   test::direction(0.08, 0.12, 0.04, std::sin(phi), 3)};
    modes[0].zeta = sweep[k].rectangular->along_length.zeta;
    modes[1].zeta = sweep[k].rectangular->along_width.zeta;
    const double rest = test::rk4_peaks(modes, sweep[k].law, o.rest_time, 1e-5).rest;
    EXPECT_NEAR(sweep[k].prediction.linear.rest.value, rest, 1e-3 * rest) << phis[k];
  }
}

TEST(RectangularTurned, MinTimeDoesNotJumpOffAnAxis) {
  // The shaper's T_min on the cup (70 mm high: the free board bounds eta_motion) was 0.669 s on
  // the axis and 0.779 s 1e-6 degree off it, where the second direction's shaper joined in
  // full; 0.619 s at 90 and 0.700 s at 90 - 1e-6. Now the same within the 1 ms grid; and
  // time_domain's, which bounds each direction by a weight that shrinks with the share, moves by
  // a few ms over the first degrees.
  MinTimeOptions o;
  o.plan = quick_options();
  o.motion_time_max = 3.0;
  auto t_min = [&o](double phi, Strategy s) {
    Format f = cup(phi);
    f.container.height = 0.07;
    const MinTimeResult r = min_time(f, s, o);
    // Found (acceptable where the linear figures stand in at T_min, the nonlinear model out of
    // its range there).
    EXPECT_TRUE(r.status == SolveStatus::kOptimal || r.status == SolveStatus::kAcceptable)
        << phi << ": " << r.message;
    return r.t_min.value_or(0.0);
  };
  EXPECT_NEAR(t_min(1e-6, Strategy::kShaper), t_min(0.0, Strategy::kShaper), 1.5e-3);
  EXPECT_NEAR(t_min(90.0 - 1e-6, Strategy::kShaper), t_min(90.0, Strategy::kShaper), 1.5e-3);
  double before = t_min(0.0, Strategy::kTimeDomain);
  for (double phi : {1e-6, 1.0, 2.0, 3.0}) {
    const double now = t_min(phi, Strategy::kTimeDomain);
    EXPECT_LT(std::abs(now - before), 0.012) << phi;
    before = now;
  }
}

TEST(RectangularTurned, SimulateSeriesMaximumIsThePeak) {
  // A square-ish move of the cup at 45 degrees (100 mm in 1.5 s, 50 mm of water: inside the
  // nonlinear model's range): the series is the highest corner, the measure the peaks take, so
  // its maximum over each window is the peak (to the series' 0.1 ms sampling). The sum of both
  // directions' walls the series took before rose 3.5 % above the rest peak here: the two
  // second modes had opposite signs.
  for (double phi : {45.0, 30.0}) {
    Format f = cup(phi, 50.0, 1.5);
    f.stroke = 0.1;
    const MotionLaw law = SevenSegmentLaw(uniform_durations(1.5), 0.1).law();
    SimulationOptions o;
    o.sample_period = 1e-4;
    const SimulationResult r = simulate(f, law, o);
    ASSERT_TRUE(r.series);
    ASSERT_TRUE(r.warnings.empty()) << r.warnings.front().text;
    double motion = 0.0, rest = 0.0;
    for (std::size_t k = 0; k < r.series->t.size(); ++k) {
      const double eta = r.series->eta_nonlinear[k];
      if (r.series->t[k] <= 1.5) motion = std::max(motion, eta);
      if (r.series->t[k] >= 1.5) rest = std::max(rest, eta);
    }
    EXPECT_LE(motion, r.nonlinear.motion.value * (1 + 1e-12)) << phi;
    EXPECT_GE(motion, r.nonlinear.motion.value * (1 - 1e-6)) << phi;
    EXPECT_LE(rest, r.nonlinear.rest.value * (1 + 1e-12)) << phi;
    EXPECT_GE(rest, r.nonlinear.rest.value * (1 - 1e-6)) << phi;
  }
}

// Under an uncertainty range fir_chain and iir keep one filter per direction on a turned tank,
// each at the middle of its direction's range: one filter between the two directions cancels
// neither (a range of +-0.001 % left 7.5 times the nominal plan's eta_rest).
TEST(RectangularTurned, TheFiltersCancelEachDirectionUnderAnUncertaintyRange) {
  const Format f = cup(30.0, 50.0, 1.0);
  for (const Strategy s : {Strategy::kFirChain, Strategy::kIir}) {
    const PlanResult nominal = plan(f, s, quick_options());
    PlanOptions tiny = quick_options();
    tiny.uncertainty.omega_error = 1e-5;
    const PlanResult r = plan(f, s, tiny);
    ASSERT_TRUE(nominal.usable() && r.usable()) << nominal.message << " / " << r.message;
    EXPECT_NEAR(r.prediction.nonlinear.rest.value / nominal.prediction.nonlinear.rest.value, 1.0,
                1e-2)
        << r.message;
    EXPECT_NE(r.message.find("(the middle of its range)"), std::string::npos) << r.message;
  }
  // A fill range: fir_chain's filters last the two directions' damped periods at the range's
  // middle frequency factor (closed-form frequencies, the plan's damping).
  PlanOptions fills = quick_options();
  fills.uncertainty.fill_height = std::array<double, 2>{0.04, 0.06};
  const PlanResult r = plan(f, Strategy::kFirChain, fills);
  ASSERT_TRUE(r.usable()) << r.message;
  ASSERT_TRUE(r.uncertainty && r.design && r.rectangular);
  const double mid = 0.5 * (r.uncertainty->scale_lo + r.uncertainty->scale_hi);
  const auto& chain = std::get<FirChainDesign>(*r.design);
  const std::vector<double> filters{chain.t1, chain.t2, chain.t3};
  for (const auto& [side, zeta] : {std::pair{0.12, r.rectangular->along_length.zeta},
                                   std::pair{0.08, r.rectangular->along_width.zeta}}) {
    const double period = 2 * kPi / (omega1(side, 0.05) * mid * std::sqrt(1 - zeta * zeta));
    EXPECT_TRUE(std::any_of(filters.begin(), filters.end(),
                            [&](double t) { return std::abs(t - period) < 1e-6 * period; }))
        << side << ": " << period << " not in " << chain.t1 << ", " << chain.t2 << ", " << chain.t3;
  }
}

}  // namespace test_rectangular_turned
}  // namespace slosh
