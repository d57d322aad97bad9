// The planner (SPEC §5-§6): every strategy returns admissible durations, and each strategy's
// constraint or objective is verified here independently of the solver (the closed-form and the
// quadrature spectrum, the dense NonlinearResponse simulation, a local solve written in the
// test). Infeasible requests, limits, the options' bounds, determinism, `auto`'s rule, the Ipopt
// path and the time budget are covered too.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "slosh/core/solve/nlp_solver.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/law_quadrature.hpp"
#include "support/random_format.hpp"
#include "support/reference_integrators.hpp"
#include "support/reference_optimum.hpp"

namespace slosh {
namespace test_planner {

using test::quadrature_of;

// gtest-only substring check with both strings in the failure message.
::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << part << "\" not in \"" << text << "\"";
}

struct FormatCase {
  const char* name;
  double stroke;  // [m]
  double T;       // [s]
};

void PrintTo(const FormatCase& c, std::ostream* os) {
  *os << c.name;
}

// The acceptance formats: the thesis format at 0.8 m in 1.0, 0.9 and 0.8 s, and 0.5 m in
// 0.7 s.
const FormatCase kFormats[] = {{"s800_T1000", 0.8, 1.0},
                               {"s800_T900", 0.8, 0.9},
                               {"s800_T800", 0.8, 0.8},
                               {"s500_T700", 0.5, 0.7}};

const Strategy kAllStrategies[] = {Strategy::kBaseline,   Strategy::kNotch,
                                   Strategy::kMultiNotch, Strategy::kMinJerkBand,
                                   Strategy::kTimeDomain, Strategy::kAuto};
const Strategy kOptimising[] = {Strategy::kNotch, Strategy::kMultiNotch, Strategy::kMinJerkBand,
                                Strategy::kTimeDomain};

Format make_format(double stroke, double T) {
  Format f = thesis_format();
  f.stroke = stroke;
  f.motion_time = T;
  return f;
}

Format make_format(const FormatCase& c) {
  return make_format(c.stroke, c.T);
}

double omega1(const Format& f, const PlanOptions& o = {}) {
  return make_sloshing_model(f, o.model).omega1();
}

// X_ref, the uniform law's largest |X| over the band [(1 - band) w1, (1 + band) w1]: the
// reference every spectral tolerance is relative to (SPEC §5 "Reference levels"), computed by the
// tests' own code [m/s].
double uniform_reference(const Format& f, double w1, double band = PlanOptions{}.band) {
  test::SevenDurations u;
  u.fill(f.motion_time / 7.0);
  return test::reference_band_max(u, f.stroke, (1.0 - band) * w1, (1.0 + band) * w1);
}

// The largest |X| of durations d over the band relative to X_ref.
double band_ratio(const Durations& d, const Format& f, double w1, double band = 0.15) {
  test::SevenDurations a;
  std::copy(d.begin(), d.end(), a.begin());
  return test::reference_band_max(a, f.stroke, (1.0 - band) * w1, (1.0 + band) * w1) /
         uniform_reference(f, w1, band);
}

bool converged(SolveStatus s) {
  return s == SolveStatus::kOptimal || s == SolveStatus::kAcceptable;
}

std::string describe(const PlanResult& r) {
  std::string text =
      to_string(r.strategy) + ": " + to_string(r.status) + " (" + r.message + ") durations {";
  for (std::size_t i = 0; i < kSegments; ++i) {
    text += (i == 0 ? "" : ", ") + std::to_string((*r.durations)[i]);
  }
  return text + "}";
}

// Admissible per check_admissible with the given minimum ramp, and the sum equal to T within
// 1e-9 s.
void expect_admissible(const PlanResult& r, const Format& f, double min_ramp = kDefaultMinRamp) {
  const auto reason = check_admissible((*r.durations), {f.motion_time, min_ramp, 1e-9});
  EXPECT_FALSE(reason.has_value()) << reason.value_or("") << "; " << describe(r);
  double sum = 0.0;
  for (double d : (*r.durations)) sum += d;
  EXPECT_NEAR(sum, f.motion_time, 1e-9) << describe(r);
}

// ---------------------------------------------------------------------------------------------
// 1. Every strategy on every acceptance format: usable, admissible, A and B finite and positive.

class PlannerStrategies : public ::testing::TestWithParam<std::tuple<FormatCase, Strategy>> {};

TEST_P(PlannerStrategies, ReturnsAUsableAdmissibleLaw) {
  const auto& [fc, strategy] = GetParam();
  const Format f = make_format(fc);
  const PlanOptions options;
  const PlanResult r = plan(f, strategy, options);
  EXPECT_EQ(to_string(r.strategy), to_string(strategy));
  EXPECT_TRUE(converged(r.status)) << describe(r);
  EXPECT_TRUE(std::isfinite(r.A) && r.A > 0.0) << r.A;
  EXPECT_TRUE(std::isfinite(r.B) && r.B > 0.0) << r.B;
  EXPECT_NEAR(r.law.stroke(), f.stroke, 1e-12);
  EXPECT_NEAR(r.law.duration(), f.motion_time, 1e-12);
  if (r.durations) {
    expect_admissible(r, f);
    // A and B are the plateau levels of the returned durations (rest-to-rest over the stroke).
    const SevenSegmentLaw law((*r.durations), f.stroke);
    EXPECT_NEAR(r.A, law.A(), 1e-12 * law.A());
    EXPECT_NEAR(r.B, law.B(), 1e-12 * law.B());
    EXPECT_NEAR(law.law().stroke(), f.stroke, 1e-12);
  } else {
    // Only auto may return a general law here (when it picks shaper or a non-trapezoidal
    // fir_chain): A and B are its peaks.
    EXPECT_EQ(strategy, Strategy::kAuto);
    EXPECT_NEAR(r.A, r.law.summary().a_peak_positive, 1e-12 * r.A);
  }
  if (strategy == Strategy::kBaseline) {
    EXPECT_EQ(r.durations, uniform_durations(f.motion_time));
  }
  if (strategy == Strategy::kAuto) {
    EXPECT_EQ(r.candidates.size(), 7u);
  } else {
    EXPECT_TRUE(r.candidates.empty());
  }
}

std::string strategy_case_name(
    const ::testing::TestParamInfo<std::tuple<FormatCase, Strategy>>& info) {
  return std::string(std::get<0>(info.param).name) + "_" + to_string(std::get<1>(info.param));
}

INSTANTIATE_TEST_SUITE_P(AcceptanceFormats, PlannerStrategies,
                         ::testing::Combine(::testing::ValuesIn(kFormats),
                                            ::testing::ValuesIn(kAllStrategies)),
                         strategy_case_name);

// ---------------------------------------------------------------------------------------------
// 2. Each strategy's constraint, verified independently of the solver.

class PlannerConstraints : public ::testing::TestWithParam<FormatCase> {};

std::string format_case_name(const ::testing::TestParamInfo<FormatCase>& info) {
  return info.param.name;
}

TEST_P(PlannerConstraints, MinJerkBandHoldsTheBandOnATenTimesFinerGrid) {
  const Format f = make_format(GetParam());
  const PlanOptions o;
  const PlanResult r = plan(f, Strategy::kMinJerkBand, o);
  ASSERT_TRUE(converged(r.status)) << describe(r);
  const double w1 = omega1(f, o);
  const double x_ref = uniform_reference(f, w1);
  const int n = (o.n_band - 1) * 10 + 1;
  double worst = 0.0, worst_omega = 0.0;
  for (int k = 0; k < n; ++k) {
    const double w = (1.0 - o.band) * w1 + 2.0 * o.band * w1 * k / (n - 1);
    const double ratio = std::abs(seven_segment_spectrum((*r.durations), f.stroke, w)) / x_ref;
    if (ratio > worst) {
      worst = ratio;
      worst_omega = w;
    }
  }
  EXPECT_LE(worst, o.tol_rel * (1.0 + 1e-6))
      << "max |X|/X_ref = " << worst << " at w/w1 = " << worst_omega / w1 << " (excess "
      << worst / o.tol_rel - 1.0 << " relative); " << describe(r);
  // The band constraint is active: a min-jerk solution does not leave room on the table.
  EXPECT_GT(worst, 0.99 * o.tol_rel);
}

TEST_P(PlannerConstraints, TimeDomainHoldsTheRestBoundOnAnIndependentDenseSimulation) {
  const Format f = make_format(GetParam());
  const PlanOptions o;
  const PlanResult r = plan(f, Strategy::kTimeDomain, o);
  ASSERT_TRUE(converged(r.status)) << describe(r);
  const SloshingModel model = make_sloshing_model(f, o.model);
  const SloshPeaks p =
      NonlinearResponse(model, SevenSegmentLaw((*r.durations), f.stroke).law(), o.rest_time)
          .peaks();
  const SloshPeaks uniform =
      NonlinearResponse(model, SevenSegmentLaw(uniform_durations(f.motion_time), f.stroke).law(),
                        o.rest_time)
          .peaks();
  EXPECT_LE(p.rest.value, o.eta_rest_max * (1.0 + 1e-6))
      << "eta_rest = " << p.rest.value << " m at t = " << p.rest.time << " s (excess "
      << p.rest.value / o.eta_rest_max - 1.0 << " relative); " << describe(r);
  EXPECT_LT(p.motion.value, uniform.motion.value) << describe(r);
  // The reported prediction is the same dense simulation.
  EXPECT_NEAR(r.prediction.nonlinear.rest.value, p.rest.value, 1e-12);
  EXPECT_NEAR(r.prediction.nonlinear.motion.value, p.motion.value, 1e-12);
}

TEST(Planner, TimeDomainRestObjectiveHoldsTheMotionBoundAndBeatsTheMotionObjectiveAtRest) {
  const Format f = make_format(0.8, 1.0);
  PlanOptions o;
  o.objective = TimeDomainObjective::kRest;
  o.eta_motion_max = 0.030;
  const PlanResult r = plan(f, Strategy::kTimeDomain, o);
  ASSERT_TRUE(converged(r.status)) << describe(r);
  const SloshingModel model = make_sloshing_model(f, o.model);
  const SloshPeaks p =
      NonlinearResponse(model, SevenSegmentLaw((*r.durations), f.stroke).law(), o.rest_time)
          .peaks();
  EXPECT_LE(p.motion.value, 0.030 * (1.0 + 1e-6)) << describe(r);
  // Minimising eta_rest must do at least as well at rest as bounding it at 3 mm.
  EXPECT_LT(p.rest.value, 0.003) << describe(r);
  // The default bound is the uniform law's eta_motion: never worse than the baseline.
  PlanOptions d;
  d.objective = TimeDomainObjective::kRest;
  const PlanResult rd = plan(f, Strategy::kTimeDomain, d);
  ASSERT_TRUE(converged(rd.status)) << describe(rd);
  EXPECT_LE(rd.prediction.nonlinear.motion.value,
            rd.baseline.nonlinear.motion.value * (1.0 + 1e-6));
}

TEST_P(PlannerConstraints, NotchIsExactByClosedFormAndByQuadrature) {
  const Format f = make_format(GetParam());
  const PlanOptions o;
  const PlanResult r = plan(f, Strategy::kNotch, o);
  ASSERT_TRUE(converged(r.status)) << describe(r);
  const double w1 = omega1(f, o);
  const double x_ref = uniform_reference(f, w1);
  const double closed = std::abs(seven_segment_spectrum((*r.durations), f.stroke, w1)) / x_ref;
  // |Re X|, |Im X| <= 1e-6 x_ref each: |X| <= sqrt(2) 1e-6 x_ref.
  EXPECT_LE(closed, 2e-6) << describe(r);
  // Gauss-Legendre quadrature of the built law, independent of the closed form.
  const SevenSegmentLaw law((*r.durations), f.stroke);
  const double quadrature = std::abs(quadrature_of(law.law(), w1)) / x_ref;
  EXPECT_LE(quadrature, 1e-5) << describe(r);
  EXPECT_NEAR(quadrature, closed, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(AcceptanceFormats, PlannerConstraints, ::testing::ValuesIn(kFormats),
                         format_case_name);

// ---------------------------------------------------------------------------------------------
// 3. multi_notch's multi-start against a single local solve from the uniform law.

// (b1 |X(w-)|^2 + b2 |X(w1)|^2 + b3 |X(w+)|^2) / |X_uniform(w1)|^2.
double multi_notch_objective(const Durations& d, const Format& f, const PlanOptions& o) {
  const double w1 = omega1(f, o);
  const double x_ref = uniform_reference(f, w1);
  const double omegas[] = {(1.0 - o.p_notch) * w1, w1, (1.0 + o.p_notch) * w1};
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    sum += o.weights[k] * std::norm(seven_segment_spectrum(d, f.stroke, omegas[k]));
  }
  return sum / (x_ref * x_ref);
}

// The same problem solved once, by NLopt SLSQP from the uniform durations: bounds as
// DurationSpace (ramps >= min_ramp, plateaus and cruise >= 0, all <= T), sum = T, exact
// gradients from spectrum_power_gradient.
NlpResult single_uniform_start(const Format& f, const PlanOptions& o) {
  const double T = f.motion_time;
  const double w1 = omega1(f, o);
  const double x_ref = uniform_reference(f, w1);
  const double stroke = f.stroke;
  const std::vector<double> omegas{(1.0 - o.p_notch) * w1, w1, (1.0 + o.p_notch) * w1};
  const std::array<double, 3> weights = o.weights;
  NlpProblem p;
  p.lower = {o.min_ramp, 0.0, o.min_ramp, 0.0, o.min_ramp, 0.0, o.min_ramp};
  p.upper.assign(kSegments, T);
  p.equalities.push_back({std::vector<double>(kSegments, 1.0), T});
  p.objective = [=](const double* x, double* grad) {
    Durations d;
    std::copy(x, x + kSegments, d.begin());
    if (grad != nullptr) std::fill(grad, grad + kSegments, 0.0);
    double value = 0.0;
    const double scale = 1.0 / (x_ref * x_ref);
    for (std::size_t k = 0; k < omegas.size(); ++k) {
      const SpectrumPowerGradient pg = spectrum_power_gradient(d, stroke, omegas[k]);
      value += weights[k] * scale * pg.power;
      if (grad != nullptr) {
        for (std::size_t i = 0; i < kSegments; ++i) grad[i] += weights[k] * scale * pg.gradient[i];
      }
    }
    return value;
  };
  NlpOptions options;
  options.tolerance = 1e-10;
  options.constraint_tolerance = 1e-10;
  options.max_iterations = 400;
  options.time_limit = 0.0;  // the comparison is about the start, not the machine's speed
  const Durations u = uniform_durations(T);
  return solve_with_nlopt(p, std::vector<double>(u.begin(), u.end()), options);
}

TEST(Planner, MultiNotchMultiStartFindsAFarLowerObjectiveThanTheUniformStart) {
  // Observed objectives (plan vs single solve from the uniform law): thesis format T = 1 s
  // 9.15e-4 vs 1.417 (1550x); T = 0.9 s 2.1e-2 vs 0.60 (28x); at T = 0.8 s and on 0.5 m / 0.7 s
  // the uniform start already lands on the same optimum (ratio 1), so the thesis T = 1 s format
  // is the one that shows what the multi-start is for.
  const Format f = thesis_format();
  const PlanOptions o;
  const PlanResult r = plan(f, Strategy::kMultiNotch, o);
  ASSERT_TRUE(converged(r.status)) << describe(r);
  const double planned = multi_notch_objective((*r.durations), f, o);
  // The reported objective is the same quantity (at the unpolished solver point).
  EXPECT_NEAR(r.solver.objective, planned, 1e-6 * planned + 1e-15);
  const NlpResult single = single_uniform_start(f, o);
  ASSERT_TRUE(single.usable()) << to_string(single.status) << " " << single.message;
  EXPECT_LT(single.max_violation, 1e-9);
  Durations ds;
  std::copy(single.x.begin(), single.x.end(), ds.begin());
  const double local = multi_notch_objective(ds, f, o);
  EXPECT_NEAR(local, single.objective, 1e-9 * single.objective);
  EXPECT_LE(10.0 * planned, local) << "plan " << planned << ", single start " << local;
}

// ---------------------------------------------------------------------------------------------
// 4. Determinism.

TEST(Planner, TheSameRequestGivesBitIdenticalDurations) {
  const Format f = thesis_format();
  const PlanOptions o;
  for (Strategy s : {Strategy::kMultiNotch, Strategy::kTimeDomain}) {
    const PlanResult a = plan(f, s, o);
    const PlanResult b = plan(f, s, o);
    EXPECT_EQ(a.durations, b.durations) << to_string(s);
    EXPECT_EQ(to_string(a.status), to_string(b.status)) << to_string(s);
    EXPECT_EQ(a.solver.objective, b.solver.objective) << to_string(s);
  }
}

// ---------------------------------------------------------------------------------------------
// 5. Infeasible requests are reported as such, with admissible durations.

TEST(Planner, UnreachableRestBoundIsReportedInfeasible) {
  const Format f = make_format(0.8, 0.5);
  PlanOptions o;
  o.eta_rest_max = 1e-4;  // 0.1 mm; the uniform law leaves 131 mm at rest
  const PlanResult r = plan(f, Strategy::kTimeDomain, o);
  EXPECT_EQ(to_string(r.status), to_string(SolveStatus::kInfeasible)) << describe(r);
  EXPECT_FALSE(r.usable());
  // A local method says what it did not find; it never claims that no law exists.
  EXPECT_TRUE(Contains(r.message, "no law found that meets eta_rest <= 0.1 mm in 0.5 s"))
      << r.message;
  EXPECT_FALSE(Contains(r.message, "not reachable")) << r.message;
  expect_admissible(r, f);
  // Not a solution indeed: the dense simulation is far above the bound.
  const SloshPeaks p =
      NonlinearResponse(make_sloshing_model(f, o.model),
                        SevenSegmentLaw((*r.durations), f.stroke).law(), o.rest_time)
          .peaks();
  EXPECT_GT(p.rest.value, 10.0 * o.eta_rest_max);
}

TEST(Planner, UnreachableBandToleranceIsReportedInfeasible) {
  // The band is not reachable in 0.5 s at these tolerances: reported infeasible with the least
  // infeasible law (min-max of the band excess), whose band maximum is above the limit.
  const Format f = make_format(0.8, 0.5);
  for (double tol : {0.002, 0.001}) {
    PlanOptions o;
    o.tol_rel = tol;
    const PlanResult r = plan(f, Strategy::kMinJerkBand, o);
    EXPECT_EQ(to_string(r.status), to_string(SolveStatus::kInfeasible))
        << "tol_rel " << tol << ": " << describe(r);
    EXPECT_TRUE(Contains(r.message, "not reachable")) << "tol_rel " << tol;
    expect_admissible(r, f);
    const double w1 = omega1(f, o);
    EXPECT_GT(band_ratio(*r.durations, f, w1), o.tol_rel);
    EXPECT_LE(band_ratio(*r.durations, f, w1), 1.0);  // no worse than the uniform law
    EXPECT_TRUE(Contains(r.message, "of X_ref on the band is not reachable in 0.5 s: the best is"));
  }
}

TEST(Planner, UnreachableAccelerationLimitIsReportedInfeasibleNamingIt) {
  const Format f = thesis_format();
  PlanOptions o;
  o.limits.a_max = 1.0;
  o.time_limit = 600.0;  // the statement is about the limit, not the budget (ASan runs slower)
  // Any rest-to-rest move of s in T needs a peak |a| >= 4 s / T^2 (bang-bang) = 3.2 m/s^2.
  ASSERT_GT(4.0 * f.stroke / (f.motion_time * f.motion_time), *o.limits.a_max);
  for (Strategy s : kOptimising) {
    const PlanResult r = plan(f, s, o);
    EXPECT_EQ(to_string(r.status), to_string(SolveStatus::kInfeasible)) << describe(r);
    EXPECT_TRUE(Contains(r.message, "a_max")) << to_string(s);
    EXPECT_TRUE(Contains(r.message, "not reachable")) << to_string(s);
    expect_admissible(r, f);
  }
}

// ---------------------------------------------------------------------------------------------
// 6. Machine limits respected.

struct Kinematics {
  double a_peak{}, v_peak{}, j_peak{};
};

// From the built law: the acceleration and velocity peaks of its pieces, the jerks of its ramps.
Kinematics kinematics(const Durations& d, double stroke) {
  const SevenSegmentLaw law(d, stroke);
  const KinematicSummary s = law.law().summary();
  Kinematics k;
  k.a_peak = std::max({s.a_peak_positive, s.a_peak_negative, law.A(), law.B()});
  k.v_peak = std::max(s.v_peak, law.v_peak());
  for (double j : law.jerks()) k.j_peak = std::max(k.j_peak, std::abs(j));
  return k;
}

void expect_within_limits(const PlanResult& r, const Format& f, const MachineLimits& lim) {
  const Kinematics k = kinematics((*r.durations), f.stroke);
  if (lim.a_max) {
    EXPECT_LE(k.a_peak, *lim.a_max * (1.0 + 1e-6)) << describe(r);
  }
  if (lim.v_max) {
    EXPECT_LE(k.v_peak, *lim.v_max * (1.0 + 1e-6)) << describe(r);
  }
  if (lim.j_max) {
    EXPECT_LE(k.j_peak, *lim.j_max * (1.0 + 1e-6)) << describe(r);
  }
}

TEST(Planner, AccelerationVelocityAndJerkLimitsAreRespected) {
  const Format f = thesis_format();
  MachineLimits lim;
  lim.a_max = 6.0;
  lim.v_max = 1.7;
  lim.j_max = 150.0;
  // Unconstrained, multi_notch reaches A = B = 6.16 m/s^2 and v = 1.78 m/s (jerk 43 m/s^3):
  // these limits bite, so the checks below can fail.
  const Kinematics free = kinematics(*plan(f, Strategy::kMultiNotch, {}).durations, f.stroke);
  ASSERT_TRUE(free.a_peak > *lim.a_max || free.v_peak > *lim.v_max)
      << free.a_peak << " " << free.v_peak;
  for (Strategy s : kOptimising) {
    PlanOptions o;
    o.limits = lim;
    // The default band (20 % of X_ref) may not be reachable under these limits; 50 % is.
    if (s == Strategy::kMinJerkBand) o.tol_rel = 0.5;
    const PlanResult r = plan(f, s, o);
    EXPECT_TRUE(converged(r.status)) << describe(r);
    expect_admissible(r, f);
    expect_within_limits(r, f, lim);
  }
}

TEST(Planner, JerkLimitIsRespected) {
  const Format f = thesis_format();
  MachineLimits lim;
  lim.j_max = 40.0;
  // Unconstrained: multi_notch 43.1, min_jerk_band 42.6, time_domain 136 m/s^3 (notch 32).
  const Kinematics free = kinematics(*plan(f, Strategy::kMultiNotch, {}).durations, f.stroke);
  ASSERT_GT(free.j_peak, *lim.j_max);
  for (Strategy s : kOptimising) {
    PlanOptions o;
    o.limits = lim;
    const PlanResult r = plan(f, s, o);
    // min_jerk_band's 20 % band is not reachable with j <= 40 m/s^3 (reported infeasible); its
    // least infeasible point must still honour the limit.
    if (s != Strategy::kMinJerkBand) {
      EXPECT_TRUE(converged(r.status)) << describe(r);
    }
    expect_admissible(r, f);
    expect_within_limits(r, f, lim);
  }
}

// ---------------------------------------------------------------------------------------------
// 7. Structural options.

// The strategy's own objective, recomputed from the durations: the jerk integral for notch and
// min_jerk_band, the weighted band power for multi_notch [-, relative to the uniform law].
double independent_objective(Strategy s, const Durations& d, const Format& f,
                             const PlanOptions& o) {
  if (s == Strategy::kMultiNotch) return multi_notch_objective(d, f, o);
  return SevenSegmentLaw(d, f.stroke).jerk_integral() /
         SevenSegmentLaw(uniform_durations(f.motion_time), f.stroke).jerk_integral();
}

TEST(Planner, FixedZeroCruiseIsExactlyZero) {
  const Format f = thesis_format();
  PlanOptions o;
  o.fix_constant_velocity_zero = true;
  for (Strategy s : kOptimising) {
    const PlanResult r = plan(f, s, o);
    EXPECT_TRUE(converged(r.status)) << describe(r);
    EXPECT_EQ((*r.durations)[3], 0.0) << describe(r);
    expect_admissible(r, f);
  }
}

TEST(Planner, FixingAZeroCruiseKeepsAnOptimumThatHasNone) {
  // On the thesis format the free optima of notch, multi_notch and min_jerk_band have no cruise
  // (d[3] ~ 1e-15 s): forcing it to zero must give the same optimum. Observed: notch and
  // multi_notch agree to 1e-10; min_jerk_band returns a jerk integral of 119 % instead of 114 %
  // with the band constraint inactive (|X| <= 10.3 % for a 20 % limit), see the report.
  const Format f = thesis_format();
  PlanOptions fixed;
  fixed.fix_constant_velocity_zero = true;
  const PlanOptions free_options;
  for (Strategy s : {Strategy::kNotch, Strategy::kMultiNotch, Strategy::kMinJerkBand}) {
    const PlanResult a = plan(f, s, free_options);
    const PlanResult b = plan(f, s, fixed);
    ASSERT_TRUE(converged(a.status) && converged(b.status)) << describe(a) << "; " << describe(b);
    ASSERT_LT((*a.durations)[3], 1e-9) << describe(a);
    const double free_value = independent_objective(s, (*a.durations), f, free_options);
    const double fixed_value = independent_objective(s, (*b.durations), f, fixed);
    EXPECT_LE(fixed_value, free_value * (1.0 + 1e-4) + 1e-12)
        << to_string(s) << ": free " << free_value << ", fixed " << fixed_value << "; "
        << describe(b);
  }
}

TEST(Planner, PlateauMinimumsAreRespected) {
  const Format f = thesis_format();
  PlanOptions o;
  o.plateau_min = {0.1, 0.12};
  for (Strategy s : kOptimising) {
    const PlanResult r = plan(f, s, o);
    EXPECT_TRUE(converged(r.status)) << describe(r);
    EXPECT_GE((*r.durations)[1], 0.1) << describe(r);
    EXPECT_GE((*r.durations)[5], 0.12) << describe(r);
    expect_admissible(r, f);
  }
}

TEST(Planner, MinimumRampIsRespected) {
  const Format f = thesis_format();
  PlanOptions o;
  o.min_ramp = 0.08;
  for (Strategy s : kOptimising) {
    const PlanResult r = plan(f, s, o);
    EXPECT_TRUE(converged(r.status)) << describe(r);
    for (std::size_t i : {0u, 2u, 4u, 6u}) EXPECT_GE((*r.durations)[i], 0.08) << describe(r);
    expect_admissible(r, f, 0.08);
  }
}

// ---------------------------------------------------------------------------------------------
// 8. auto: SPEC §5's rule recomputed from the candidates.

// Checks the rule on plan(f, auto) and returns the plan.
PlanResult expect_auto_rule(const Format& f) {
  const PlanOptions o;
  const PlanResult r = plan(f, Strategy::kAuto, o);
  EXPECT_EQ(r.candidates.size(), 7u);
  if (r.candidates.size() != 7u) return r;
  const Strategy order[] = {Strategy::kBaseline,    Strategy::kNotch,      Strategy::kMultiNotch,
                            Strategy::kMinJerkBand, Strategy::kTimeDomain, Strategy::kFirChain,
                            Strategy::kShaper};
  const SloshingModel model = make_sloshing_model(f, o.model);
  int chosen_count = 0;
  std::size_t chosen = 0;
  for (std::size_t k = 0; k < r.candidates.size(); ++k) {
    const PlanCandidate& c = r.candidates[k];
    EXPECT_EQ(to_string(c.strategy), to_string(order[k]));
    if (c.chosen) {
      ++chosen_count;
      chosen = k;
    }
    // The predictions are the dense simulation of the candidate's law, which is its durations'
    // 7-segment law when it has durations.
    if (c.durations) {
      EXPECT_EQ(c.law.breakpoints(), SevenSegmentLaw(*c.durations, f.stroke).law().breakpoints());
    }
    const SloshPeaks p = NonlinearResponse(model, c.law, o.rest_time).peaks();
    EXPECT_NEAR(c.prediction.nonlinear.motion.value, p.motion.value, 1e-12)
        << to_string(c.strategy);
    EXPECT_NEAR(c.prediction.nonlinear.rest.value, p.rest.value, 1e-12) << to_string(c.strategy);
    // Each candidate is what the strategy gives on its own.
    if (c.strategy != Strategy::kBaseline) {
      EXPECT_EQ(c.durations, plan(f, c.strategy, o).durations) << to_string(c.strategy);
    }
  }
  EXPECT_EQ(chosen_count, 1);
  if (chosen_count != 1) return r;
  // Eligible: usable status; among them, those within 5 % of the best eta_motion; among those,
  // the lowest eta_rest.
  auto usable = [](SolveStatus s) {
    return s == SolveStatus::kOptimal || s == SolveStatus::kAcceptable ||
           s == SolveStatus::kTimeLimit;
  };
  // The eta bound first: only the usable candidates within eta_rest_max compete; when none is,
  // auto returns the lowest eta_rest of the usable ones and time_domain's, as infeasible.
  const auto within = [&](const PlanCandidate& c) {
    return c.prediction.nonlinear.rest.value <= o.eta_rest_max * (1.0 + 1e-6);
  };
  bool any_within = false;
  for (const PlanCandidate& c : r.candidates)
    any_within = any_within || (usable(c.status) && within(c));
  if (!any_within) {
    // Among those whose one fault is the bound, not worse than the uniform law while one is not.
    auto bound_only = [&](const PlanCandidate& c) {
      return usable(c.status) || c.strategy == Strategy::kTimeDomain;
    };
    bool any_not_worse = false;
    for (const PlanCandidate& c : r.candidates) {
      any_not_worse = any_not_worse || (bound_only(c) && c.worse_than_baseline.empty());
    }
    std::size_t least = r.candidates.size();
    for (std::size_t k = 0; k < r.candidates.size(); ++k) {
      const PlanCandidate& c = r.candidates[k];
      if (!bound_only(c) || (any_not_worse && !c.worse_than_baseline.empty())) continue;
      if (least == r.candidates.size() ||
          c.prediction.nonlinear.rest.value < r.candidates[least].prediction.nonlinear.rest.value) {
        least = k;
      }
    }
    EXPECT_EQ(chosen, least);
    EXPECT_EQ(to_string(r.status), to_string(SolveStatus::kInfeasible));
    EXPECT_TRUE(Contains(r.message, "no candidate meets eta_rest <= ")) << r.message;
    return r;
  }
  double best_motion = std::numeric_limits<double>::infinity();
  for (const PlanCandidate& c : r.candidates) {
    if (usable(c.status) && within(c)) {
      best_motion = std::min(best_motion, c.prediction.nonlinear.motion.value);
    }
  }
  double best_rest = std::numeric_limits<double>::infinity();
  std::size_t expected = r.candidates.size();
  for (std::size_t k = 0; k < r.candidates.size(); ++k) {
    const PlanCandidate& c = r.candidates[k];
    if (!usable(c.status) || !within(c) ||
        c.prediction.nonlinear.motion.value > 1.05 * best_motion) {
      continue;
    }
    if (c.prediction.nonlinear.rest.value < best_rest) {
      best_rest = c.prediction.nonlinear.rest.value;
      expected = k;
    }
  }
  EXPECT_LT(expected, r.candidates.size());
  if (expected == r.candidates.size()) return r;
  const PlanCandidate& c = r.candidates[chosen];
  EXPECT_TRUE(usable(c.status));
  EXPECT_LE(c.prediction.nonlinear.motion.value, 1.05 * best_motion);
  // Ties (within 1e-6) may be broken by the peak acceleration.
  EXPECT_LE(c.prediction.nonlinear.rest.value, best_rest * (1.0 + 1e-6))
      << "chose " << to_string(c.strategy) << ", expected " << to_string(order[expected]);
  EXPECT_EQ(r.durations, c.durations);
  EXPECT_EQ(to_string(r.status), to_string(c.status));
  EXPECT_TRUE(Contains(r.message, "auto chose " + to_string(c.strategy)));
  return r;
}

TEST(Planner, AutoPicksTheLowestRestAmongTheCandidatesNearTheBestMotion) {
  // Thesis format: the ZV-shaped poly5 law has the best eta_motion (25.6 mm; time_domain 26.7 mm,
  // outside the 5 % window); observed pick shaper.
  const PlanResult r = expect_auto_rule(thesis_format());
  EXPECT_EQ(r.candidates.size(), 7u);
}

TEST(Planner, AutoIgnoresInfeasibleCandidates) {
  // 0.8 m in 0.5 s: min_jerk_band and time_domain are infeasible (time_domain's least infeasible
  // point has the lowest eta_motion of all, 90.6 mm, and must not set the 5 % window); observed
  // pick multi_notch (eta_rest 108.6 mm vs notch 108.8 mm).
  const PlanResult r = expect_auto_rule(make_format(0.8, 0.5));
  // The case exercises the rule: an infeasible candidate moves less during the motion than every
  // usable one, so counting it would shift the 5 % window.
  double best_usable = std::numeric_limits<double>::infinity();
  double best_infeasible = std::numeric_limits<double>::infinity();
  for (const PlanCandidate& c : r.candidates) {
    const double motion = c.prediction.nonlinear.motion.value;
    if (c.status == SolveStatus::kInfeasible) {
      best_infeasible = std::min(best_infeasible, motion);
    } else {
      best_usable = std::min(best_usable, motion);
    }
    // No candidate reaches eta_rest <= 3 mm here: auto returns the least infeasible law
    // (expect_auto_rule checks which) as infeasible.
    if (c.chosen) {
      EXPECT_EQ(to_string(r.status), to_string(SolveStatus::kInfeasible));
    }
  }
  EXPECT_LT(best_infeasible, best_usable / 1.05);
}

// ---------------------------------------------------------------------------------------------
// 9. The Ipopt path.

TEST(Planner, IpoptMultiNotchIsUsableAndAsGoodAsNlopt) {
  const Format f = thesis_format();
  PlanOptions nl;
  nl.solver = SolverChoice::kNlopt;
  PlanOptions ip;
  ip.solver = SolverChoice::kIpopt;
  // Ipopt takes ~2 s here in a Release build and several times more under a sanitizer: a budget
  // that is not the default 5 s, so the test checks the solver and not the machine's speed.
  ip.time_limit = 600.0;
  const PlanResult a = plan(f, Strategy::kMultiNotch, nl);
  const PlanResult b = plan(f, Strategy::kMultiNotch, ip);
  ASSERT_TRUE(converged(a.status)) << describe(a);
  EXPECT_EQ(b.solver.name, "ipopt");
  EXPECT_EQ(a.solver.name, "nlopt-slsqp");
  expect_admissible(b, f);
  const double objective_nlopt = multi_notch_objective((*a.durations), f, nl);
  const double objective_ipopt = multi_notch_objective((*b.durations), f, ip);
  // Observed: both reach 9.1464e-4, but Ipopt takes ~1.8 s (10 starts, ~20000 evaluations,
  // the uniform start runs into the iteration limit) against ~1.5 ms for NLopt.
  EXPECT_TRUE(converged(b.status)) << describe(b);
  EXPECT_LE(objective_ipopt, 1.05 * objective_nlopt)
      << "ipopt " << objective_ipopt << ", nlopt " << objective_nlopt;
}

// ---------------------------------------------------------------------------------------------
// 10. PlanOptions::is_valid.

TEST(PlanOptionsValidation, RejectsFloorsLongerThanTheMotionNamingMinRamp) {
  const Format f = thesis_format();
  PlanOptions o;
  o.min_ramp = 0.2;
  o.plateau_min = {0.1, 0.12};  // 4 x 0.2 + 0.22 = 1.02 s > 1 s
  InvalidInput error;
  EXPECT_FALSE(o.is_valid(f, &error));
  EXPECT_TRUE(Contains(error.message, "min_ramp = 0.2 s"));
  EXPECT_TRUE(Contains(error.message, "plateau_min = [0.1, 0.12] s"));
  EXPECT_TRUE(Contains(error.message, "1.02 s"));
  EXPECT_TRUE(Contains(error.message, "motion_time 1 s"));
  EXPECT_TRUE(
      Contains(error.message, "min_ramp <= (motion_time - plateau minimums) / 4 = 0.195 s"));
  // Exactly filling the motion time is allowed (4 x 0.25 = 1 s).
  PlanOptions full;
  full.min_ramp = 0.25;
  EXPECT_TRUE(full.is_valid(f, &error));
  PlanOptions over;
  over.min_ramp = 0.26;
  EXPECT_FALSE(over.is_valid(f, &error));
  EXPECT_TRUE(Contains(error.message, "min_ramp = 0.26 s"));
}

TEST(PlanOptionsValidation, RejectsZeroWeightsAndAFullWidthNotch) {
  const Format f = thesis_format();
  InvalidInput error;
  PlanOptions zero;
  zero.weights = {0.0, 0.0, 0.0};
  EXPECT_FALSE(zero.is_valid(f, &error));
  EXPECT_TRUE(Contains(error.message, "weights = [0, 0, 0]"));
  EXPECT_TRUE(Contains(error.message, "at least one weight must be > 0"));
  PlanOptions one_weight;
  one_weight.weights = {0.0, 1.0, 0.0};
  EXPECT_TRUE(one_weight.is_valid(f, &error));
  PlanOptions p1;
  p1.p_notch = 1.0;
  EXPECT_FALSE(p1.is_valid(f, &error));
  EXPECT_TRUE(Contains(error.message, "p_notch = 1"));
  EXPECT_TRUE(Contains(error.message, "must be finite and in (0, 1)"));
}

TEST(PlanOptionsValidation, DefaultsAreValidAndLeaveTheErrorUntouched) {
  InvalidInput error;
  error.message = "untouched";
  EXPECT_TRUE(PlanOptions{}.is_valid(thesis_format(), &error));
  EXPECT_EQ(error.message, "untouched");
  EXPECT_TRUE(PlanOptions{}.is_valid(thesis_format(), nullptr));
}

// ---------------------------------------------------------------------------------------------
// 11. Time budget.

TEST(Planner, ExhaustedTimeBudgetReturnsTheBestAdmissiblePoint) {
  // Observed: the budget is gone before the first solve (the baseline prediction alone takes
  // longer): kTimeLimit with the uniform law, in ~2 ms.
  const Format f = thesis_format();
  PlanOptions o;
  o.time_limit = 1e-4;
  const auto start = std::chrono::steady_clock::now();
  const PlanResult r = plan(f, Strategy::kTimeDomain, o);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(to_string(r.status), to_string(SolveStatus::kTimeLimit)) << describe(r);
  EXPECT_TRUE(r.usable());
  EXPECT_TRUE(Contains(r.message, "time budget"));
  expect_admissible(r, f);
  EXPECT_LT(elapsed, 1.0);
}

// The uniform law is simulated once per plan and shared (the baseline comparison, auto's baseline
// candidate, plan(baseline)'s own prediction): every copy must equal a simulation of that law
// made here, to the last bit; and a baseline that is not the uniform law (min_ramp above T/7)
// must get its own law's figures, not the uniform law's.
TEST(Planner, TheSharedUniformPredictionIsTheUniformLawsOwnToTheLastBit) {
  std::mt19937 rng(20261126);
  std::vector<Format> formats{thesis_format()};
  for (int k = 0; k < 2; ++k) formats.push_back(test::random_format(rng));
  for (const Format& f : formats) {
    SCOPED_TRACE("R = " + std::to_string(f.container.radius) +
                 ", T = " + std::to_string(f.motion_time));
    PlanOptions o;
    o.robustness = false;
    const SloshingModel model = make_sloshing_model(f, o.model);
    auto expect_simulated = [&](const LawPrediction& p, const MotionLaw& law) {
      const SloshPeaks lin = LinearResponse(model, law, o.rest_time).peaks();
      const SloshPeaks nl = NonlinearResponse(model, law, o.rest_time).peaks();
      EXPECT_EQ(p.linear.motion.value, lin.motion.value);
      EXPECT_EQ(p.linear.motion.time, lin.motion.time);
      EXPECT_EQ(p.linear.rest.value, lin.rest.value);
      EXPECT_EQ(p.nonlinear.motion.value, nl.motion.value);
      EXPECT_EQ(p.nonlinear.motion.time, nl.motion.time);
      EXPECT_EQ(p.nonlinear.rest.value, nl.rest.value);
      EXPECT_EQ(p.nonlinear.rest.time, nl.rest.time);
      EXPECT_EQ(p.kinematics.v_peak, law.summary().v_peak);
    };
    const MotionLaw uniform = SevenSegmentLaw(uniform_durations(f.motion_time), f.stroke).law();
    const PlanResult b = plan(f, Strategy::kBaseline, o);
    ASSERT_EQ(b.status, SolveStatus::kOptimal) << b.message;
    expect_simulated(b.baseline, uniform);
    expect_simulated(b.prediction, uniform);
    const PlanResult a = plan(f, Strategy::kAuto, o);
    const auto base = std::find_if(a.candidates.begin(), a.candidates.end(),
                                   [](const auto& k) { return k.strategy == Strategy::kBaseline; });
    ASSERT_NE(base, a.candidates.end());
    expect_simulated(base->prediction, uniform);
    expect_simulated(a.baseline, uniform);
    // Ramps of at least T/5: the uniform law (ramps T/7) is excluded, baseline is another law.
    PlanOptions wide = o;
    wide.min_ramp = 0.2 * f.motion_time;
    const PlanResult w = plan(f, Strategy::kBaseline, wide);
    ASSERT_TRUE(w.durations);
    ASSERT_NE(*w.durations, uniform_durations(f.motion_time));
    expect_simulated(w.prediction, SevenSegmentLaw(*w.durations, f.stroke).law());
    expect_simulated(w.baseline, uniform);
    EXPECT_NE(w.prediction.nonlinear.motion.value, w.baseline.nonlinear.motion.value);
  }
}

// The tie rule is not transitive: A ties B and keeps it out on peak acceleration, then C, lower
// than A by more than the tie tolerance, replaces A while it still ties B. B lost to A, on a tie
// with A's peak acceleration; judged again against C it would claim a peak "not below" C's, false.
TEST(ChooseAuto, ALoserSaysWhatItLostToWhenTheWinnerIsLaterReplaced) {
  auto candidate = [](Strategy s, double eta_rest, double a_peak) {
    PlanCandidate c;
    c.strategy = s;
    c.status = SolveStatus::kOptimal;
    c.prediction.nonlinear.motion.value = 0.005;
    c.prediction.nonlinear.rest.value = eta_rest;
    c.prediction.kinematics.a_peak_positive = a_peak;
    c.prediction.kinematics.a_peak_negative = a_peak;
    return c;
  };
  const double rest = 1e-3;
  const std::vector<PlanCandidate> c{
      candidate(Strategy::kNotch, rest, 5.0),                        // A
      candidate(Strategy::kMultiNotch, rest * (1.0 - 0.9e-6), 6.0),  // B: ties A
      candidate(Strategy::kTimeDomain, rest * (1.0 - 1.5e-6), 7.0),  // C: below A, ties B
  };
  // The premises, computed here with the rule's 1e-6 relative tie.
  auto ties = [](double a, double b) { return std::abs(a - b) <= 1e-6 * b; };
  const double ra = c[0].prediction.nonlinear.rest.value;
  const double rb = c[1].prediction.nonlinear.rest.value;
  const double rc = c[2].prediction.nonlinear.rest.value;
  ASSERT_TRUE(ties(rb, ra));
  ASSERT_TRUE(rc < ra * (1.0 - 1e-6));
  ASSERT_TRUE(ties(rb, rc));

  const AutoChoice choice = choose_auto(c, {false, false, false});
  ASSERT_EQ(choice.index, 2u);
  const std::vector<CandidateLoss> lost{CandidateLoss::kHigherRest, CandidateLoss::kTieOnRest,
                                        CandidateLoss::kNone};
  EXPECT_EQ(choice.lost, lost);
  EXPECT_EQ(choice.lost_detail[0], "eta_rest 1 mm vs 1 mm of the chosen time_domain");
  EXPECT_EQ(choice.lost_detail[1],
            "eta_rest 1 mm ties with notch (kept then, later replaced; auto chose time_domain) "
            "and its peak acceleration 6 m/s^2 is not below 5 m/s^2");
  EXPECT_EQ(choice.lost_detail[2], "");
}

}  // namespace test_planner
}  // namespace slosh
