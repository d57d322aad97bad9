// The JDSMC filtering strategies through plan(): fir_chain against the paper's closed form
// (eq. 5, 13-14), shaper and iir laws of exactly the prescribed duration, their residual on the
// exact linear model, honest infeasibility, and auto's two extra candidates.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "slosh/core/law/filtered_laws.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh {
namespace test_filter_strategies {

constexpr double kPi = std::numbers::pi;

::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

Format with_time(double T) {
  Format f = thesis_format();
  f.motion_time = T;
  return f;
}

// The damped period of mode 1 from the model the plan reports (paper eq. 5), computed here.
double damped_period_of(const PlanResult& r) {
  const double w = r.model.omega1(), z = r.model.zeta;
  return 2.0 * kPi / (w * std::sqrt(1.0 - z * z));
}

// Final velocity and position of a law, by Simpson on its acceleration (independent of the
// law's own closed-form integration).
std::pair<double, double> integrate_end(const MotionLaw& law) {
  double v = 0.0, s = 0.0;
  for (const LawPiece& p : law.pieces()) {
    // Simpson's error on the quartic (T - t) a(t) of a cubic piece stays below 1e-13 here.
    const int n =
        2 * std::max(10, static_cast<int>(std::ceil(4000.0 * p.duration() / law.duration())));
    const double h = p.duration() / n;
    // v(t) = v0 + int a, s(T) = int_0^T (T - t) a(t) dt.
    double dv = 0.0, ds = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
      const double a = p.at(i * h).acceleration;
      dv += w * a;
      ds += w * a * (law.duration() - (p.t_begin + i * h));
    }
    v += dv * h / 3.0;
    s += ds * h / 3.0;
  }
  return {v, s};
}

TEST(FirChainStrategy, SevenDurationsInClosedFormWhenConditions14Hold) {
  for (double T : {1.4, 1.6, 2.3}) {
    const Format f = with_time(T);
    const PlanResult r = plan(f, Strategy::kFirChain, PlanOptions{});
    const double T3 = damped_period_of(r);
    ASSERT_GE(T, 4.0 * T3) << "the case needs T >= 4 T3";
    EXPECT_EQ(r.status, SolveStatus::kOptimal) << r.message;
    ASSERT_TRUE(r.durations.has_value()) << r.message;
    // T1 = T/2, T2 = T/2 - T3: the least peak acceleration S / (T1 T2) satisfying (14).
    const Durations expected{T3, T / 2 - 2 * T3, T3, 0.0, T3, T / 2 - 2 * T3, T3};
    for (std::size_t i = 0; i < kSegments; ++i) {
      EXPECT_NEAR((*r.durations)[i], expected[i], 1e-12) << "segment " << i + 1;
    }
    double sum = 0.0;
    for (double d : *r.durations) sum += d;
    EXPECT_NEAR(sum, T, 1e-14);
    // Rest-to-rest over the stroke, integrated independently.
    const auto [v_end, s_end] = integrate_end(r.law);
    EXPECT_NEAR(v_end, 0.0, 1e-12);
    EXPECT_NEAR(s_end, f.stroke, 1e-12);
    // Plateau levels of the FIR chain: S / (T1 T2).
    EXPECT_NEAR(r.A, f.stroke / ((T / 2) * (T / 2 - T3)), 1e-9 * r.A);
    const auto& design = std::get<FirChainDesign>(*r.design);
    EXPECT_TRUE(design.trapezoidal);
    EXPECT_NEAR(design.t3, T3, 1e-15);
    EXPECT_TRUE(Contains(r.message, "conditions (14) hold"));
  }
}

