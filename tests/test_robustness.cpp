// Robust plans (SPEC §10): the robustness report against an independent re-simulation,
// the uncertainty ranges through the model, and the robust designs.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "slosh/core/constants.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/uncertainty.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "slosh/core/strategy/robustness.hpp"
#include "support/random_format.hpp"

namespace slosh {
namespace test_robustness {

// Every mode frequency times s on a law of duration T is, with tau = s t, the nominal model on the
// same stroke moved in s T (x(t) = y(s t) turns eq. 2.35 and the linear modes into the nominal
// equations forced by a(tau / s) / s^2, which is the stretched law's acceleration). So the peaks
// of the report's point delta equal those of the nominal model on the law stretched by 1 + delta,
// over a rest window stretched as well: an independent computation through simulate().
SimulationResult stretched(const Format& format, const Durations& d, double s, double rest) {
  Durations scaled = d;
  for (double& x : scaled) x *= s;
  Format f = format;
  f.motion_time = format.motion_time * s;
  SimulationOptions o;
  o.rest_time = rest * s;
  return simulate(f, SevenSegmentLaw(scaled, format.stroke).law(), o);
}

Durations random_durations(std::mt19937& rng, double T) {
  std::uniform_real_distribution<double> u(0.2, 1.0);
  Durations d;
  double sum = 0.0;
  for (double& x : d) sum += (x = u(rng));
  for (double& x : d) x *= T / sum;
  return d;
}

TEST(RobustnessReport, EveryPointEqualsTheNominalModelOnTheTimeStretchedLaw) {
  std::mt19937 rng(2026);
  for (int trial = 0; trial < 6; ++trial) {
    const Format f = test::random_format(rng);
    const Durations d = random_durations(rng, f.motion_time);
    const SloshingModel model = make_sloshing_model(f, ModelOptions{});
    RobustnessSweep sweep;
    sweep.delta_lo = -0.2;
    sweep.delta_hi = 0.15;
    sweep.points = 7;
    sweep.zeta = model.zeta;
    sweep.eta_rest_max = 0.003;
    const RobustnessReport r = robustness_report(model, SevenSegmentLaw(d, f.stroke).law(), sweep);
    ASSERT_EQ(r.points.size(), 8u);  // 7 even points and delta = 0
    for (const RobustnessPoint& p : r.points) {
      const SimulationResult ref = stretched(f, d, 1.0 + p.delta, sweep.rest_time);
      ASSERT_FALSE(ref.invalid_input);
      const double lin = ref.linear.motion.value, nl = ref.nonlinear.motion.value;
      EXPECT_NEAR(p.linear.motion.value, lin, 1e-7 * lin) << trial << " " << p.delta;
      EXPECT_NEAR(p.linear.rest.value, ref.linear.rest.value, 1e-7 * lin) << p.delta;
      EXPECT_NEAR(p.nonlinear.motion.value, nl, 1e-4 * nl) << trial << " " << p.delta;
      EXPECT_NEAR(p.nonlinear.rest.value, ref.nonlinear.rest.value, 1e-4 * nl) << p.delta;
      // The peak times map back through tau = s t.
      EXPECT_NEAR(p.linear.motion.time * (1.0 + p.delta), ref.linear.motion.time, 1e-6);
    }
  }
}

// The report integrates its points side by side (lanes in lockstep, each on its own step grid);
// every point must be exactly what the one-point responses give, bit for bit, including the
// peak times and a sweep whose point count leaves idle lanes.
TEST(RobustnessReport, SideBySidePointsEqualThePointByPointResponsesBitForBit) {
  std::mt19937 rng(4242);
  for (int trial = 0; trial < 8; ++trial) {
    const Format f = test::random_format(rng);
    const Durations d = random_durations(rng, f.motion_time);
    const SloshingModel model = make_sloshing_model(f, ModelOptions{});
    const MotionLaw law = SevenSegmentLaw(d, f.stroke).law();
    RobustnessSweep sweep;
    sweep.delta_lo = -0.05 - 0.1 * trial / 8.0;
    sweep.delta_hi = 0.03 + 0.1 * trial / 8.0;
    sweep.points = 5 + 2 * trial;  // 5..19 points plus delta = 0: every lane remainder
    sweep.zeta = model.zeta * (trial % 2 == 0 ? 1.0 : 0.5);
    sweep.rest_time = 0.5 + 0.25 * trial;
    sweep.eta_rest_max = 0.002;
    const RobustnessReport r = robustness_report(model, law, sweep);
    ASSERT_EQ(r.points.size(), robustness_deltas(sweep).size());
    for (const RobustnessPoint& p : r.points) {
      const SloshingModel m = scaled_model(model, 1.0 + p.delta, sweep.zeta);
      const SloshPeaks nl = nonlinear_peaks(m, law, sweep.rest_time);
      const SloshPeaks lin = LinearResponse(m, law, sweep.rest_time).peaks();
      EXPECT_EQ(p.nonlinear.motion.value, nl.motion.value) << trial << " " << p.delta;
      EXPECT_EQ(p.nonlinear.motion.time, nl.motion.time) << trial << " " << p.delta;
      EXPECT_EQ(p.nonlinear.rest.value, nl.rest.value) << trial << " " << p.delta;
      EXPECT_EQ(p.nonlinear.rest.time, nl.rest.time) << trial << " " << p.delta;
      EXPECT_EQ(p.linear.motion.value, lin.motion.value) << trial << " " << p.delta;
      EXPECT_EQ(p.linear.motion.time, lin.motion.time) << trial << " " << p.delta;
      EXPECT_EQ(p.linear.rest.value, lin.rest.value) << trial << " " << p.delta;
      EXPECT_EQ(p.linear.rest.time, lin.rest.time) << trial << " " << p.delta;
      // The trajectory-keeping response agrees with the peaks-only one.
      const SloshPeaks kept = NonlinearResponse(m, law, sweep.rest_time).peaks();
      EXPECT_EQ(p.nonlinear.rest.value, kept.rest.value) << trial << " " << p.delta;
      EXPECT_EQ(p.nonlinear.motion.value, kept.motion.value) << trial << " " << p.delta;
    }
  }
}

// The linear lanes over every mode count the lanes take (1..kMaxModes), every group remainder
// (1..4 lanes) and damping ratios that end the rest windows at different samples: each response
// equals its own one-point scan bit for bit.
TEST(RobustnessReport, LinearLanesEqualTheOnePointScanForEveryModeCount) {
  std::mt19937 rng(777);
  std::uniform_real_distribution<double> zeta(0.002, 0.08);
  for (int modes = 1; modes <= static_cast<int>(kMaxModes); ++modes) {
    for (int count = 1; count <= 6; ++count) {
      const Format f = test::random_format(rng);
      const Durations d = random_durations(rng, f.motion_time);
      ModelOptions mo;
      mo.modes = modes;
      const SloshingModel model = make_sloshing_model(f, mo);
      const MotionLaw law = SevenSegmentLaw(d, f.stroke).law();
      std::vector<LinearResponse> responses;
      for (int k = 0; k < count; ++k) {
        const SloshingModel m = scaled_model(model, 1.0 + 0.02 * (k - count / 2), zeta(rng));
        responses.emplace_back(m, law, 0.5 + 0.1 * modes);
      }
      const std::vector<SloshPeaks> side = LinearResponse::peaks_of(responses);
      ASSERT_EQ(side.size(), responses.size());
      for (std::size_t k = 0; k < responses.size(); ++k) {
        const SloshPeaks one = responses[k].peaks();
        EXPECT_EQ(side[k].motion.value, one.motion.value) << modes << " " << count << " " << k;
        EXPECT_EQ(side[k].motion.time, one.motion.time) << modes << " " << count << " " << k;
        EXPECT_EQ(side[k].rest.value, one.rest.value) << modes << " " << count << " " << k;
        EXPECT_EQ(side[k].rest.time, one.rest.time) << modes << " " << count << " " << k;
      }
    }
  }
}

// A lane that leaves the model's range is answered by the one-point path's fine fallback grid,
// while the other lanes of its vector keep the fast grid.
TEST(RobustnessReport, ALaneOutsideTheModelsRangeTakesTheOnePointFallback) {
  const Format f = thesis_format();
  const SloshingModel model = make_sloshing_model(f, ModelOptions{});
  const MotionLaw calm = SevenSegmentLaw(uniform_durations(1.0), 0.8).law();
  const MotionLaw harsh = SevenSegmentLaw(uniform_durations(0.25), 3.0).law();
  std::vector<SloshingModel> models;
  for (double s : {0.9, 0.95, 1.0, 1.05, 1.1}) models.push_back(scaled_model(model, s, 0.0));
  bool outside = false;  // the harsh law takes some lane beyond |xbar| = 1 (or diverges)
  for (const MotionLaw* law : {&calm, &harsh}) {
    const std::vector<SloshPeaks> side = nonlinear_peaks(models, *law, 1.0);
    ASSERT_EQ(side.size(), models.size());
    for (std::size_t i = 0; i < models.size(); ++i) {
      const SloshPeaks one = nonlinear_peaks(models[i], *law, 1.0);
      if (law == &harsh && !(std::max(one.motion.value, one.rest.value) <= models[i].K)) {
        outside = true;
      }
      if (std::isnan(one.motion.value)) {
        EXPECT_TRUE(std::isnan(side[i].motion.value)) << i;
        continue;
      }
      EXPECT_EQ(side[i].motion.value, one.motion.value) << i;
      EXPECT_EQ(side[i].rest.value, one.rest.value) << i;
      EXPECT_EQ(side[i].rest.time, one.rest.time) << i;
    }
  }
  EXPECT_TRUE(outside);
  EXPECT_TRUE(nonlinear_peaks(std::vector<SloshingModel>{}, calm, 1.0).empty());
}

TEST(RobustnessReport, TheIntervalEndsLieBetweenTheLastPointThatHoldsAndTheFirstThatDoesNot) {
  const Format f = thesis_format();
  PlanOptions o;
  const PlanResult p = plan(f, Strategy::kTimeDomain, o);
  ASSERT_TRUE(p.robustness);
  const RobustnessReport& r = *p.robustness;
  ASSERT_EQ(r.points.size(), 21u);
  ASSERT_TRUE(r.nonlinear);
  const DeltaInterval& in = *r.nonlinear;
  EXPECT_LE(in.lo, 0.0);
  EXPECT_GE(in.hi, 0.0);
  int checked = 0;
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    const RobustnessPoint& pt = r.points[k];
    const bool inside = pt.delta >= in.lo && pt.delta <= in.hi;
    const bool holds = pt.nonlinear.rest.value <= o.eta_rest_max * (1.0 + kRobustnessSlack);
    EXPECT_EQ(pt.holds_nonlinear, holds) << pt.delta;
    if (inside) {
      EXPECT_TRUE(holds) << pt.delta;
    }
    // The first point beyond each end fails, and the end is within one step of it.
    if (k + 1 < r.points.size() && pt.delta <= in.hi && r.points[k + 1].delta > in.hi) {
      EXPECT_FALSE(r.points[k + 1].holds_nonlinear);
      EXPECT_LT(in.hi, r.points[k + 1].delta);
      ++checked;
    }
    if (k > 0 && pt.delta >= in.lo && r.points[k - 1].delta < in.lo) {
      EXPECT_FALSE(r.points[k - 1].holds_nonlinear);
      ++checked;
    }
  }
  // The nominal time_domain law sits on its eta_rest bound: it breaks it on at least one side.
  EXPECT_GE(checked + (in.lo_is_sweep_end ? 1 : 0) + (in.hi_is_sweep_end ? 1 : 0), 2);
  EXPECT_TRUE(checked >= 1) << "the nominal plan holds everywhere: nothing was checked";
}

// The issue's table: thesis format, nonlinear eta_motion / eta_rest in mm at -10, -5, 0, 5, 10 %,
// measured by re-simulating each strategy's law.
struct TableRow {
  Strategy strategy;
  std::array<double, 5> motion;
  std::array<double, 5> rest;
};

TEST(RobustnessReport, ReproducesTheIssuesSensitivityTableOfTheThesisFormat) {
  const std::array<TableRow, 6> rows{{
      {Strategy::kBaseline, {58, 53, 45, 37, 30}, {53.2, 42.1, 27.3, 13.3, 4.0}},
      {Strategy::kTimeDomain, {40, 33, 27, 24, 23}, {5.7, 1.8, 3.0, 4.3, 5.8}},
      {Strategy::kMultiNotch, {40, 33, 29, 26, 23}, {3.5, 0.3, 0.1, 0.9, 1.2}},
      {Strategy::kMinJerkBand, {38, 33, 29, 26, 23}, {0.6, 1.6, 0.7, 1.0, 2.1}},
      {Strategy::kNotch, {43, 39, 33, 28, 26}, {34.9, 22.8, 9.2, 2.1, 8.7}},
      {Strategy::kShaper, {34, 29, 26, 22, 20}, {8.8, 5.7, 1.8, 0.7, 1.3}},
  }};
  const std::array<double, 5> deltas{-0.10, -0.05, 0.0, 0.05, 0.10};
  // The table's min_jerk_band row predates the reference level: its band limit is 20 % of
  // |X_uniform(w1)|, i.e. tol_rel = 0.2 |X_uniform(w1)| / X_ref with X_ref the uniform law's
  // largest |X| over the band (computed here on a fine grid).
  const Format f = thesis_format();
  const double w1 = make_sloshing_model(f, ModelOptions{}).omega1();
  const Durations uniform = uniform_durations(f.motion_time);
  double x_ref = 0.0;
  for (int k = 0; k <= 20000; ++k) {
    const double w = (0.85 + 0.3 * k / 20000.0) * w1;
    x_ref = std::max(x_ref, std::abs(seven_segment_spectrum(uniform, f.stroke, w)));
  }
  for (const TableRow& row : rows) {
    PlanOptions o;
    if (row.strategy == Strategy::kMinJerkBand) {
      o.tol_rel = 0.2 * std::abs(seven_segment_spectrum(uniform, f.stroke, w1)) / x_ref;
    }
    const PlanResult p = plan(f, row.strategy, o);
    ASSERT_TRUE(p.robustness);
    for (std::size_t i = 0; i < deltas.size(); ++i) {
      const auto it = std::find_if(
          p.robustness->points.begin(), p.robustness->points.end(),
          [&](const RobustnessPoint& q) { return std::abs(q.delta - deltas[i]) < 1e-12; });
      ASSERT_NE(it, p.robustness->points.end());
      // The table prints eta_motion to the mm and eta_rest to 0.1 mm.
      EXPECT_NEAR(it->nonlinear.motion.value * 1e3, row.motion[i], 0.5 + 1e-9)
          << to_string(row.strategy) << " " << deltas[i];
      EXPECT_NEAR(it->nonlinear.rest.value * 1e3, row.rest[i], 0.05 + 0.1)
          << to_string(row.strategy) << " " << deltas[i];
    }
  }
}

TEST(Uncertainty, AFillHeightRangeOfAShallowFormatMapsToTheOmegaRangeOfTheDispersionRelation) {
  Format f;
  f.container.radius = 0.05;
  f.fill_height = 0.025;  // h/R = 0.5: omega_1 moves with h
  Uncertainty u;
  u.fill_height = std::array<double, 2>{0.02, 0.03};
  const UncertaintyRange r = uncertainty_range(f, ModelOptions{}, u);
  // omega^2 = g xi / R tanh(xi h / R), xi = 1.8411837813 (first root of J1'; the model takes the
  // thesis' 1.841184, 1e-7 away).
  auto omega = [](double R, double h) {
    const double xi = 1.8411837813406593;
    return std::sqrt(9.81 * xi / R * std::tanh(xi * h / R));
  };
  EXPECT_NEAR(r.omega_lo, omega(0.05, 0.02), 1e-6 * r.omega_lo);
  EXPECT_NEAR(r.omega_hi, omega(0.05, 0.03), 1e-6 * r.omega_hi);
  EXPECT_NEAR(r.scale_lo, omega(0.05, 0.02) / omega(0.05, 0.025), 1e-7);
  // The frequency error widens it on both sides.
  u.omega_error = 0.05;
  const UncertaintyRange w = uncertainty_range(f, ModelOptions{}, u);
  EXPECT_NEAR(w.omega_lo, 0.95 * omega(0.05, 0.02), 1e-6 * w.omega_lo);
  EXPECT_NEAR(w.omega_hi, 1.05 * omega(0.05, 0.03), 1e-6 * w.omega_hi);
  // A deep fill hardly moves omega_1 (SPEC §10, h/R > 1.5).
  Format deep = f;
  deep.fill_height = 0.1;
  Uncertainty du;
  du.fill_height = std::array<double, 2>{0.09, 0.11};
  const UncertaintyRange d = uncertainty_range(deep, ModelOptions{}, du);
  EXPECT_LT(d.scale_hi - d.scale_lo, 0.01);
  EXPECT_GT(r.scale_hi - r.scale_lo, 0.1);
}

TEST(Uncertainty, AViscosityRangeMapsToTheZetaOfTheCorrelationAtItsEnds) {
  Format f = thesis_format();
  Uncertainty u;
  u.viscosity = std::array<double, 2>{0.5e-3, 4e-3};
  const UncertaintyRange r = uncertainty_range(f, ModelOptions{}, u);
  Format lo = f, hi = f;
  lo.fluid.viscosity = 0.5e-3;
  hi.fluid.viscosity = 4e-3;
  // zeta grows as sqrt(nu) in every correlation: the range's ends are the viscosity's.
  EXPECT_NEAR(r.zeta_lo, damping_ratio(lo, DampingCorrelation::kThesis), 1e-15);
  EXPECT_NEAR(r.zeta_hi, damping_ratio(hi, DampingCorrelation::kThesis), 1e-15);
  EXPECT_NEAR(r.zeta_hi / r.zeta_lo, std::sqrt(8.0), 1e-9);
  EXPECT_EQ(r.scale_lo, 1.0);
  EXPECT_EQ(r.scale_hi, 1.0);
}

TEST(RobustTimeDomain, HoldsEtaRestAtEveryPointOfPlusMinusFivePercentWhereTheNominalPlanDoesNot) {
  const Format f = thesis_format();
  PlanOptions nominal;
  const PlanResult n = plan(f, Strategy::kTimeDomain, nominal);
  PlanOptions robust;
  robust.uncertainty.omega_error = 0.05;
  const PlanResult r = plan(f, Strategy::kTimeDomain, robust);
  ASSERT_TRUE(r.usable()) << r.message;
  ASSERT_TRUE(r.robustness && n.robustness);
  // The robust plan's report sweeps its own range, +-5 % in 21 points.
  ASSERT_EQ(r.robustness->points.size(), 21u);
  EXPECT_NEAR(r.robustness->points.front().delta, -0.05, 1e-15);
  EXPECT_NEAR(r.robustness->points.back().delta, 0.05, 1e-15);
  for (const RobustnessPoint& p : r.robustness->points) {
    EXPECT_LE(p.nonlinear.rest.value, 0.003 * (1.0 + 1e-6)) << p.delta;
  }
  // The nominal plan breaks 3 mm somewhere in +-5 %: re-simulated independently.
  double worst_nominal = 0.0;
  for (int k = 0; k <= 20; ++k) {
    const double delta = -0.05 + 0.005 * k;
    const SimulationResult s = stretched(f, *n.durations, 1.0 + delta, nominal.rest_time);
    worst_nominal = std::max(worst_nominal, s.nonlinear.rest.value);
  }
  EXPECT_GT(worst_nominal, 0.003 * 1.05);
  // The price: the nominal eta_motion within 10 % of the nominal plan's.
  EXPECT_LT(r.prediction.nonlinear.motion.value, 1.10 * n.prediction.nonlinear.motion.value);
  EXPECT_NEAR(n.prediction.nonlinear.motion.value * 1e3, 26.7, 0.1);
}

TEST(RobustShaper, ChoosesTheShortestFamilyWhoseResidualStaysBelowVOverTheRange) {
  const Format f = thesis_format();
  for (double error : {0.05, 0.10, 0.25}) {
    PlanOptions o;
    o.uncertainty.omega_error = error;
    const PlanResult p = plan(f, Strategy::kShaper, o);
    ASSERT_TRUE(p.design && std::holds_alternative<ShaperDesign>(*p.design)) << p.message;
    const ShaperDesign& d = std::get<ShaperDesign>(*p.design);
    ASSERT_TRUE(p.uncertainty);
    const double w_lo = p.uncertainty->omega_lo, w_hi = p.uncertainty->omega_hi;
    const double w_mid = 0.5 * (w_lo + w_hi), z_mid = p.uncertainty->zeta_mid();
    // Independently: the families by delay, each swept on 20 001 frequencies of the range.
    std::optional<ShaperType> expected;
    for (ShaperType t : {ShaperType::kZV, ShaperType::kMZV, ShaperType::kZVD, ShaperType::kEI,
                         ShaperType::kZVDD, ShaperType::kEI2, ShaperType::kEI3}) {
      const InputShaper s = make_shaper(t, w_mid, z_mid, o.residual);
      double worst = 0.0;
      for (int k = 0; k <= 20000; ++k) {
        const double w = w_lo + (w_hi - w_lo) * k / 20000.0;
        worst = std::max(worst, shaper_residual(s, w, p.uncertainty->zeta_lo));
      }
      if (worst <= o.residual * (1.0 + 1e-6)) {
        expected = t;
        break;
      }
    }
    ASSERT_TRUE(expected) << error;
    EXPECT_EQ(d.shaper.type, *expected) << error << ": " << p.message;
    EXPECT_NEAR(d.shaper.delay(), make_shaper(*expected, w_mid, z_mid, o.residual).delay(), 1e-12);
  }
  // A family named by the caller is kept.
  PlanOptions named;
  named.uncertainty.omega_error = 0.10;
  named.shaper_for_range = false;
  const PlanResult zv = plan(f, Strategy::kShaper, named);
  EXPECT_EQ(std::get<ShaperDesign>(*zv.design).shaper.type, ShaperType::kZV);
}

TEST(RobustSpectral, TheBandAndTheNotchesCoverTheRange) {
  const Format f = thesis_format();
  PlanOptions o;
  o.uncertainty.omega_error = 0.10;
  const PlanResult p = plan(f, Strategy::kMinJerkBand, o);
  const double w1 = p.model.omega1();
  // The band reaches (1 + band) of the highest omega_1 and at least (1 - band) of the lowest.
  EXPECT_NEAR(p.band_omega[1], 1.15 * 1.10 * w1, 1e-9 * w1);
  EXPECT_LE(p.band_omega[0], 0.85 * 0.90 * w1 * (1 + 1e-12));
  // Widened, the band must hold on the range's frequencies with the nominal X_ref.
  EXPECT_TRUE(p.usable()) << p.message;
  PlanOptions wide;
  wide.uncertainty.omega_error = 0.30;
  const PlanResult mn = plan(f, Strategy::kMultiNotch, wide);
  ASSERT_TRUE(mn.durations);
  // Notches at the middle of the range and at its ends: |X| there is far below the uniform law's.
  for (double s : {0.7, 1.0, 1.3}) {
    const double x = std::abs(seven_segment_spectrum(*mn.durations, f.stroke, s * w1));
    const double u = std::abs(seven_segment_spectrum(uniform_durations(1.0), f.stroke, s * w1));
    EXPECT_LT(x, 0.05 * u + 1e-9) << s;
  }
}

TEST(Uncertainty, RangesThatAreEmptyExcludeTheNominalOrLeaveTheBoundsAreRefused) {
  const Format f = thesis_format();
  auto refusal = [&](const Uncertainty& u) {
    PlanOptions o;
    o.uncertainty = u;
    const std::optional<InvalidInput> e = o.validate(f);
    return e ? e->message : std::string("accepted");
  };
  Uncertainty empty;
  empty.fill_height = std::array<double, 2>{0.09, 0.07};
  EXPECT_EQ(refusal(empty),
            "fill_height = [0.09, 0.07] m is empty: the maximum must be >= the minimum");
  Uncertainty outside;
  outside.fill_height = std::array<double, 2>{0.09, 0.1};
  EXPECT_EQ(refusal(outside), "fill_height = [0.09, 0.1] m must contain the nominal 0.082 m");
  Uncertainty negative;
  negative.viscosity = std::array<double, 2>{-1e-3, 2e-3};
  EXPECT_EQ(refusal(negative),
            "viscosity_range[0] = -0.001 Pa s must be finite and in [0, 1e+06] Pa s");
  Uncertainty wide;
  wide.omega_error = 0.6;
  EXPECT_EQ(refusal(wide), "omega_error = 0.6 must be finite and in [0, 0.5]");
  Uncertainty samples;
  samples.omega_error = 0.1;
  samples.sample_points = 1;
  EXPECT_EQ(refusal(samples), "uncertainty_samples = 1 must be finite and in [2, 21]");
  PlanOptions explicit_zeta;
  explicit_zeta.model.damping = DampingCorrelation::kExplicit;
  explicit_zeta.model.explicit_zeta = 0.01;
  explicit_zeta.uncertainty.viscosity = std::array<double, 2>{0.5e-3, 2e-3};
  ASSERT_TRUE(explicit_zeta.validate(f));
  EXPECT_EQ(explicit_zeta.validate(f)->message,
            "a viscosity range has no effect with an explicit zeta: give a zeta correlation, or "
            "no viscosity range");
}

}  // namespace test_robustness
}  // namespace slosh