TEST(FirChainStrategy, ZeroLinearResidualWithoutDamping) {
  // zeta = 0: T3 is the natural period, and the 7-segment law leaves mode 1 at rest exactly.
  const Format f = with_time(1.6);
  PlanOptions o;
  o.model.damping = DampingCorrelation::kExplicit;
  o.model.explicit_zeta = 0.0;
  o.model.modes = 1;
  const PlanResult r = plan(f, Strategy::kFirChain, o);
  ASSERT_TRUE(r.durations.has_value()) << r.message;
  const SloshingModel& m = r.model;
  EXPECT_NEAR((*r.durations)[0], 2.0 * kPi / m.omega1(), 1e-14);
  const LinearResponse linear(m, r.law, 1.0);
  const ModeState end = linear.mode_state(0, f.motion_time);
  const LinearResponse uniform(m, SevenSegmentLaw(uniform_durations(1.6), f.stroke).law(), 1.0);
  const ModeState ref = uniform.mode_state(0, f.motion_time);
  const double scale = std::hypot(ref.x, ref.x_dot / m.omega1());
  EXPECT_LT(std::hypot(end.x, end.x_dot / m.omega1()), 1e-10 * scale);
  EXPECT_LT(r.prediction.linear.rest.value, 1e-9 * r.baseline.linear.rest.value);
  // The spectrum has its zero at the natural frequency.
  EXPECT_LT(std::abs(acceleration_spectrum(r.law, m.omega1())),
            1e-10 * std::abs(acceleration_spectrum(r.law, 0.5 * m.omega1())));
}

TEST(FirChainStrategy, GeneralLawWhenTheMotionIsShorterThanFourT3) {
  const Format f = thesis_format();  // T = 1 s < 4 T3 ~ 1.3 s
  const PlanResult r = plan(f, Strategy::kFirChain, PlanOptions{});
  const double T3 = damped_period_of(r);
  ASSERT_LT(f.motion_time, 4.0 * T3);
  EXPECT_EQ(r.status, SolveStatus::kOptimal) << r.message;
  EXPECT_FALSE(r.durations.has_value());
  EXPECT_TRUE(Contains(r.message, "conditions (14) need T >= 4 T3"));
  const auto& design = std::get<FirChainDesign>(*r.design);
  EXPECT_FALSE(design.trapezoidal);
  EXPECT_NEAR(design.t1, 0.5 * (f.motion_time - T3), 1e-15);
  EXPECT_NEAR(design.t2, design.t1, 1e-15);
  EXPECT_NEAR(r.law.duration(), f.motion_time, 1e-15);
  const auto [v_end, s_end] = integrate_end(r.law);
  EXPECT_NEAR(v_end, 0.0, 1e-12);
  EXPECT_NEAR(s_end, f.stroke, 1e-12);
  // The acceleration as the convolution of eq. 13: a = S / T1 [w(t) - w(t - T1)] with w the
  // unit-area trapezoid box_T2 * box_T3, against the law and its peak.
  auto w = [&](double t) {
    return std::max(0.0, std::min(design.t2, t) - std::max(0.0, t - T3)) / (design.t2 * T3);
  };
  double peak = 0.0;
  for (int k = 0; k <= 100000; ++k) {
    const double t = f.motion_time * k / 100000.0;
    const double a = f.stroke / design.t1 * (w(t) - w(t - design.t1));
    peak = std::max(peak, a);
    EXPECT_NEAR(r.law.at(t).acceleration, a, 1e-9) << "t = " << t;
  }
  EXPECT_NEAR(r.A, peak, 1e-4 * peak);
}

TEST(FirChainStrategy, VelocityLimitLengthensT1AndOtherLimitsMakeItInfeasible) {
  const Format f = with_time(1.6);
  PlanOptions o;
  o.limits.v_max = 0.9;  // T1 = T/2 gives S / T1 = 1.0 m/s
  const PlanResult r = plan(f, Strategy::kFirChain, o);
  EXPECT_EQ(r.status, SolveStatus::kOptimal) << r.message;
  ASSERT_TRUE(r.durations.has_value());
  EXPECT_LE(r.prediction.kinematics.v_peak, 0.9 * (1 + 1e-9));
  EXPECT_NEAR(std::get<FirChainDesign>(*r.design).t1, f.stroke / 0.9, 1e-12);
  EXPECT_GT((*r.durations)[3], 0.0);  // a cruise segment appears

  PlanOptions a;
  a.limits.a_max = 1.0;
  const PlanResult tight = plan(f, Strategy::kFirChain, a);
  EXPECT_EQ(tight.status, SolveStatus::kInfeasible);
  EXPECT_TRUE(Contains(tight.message, "exceeds limits.a_max = 1 m/s^2"));

  PlanOptions ramp;
  ramp.min_ramp = 0.39;  // T3 ~ 0.33 s
  const PlanResult short_ramps = plan(f, Strategy::kFirChain, ramp);
  EXPECT_EQ(short_ramps.status, SolveStatus::kInfeasible);
  EXPECT_TRUE(Contains(short_ramps.message, "shorter than min_ramp_s = 0.39 s"));
}

TEST(FirChainStrategy, NoLawWhenTheMotionIsNotLongerThanT3) {
  const Format f = with_time(0.3);
  const PlanResult r = plan(f, Strategy::kFirChain, PlanOptions{});
  EXPECT_EQ(r.status, SolveStatus::kInfeasible);
  EXPECT_TRUE(Contains(r.message, "fir_chain needs T > T3"));
  // The uniform law's ramps (0.3 / 7 s) break min_ramp_s = 0.05 s: baseline's admissible law,
  // every segment at its minimum plus an equal share of the 0.1 s left.
  EXPECT_TRUE(Contains(r.message,
                       "the law returned is baseline's (the uniform law breaks the "
                       "options: every segment at its minimum plus an equal share)"));
  ASSERT_TRUE(r.durations.has_value());
  for (std::size_t i = 0; i < kSegments; ++i) {
    EXPECT_NEAR((*r.durations)[i], (i % 2 == 0 ? 0.05 : 0.0) + 0.1 / 7.0, 1e-15) << i;
  }
  EXPECT_FALSE(r.usable());
}

// T = 0.35 s: T/7 is 0.049999999999999996 in doubles, min_ramp_s 0.05 to round-off. The uniform
// law holds the ramp minimum there: baseline returns it without claiming it breaks an option.
TEST(BaselineStrategy, RampsEqualToMinRampUpToRoundOffAreTheUniformLaw) {
  const Format f = with_time(0.35);
  ASSERT_LT(f.motion_time / 7.0, PlanOptions{}.min_ramp);
  const PlanResult r = plan(f, Strategy::kBaseline, PlanOptions{});
  EXPECT_FALSE(Contains(r.message, "breaks the options")) << r.message;
  ASSERT_TRUE(r.durations.has_value());
  for (std::size_t i = 0; i < kSegments; ++i) EXPECT_NEAR((*r.durations)[i], 0.05, 1e-15) << i;
}

TEST(ShaperStrategy, ExactlyTLongRestToRestAndNoLinearResidualForTheZvFamily) {
  const Format f = thesis_format();
  for (BaseLaw base :
       {BaseLaw::kPoly5, BaseLaw::kModifiedTrapezoid, BaseLaw::kSevenSegmentUniform}) {
    for (ShaperType type : {ShaperType::kZV, ShaperType::kZVD, ShaperType::kEI}) {
      PlanOptions o;
      o.base = base;
      o.shaper = type;
      o.model.modes = 1;
      const PlanResult r = plan(f, Strategy::kShaper, o);
      const std::string what = to_string(base) + " " + to_string(type);
      EXPECT_EQ(r.status, SolveStatus::kOptimal) << what << ": " << r.message;
      EXPECT_FALSE(r.durations.has_value());
      EXPECT_NEAR(r.law.duration(), f.motion_time, 1e-15) << what;
      const auto& design = std::get<ShaperDesign>(*r.design);
      EXPECT_NEAR(design.base_duration + design.shaper.delay(), f.motion_time, 1e-15) << what;
      // Impulse times t_j = j T_d / 2 (eq. 6) and unit sum.
      const double Td = damped_period_of(r);
      double sum = 0.0;
      for (std::size_t j = 0; j < design.shaper.impulses.size(); ++j) {
        EXPECT_NEAR(design.shaper.impulses[j].time, 0.5 * Td * static_cast<double>(j), 1e-14);
        sum += design.shaper.impulses[j].amplitude;
      }
      EXPECT_NEAR(sum, 1.0, 1e-14);
      const auto [v_end, s_end] = integrate_end(r.law);
      EXPECT_NEAR(v_end, 0.0, 1e-11) << what;
      EXPECT_NEAR(s_end, f.stroke, 1e-11) << what;
      // Mode 1 alone: the ZV family leaves it still after T; EI leaves V (5 %) of what the
      // compressed base law leaves after its own end (peaks within a period of the window
      // start, where zeta ~ 0.005 decays less than 5 %).
      if (type == ShaperType::kEI) {
        const MotionLaw base_law = make_base_law(base, f.stroke, design.base_duration);
        const double base_rest = LinearResponse(r.model, base_law, 1.0).peaks().rest.value;
        EXPECT_NEAR(r.prediction.linear.rest.value / base_rest, 0.05, 0.05 * 0.05) << what;
      } else {
        EXPECT_LT(r.prediction.linear.rest.value, 1e-8 * r.baseline.linear.rest.value) << what;
      }
    }
  }
}

TEST(ShaperStrategy, InfeasibleWhenTheDelayLeavesNoTime) {
  const Format f = with_time(0.45);
  PlanOptions o;
  o.shaper = ShaperType::kZVDD;  // delay 1.5 T_d ~ 0.49 s
  const PlanResult r = plan(f, Strategy::kShaper, o);
  EXPECT_EQ(r.status, SolveStatus::kInfeasible);
  EXPECT_TRUE(Contains(r.message, "the zvdd shaper delays the law by"));
  EXPECT_TRUE(Contains(r.message, " s of T = 0.45 s, leaving less than the 1 ms a base law needs"));
  EXPECT_EQ(r.durations, uniform_durations(0.45));
}

TEST(IirStrategy, ExactlyTLongFilteredWithinOneSampleAndNearlyNoLinearResidual) {
  const Format f = thesis_format();
  for (IirOrder order : {IirOrder::kSecond, IirOrder::kThird}) {
    for (double Ts : {1e-3, 5e-4}) {
      PlanOptions o;
      o.iir_order = order;
      o.iir_sample_period = Ts;
      o.model.modes = 1;
      const PlanResult r = plan(f, Strategy::kIir, o);
      EXPECT_EQ(r.status, SolveStatus::kOptimal) << r.message;
      EXPECT_FALSE(r.durations.has_value());
      EXPECT_EQ(r.law.duration(), f.motion_time);
      const auto& d = std::get<IirDesign>(*r.design);
      EXPECT_GT(d.filtered_duration, f.motion_time - Ts - 1e-12);
      EXPECT_LE(d.filtered_duration, f.motion_time + 1e-12);
      EXPECT_EQ(d.filter.sample_period, Ts);
      const auto [v_end, s_end] = integrate_end(r.law);
      EXPECT_NEAR(v_end, 0.0, 1e-11);
      EXPECT_NEAR(s_end, f.stroke, 1e-11);
      // Breakpoints on the sample grid.
      const auto b = r.law.breakpoints();
      for (std::size_t k = 0; k + 1 < b.size(); k += 50) {
        EXPECT_NEAR(b[k], static_cast<double>(k) * Ts, 1e-12);
      }
      EXPECT_LT(r.prediction.linear.rest.value, 0.05 * r.baseline.linear.rest.value);
    }
  }
}

TEST(IirStrategy, InfeasibleWhenTheDelayExceedsTheMotionTime) {
  const Format f = with_time(0.5);
  PlanOptions o;
  o.iir_tau = 1.0;
  const PlanResult r = plan(f, Strategy::kIir, o);
  EXPECT_EQ(r.status, SolveStatus::kInfeasible);
  EXPECT_TRUE(Contains(r.message, "raise tau or lengthen the motion"));
}

TEST(IirStrategy, RefusesMoreSamplesThanItPlans) {
  // 30 s at 1 ms: 30 000 samples > 20 000; the same at 2 ms plans.
  const Format f = with_time(30.0);
  const PlanResult r = plan(f, Strategy::kIir, PlanOptions{});
  EXPECT_EQ(r.status, SolveStatus::kInfeasible);
  EXPECT_TRUE(Contains(r.message,
                       "iir_sample_period_s = 1 ms gives 30000 samples over T = 30 s, more than "
                       "the 20000 the iir strategy plans: use iir_sample_period_s >= 1.5 ms"));
  PlanOptions o;
  o.iir_sample_period = 2e-3;
  const PlanResult coarse = plan(f, Strategy::kIir, o);
  EXPECT_EQ(coarse.status, SolveStatus::kOptimal) << coarse.message;
  EXPECT_EQ(coarse.law.duration(), 30.0);
}

TEST(FilterStrategies, OptionsAreValidatedWithTheirRanges) {
  const Format f = thesis_format();
  InvalidInput error;
  PlanOptions o;
  o.residual = 1.0;
  EXPECT_FALSE(o.is_valid(f, &error));
  EXPECT_EQ(error.message, "residual = 1 must be finite and in [0, 1)");
  o = PlanOptions{};
  o.iir_tau = 0.0;
  EXPECT_FALSE(o.is_valid(f, &error));
  EXPECT_EQ(error.message, "iir_tau = 0 1/s must be finite and > 0 1/s");
  o = PlanOptions{};
  o.iir_sample_period = 0.06;
  EXPECT_FALSE(o.is_valid(f, &error));
  EXPECT_EQ(error.message, "iir_sample_period = 0.06 s must be finite and in (0, 0.05] s");
}

// Property: on seeded random formats every filtering law is exactly T long and rest-to-rest,
// and each design is what the paper's formulas say.
TEST(FilterStrategies, SeededRandomFormatsGiveRestToRestLawsOfDurationT) {
  std::mt19937 rng(20261123);
  std::uniform_real_distribution<double> radius(0.02, 0.08), fill(0.04, 0.15), stroke(0.2, 1.0),
      time(0.6, 2.5);
  for (int k = 0; k < 12; ++k) {
    Format f = thesis_format();
    f.container.radius = radius(rng);
    f.container.height.reset();
    f.fill_height = fill(rng);
    f.stroke = stroke(rng);
    f.motion_time = time(rng);
    for (Strategy s : {Strategy::kFirChain, Strategy::kShaper, Strategy::kIir}) {
      const PlanResult r = plan(f, s, PlanOptions{});
      const std::string what = to_string(s) + " case " + std::to_string(k);
      if (!r.usable()) {
        // Only when the filter's delay (or T3) does not fit.
        EXPECT_TRUE(Contains(r.message, "T = ")) << what;
        continue;
      }
      EXPECT_NEAR(r.law.duration(), f.motion_time, 1e-12) << what;
      const auto [v_end, s_end] = integrate_end(r.law);
      EXPECT_NEAR(v_end, 0.0, 1e-10 * f.stroke) << what;
      EXPECT_NEAR(s_end, f.stroke, 1e-10 * f.stroke) << what;
      EXPECT_EQ(r.durations.has_value(),
                s == Strategy::kFirChain && f.motion_time >= 4.0 * damped_period_of(r))
          << what;
    }
  }
}

}  // namespace test_filter_strategies
}  // namespace slosh
