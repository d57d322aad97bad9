// The dual-number integrator of the time-domain strategy (core/src/nonlinear_sensitivity): its
// exact gradients against central finite differences of the same function, its values against
// the double integrator NonlinearResponse (same grid), and its peaks against an independent
// fine-step RK4 of eq. 2.35 re-typed from SPEC §2.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "response/nonlinear_sensitivity.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/response.hpp"
#include "support/fixtures.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_nonlinear_sensitivity {

using detail::NonlinearSensitivity;
using detail::WindowPeak;

constexpr double kStroke{0.8};
constexpr double kMotionTime{1.0};
constexpr double kRest{1.0};

SloshingModel thesis_model() {
  return make_sloshing_model(thesis_format(), {});
}

// Largest step of the integrators: min(1 ms, period_1 / 100) (NonlinearOptions defaults).
double max_step(const SloshingModel& model) {
  return std::min(1e-3, 2.0 * std::numbers::pi / model.omega1() / 100.0);
}

// True when every non-zero d / h is at least `margin` away from an integer: a finite-difference
// step far below margin * h then keeps the step count ceil(d / h) of the segment (no jump), and
// both integrators round the step count the same way.
bool away_from_step_multiples(const Durations& d, double h, double margin) {
  for (double di : d) {
    if (di == 0.0) continue;  // one empty step in the sensitivity, none in NonlinearResponse
    const double r = di / h;
    const double frac = r - std::floor(r);
    if (frac < margin || frac > 1.0 - margin) return false;
  }
  return true;
}

// Admissible durations summing to T, ramps >= 0.05 s, from a fixed-seed generator (the uniform
// variates are built from the raw 32-bit outputs of mt19937, fully specified by the standard).
std::vector<Durations> random_durations(int count, double h) {
  std::mt19937 rng(20251123u);
  auto uniform = [&rng] { return static_cast<double>(rng()) / 4294967296.0; };
  std::vector<Durations> out;
  while (static_cast<int>(out.size()) < count) {
    Durations w{};
    double total = 0.0;
    for (double& wi : w) {
      wi = 0.15 + uniform();
      total += wi;
    }
    const double room = kMotionTime - 4.0 * kDefaultMinRamp;
    Durations d{};
    double sum = 0.0;
    for (std::size_t i = 0; i + 1 < kSegments; ++i) {
      d[i] = (i % 2 == 0 ? kDefaultMinRamp : 0.0) + room * w[i] / total;
      sum += d[i];
    }
    d[kSegments - 1] = kMotionTime - sum;
    if (check_admissible(d, {kMotionTime, kDefaultMinRamp, 1e-12})) continue;
    if (!away_from_step_multiples(d, h, 0.02)) continue;
    out.push_back(d);
  }
  return out;
}

double window_value(NonlinearSensitivity& s, const Durations& d, double a, double b) {
  s.compute(d.data());
  return s.window_peak(a, b).value;
}

double eta_value(NonlinearSensitivity& s, const Durations& d, double t) {
  s.compute(d.data());
  std::vector<double> v;
  s.abs_eta_at({t}, &v, nullptr);
  return v.front();
}

// Central difference of f along every duration with step h (the same function the sensitivity
// differentiates, evaluated in double; truncation O(h^2), round-off ~1e-16 |f| / h).
template <typename F>
std::array<double, kSegments> central_difference(const F& f, const Durations& d, double h) {
  std::array<double, kSegments> g{};
  for (std::size_t i = 0; i < kSegments; ++i) {
    Durations up = d, down = d;
    up[i] += h;
    down[i] -= h;
    g[i] = (f(up) - f(down)) / (2.0 * h);
  }
  return g;
}

double max_abs(const std::array<double, kSegments>& g) {
  double m = 0.0;
  for (double gi : g) m = std::max(m, std::abs(gi));
  return m;
}

constexpr double kFdStep{1e-7};  // [s]
// Relative to the largest gradient component; observed 2.7e-9 (round-off of the difference).
constexpr double kGradientTolerance{1e-7};

TEST(NonlinearSensitivity, RandomDurationsAvoidStepCountJumps) {
  // The finite-difference tests below rely on this: every segment is >= 2 % of a step away from
  // a multiple of the step, far more than the 1e-7 s difference step (1e-4 of a 1 ms step).
  const SloshingModel model = thesis_model();
  const double h = max_step(model);
  EXPECT_DOUBLE_EQ(h, 1e-3);  // thesis format: period 0.33 s, so the 1 ms cap applies
  for (const Durations& d : random_durations(6, h)) {
    EXPECT_FALSE(check_admissible(d, {kMotionTime, kDefaultMinRamp, 1e-12}).has_value());
    EXPECT_TRUE(away_from_step_multiples(d, h, 0.02));
    EXPECT_TRUE(away_from_step_multiples(d, h, 100.0 * kFdStep / h));
  }
}

TEST(NonlinearSensitivity, WindowPeakGradientMatchesCentralDifferences) {
  const SloshingModel model = thesis_model();
  NonlinearSensitivity sens(model, kStroke, kRest);
  NonlinearSensitivity probe(model, kStroke, kRest);
  const std::array<std::array<double, 2>, 3> windows{
      {{0.0, kMotionTime}, {kMotionTime, kMotionTime + kRest}, {0.3, 0.7}}};
  for (const Durations& d : random_durations(6, max_step(model))) {
    sens.compute(d.data());
    for (const auto& window : windows) {
      // Plain names, not a structured binding: clang 14 (the sanitizer build) cannot capture one.
      const double a = window[0];
      const double b = window[1];
      const WindowPeak peak = sens.window_peak(a, b);
      ASSERT_GT(peak.value, 1e-4) << "window [" << a << ", " << b << "]";
      const auto fd = central_difference(
          [&](const Durations& x) { return window_value(probe, x, a, b); }, d, kFdStep);
      const double scale = max_abs(fd);
      ASSERT_GT(scale, 1e-4);
      for (std::size_t i = 0; i < kSegments; ++i) {
        EXPECT_NEAR(peak.gradient[i], fd[i], kGradientTolerance * scale)
            << "window [" << a << ", " << b << "], direction " << i << ", d = {" << d[0] << ", "
            << d[1] << ", " << d[2] << ", " << d[3] << ", " << d[4] << ", " << d[5] << ", " << d[6]
            << "}";
      }
    }
  }
}

TEST(NonlinearSensitivity, AbsEtaGradientMatchesCentralDifferences) {
  const SloshingModel model = thesis_model();
  NonlinearSensitivity sens(model, kStroke, kRest);
  NonlinearSensitivity probe(model, kStroke, kRest);
  // Off the integration grid, in the motion and in the rest window.
  std::vector<double> times;
  for (int k = 0; k < 24; ++k) times.push_back(0.0371 + 0.0789 * k);
  int checked = 0;
  for (const Durations& d : random_durations(4, max_step(model))) {
    sens.compute(d.data());
    std::vector<double> values;
    std::vector<std::array<double, kSegments>> gradients;
    sens.abs_eta_at(times, &values, &gradients);
    ASSERT_EQ(values.size(), times.size());
    ASSERT_EQ(gradients.size(), times.size());
    const double peak = *std::max_element(values.begin(), values.end());
    for (std::size_t k = 0; k < times.size(); ++k) {
      // |eta| has a kink where eta crosses zero: compare only where it is well away from zero.
      if (values[k] < 0.05 * peak) continue;
      const double t = times[k];
      const auto fd = central_difference([&](const Durations& x) { return eta_value(probe, x, t); },
                                         d, kFdStep);
      const double scale = max_abs(fd);
      for (std::size_t i = 0; i < kSegments; ++i) {
        EXPECT_NEAR(gradients[k][i], fd[i], kGradientTolerance * scale)
            << "t = " << t << ", direction " << i;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 40);
}

TEST(NonlinearSensitivity, ValuesMatchNonlinearResponseOnTheSameGrid) {
  const SloshingModel model = thesis_model();
  NonlinearSensitivity sens(model, kStroke, kRest);
  const double h = max_step(model);
  std::vector<Durations> cases = random_durations(3, h);
  cases.push_back(uniform_durations(kMotionTime));
  // Zero cruise and zero plateaus: the sensitivity takes an empty step on each, the double
  // integrator skips the segment; the values must still agree.
  cases.push_back(Durations{0.2003, 0.0, 0.1507, 0.0, 0.3011, 0.0, 0.3479});
  for (const Durations& d : cases) {
    // Same grid only when no segment is a multiple of the step (see the next test).
    ASSERT_TRUE(away_from_step_multiples(d, h, 0.02));
    const SevenSegmentLaw law(d, kStroke);
    const NonlinearResponse response(model, law.law(), kRest);
    sens.compute(d.data());
    EXPECT_DOUBLE_EQ(sens.motion_time(), law.motion_time());
    const SloshPeaks p = response.peaks();
    const double T = law.motion_time();
    const WindowPeak motion = sens.window_peak(0.0, T);
    const WindowPeak rest = sens.window_peak(T, T + kRest);
    // Both locate the maximum of the same Hermite interpolant (exact roots here, golden section
    // to 1e-10 s there).
    EXPECT_NEAR(motion.value, p.motion.value, 1e-9 * p.motion.value);
    EXPECT_NEAR(rest.value, p.rest.value, 1e-9 * p.rest.value);
    EXPECT_NEAR(motion.time, p.motion.time, 1e-6);
    EXPECT_NEAR(rest.time, p.rest.time, 1e-6);
    // Point values of the dense output.
    std::vector<double> times;
    for (int k = 0; k < 400; ++k) times.push_back(0.00123 + 0.004987 * k);
    std::vector<double> values;
    sens.abs_eta_at(times, &values, nullptr);
    const double scale = std::max(p.motion.value, p.rest.value);
    for (std::size_t k = 0; k < times.size(); ++k) {
      EXPECT_NEAR(values[k], std::abs(response.eta(times[k])), 1e-12 * scale) << "t = " << times[k];
    }
  }
}

TEST(NonlinearSensitivity, SegmentsOnExactStepMultiplesMayTakeOneStepMore) {
  // 0.17 s / 1 ms = 170.00000000000003 in double: the sensitivity (ceil(d_k / h)) takes 171 steps
  // on segment 2 where NonlinearResponse (ceil((t_2 - t_1) / h) with t_2 - t_1 =
  // 0.16999999999999998) takes 170. Both grids are valid RK4 grids: the values then agree to the
  // integration error (observed 1.2e-11 m on a 45 mm peak), not to round-off.
  const SloshingModel model = thesis_model();
  const Durations d = test::kAsymmetricDurations;
  EXPECT_FALSE(away_from_step_multiples(d, max_step(model), 1e-6));
  const SevenSegmentLaw law(d, kStroke);
  const NonlinearResponse response(model, law.law(), kRest);
  NonlinearSensitivity sens(model, kStroke, kRest);
  sens.compute(d.data());
  const SloshPeaks p = response.peaks();
  const double scale = std::max(p.motion.value, p.rest.value);
  std::vector<double> times;
  for (int k = 0; k < 400; ++k) times.push_back(0.00123 + 0.004987 * k);
  std::vector<double> values;
  sens.abs_eta_at(times, &values, nullptr);
  for (std::size_t k = 0; k < times.size(); ++k) {
    EXPECT_NEAR(values[k], std::abs(response.eta(times[k])), 1e-8 * scale) << "t = " << times[k];
  }
  EXPECT_NEAR(sens.window_peak(0.0, 1.0).value, p.motion.value, 1e-8 * scale);
  EXPECT_NEAR(sens.window_peak(1.0, 2.0).value, p.rest.value, 1e-8 * scale);
}

// A solver differentiates the response it is given: across a duration where a segment's step
// count would change (d_k / h crossing an integer) the response must not jump. With the counts
// frozen at d, the response at d + delta e_k is its first-order Taylor expansion from the exact
// gradient at d (the second-order term is ~1e-18 here); a sensitivity that follows the counts of
// its own durations jumps by the difference of two discretisations. Coarse steps (8 per period)
// make that difference large enough to see; the property does not depend on the step.
TEST(NonlinearSensitivity, FrozenStepCountsKeepTheResponseSmoothAcrossAStepMultiple) {
  const SloshingModel model = thesis_model();
  NonlinearOptions coarse;
  coarse.steps_per_period = 8.0;
  const double h =
      std::min(coarse.max_step, 2.0 * std::numbers::pi / model.omega1() / coarse.steps_per_period);
  Durations d = uniform_durations(kMotionTime);
  const std::size_t k = 1;  // the first plateau
  const double multiple = std::ceil(d[k] / h) * h;
  const double delta = 1e-9;
  d[k] = multiple - 0.5 * delta;
  Durations moved = d;
  moved[k] = multiple + 0.5 * delta;
  ASSERT_LT(step_count(d[k], h, 1), step_count(moved[k], h, 1));
  std::vector<double> times;
  for (int j = 0; j < 40; ++j) times.push_back(1.0 + 0.0237 * j);  // the rest window
  // The worst departure of the response at `moved` from its Taylor expansion at d [m].
  auto departure = [&](NonlinearSensitivity& s) {
    std::vector<double> at_d, at_moved;
    std::vector<std::array<double, kSegments>> gradients;
    s.compute(d.data());
    s.abs_eta_at(times, &at_d, &gradients);
    s.compute(moved.data());
    s.abs_eta_at(times, &at_moved, nullptr);
    const double scale = *std::max_element(at_d.begin(), at_d.end());
    double worst = 0.0;
    for (std::size_t j = 0; j < times.size(); ++j) {
      if (at_d[j] < 0.05 * scale) continue;  // |eta| has a kink at its zeros
      worst = std::max(worst, std::abs(at_moved[j] - (at_d[j] + gradients[j][k] * delta)));
    }
    return worst / scale;
  };
  NonlinearSensitivity frozen(model, kStroke, kRest, coarse);
  EXPECT_TRUE(frozen.freeze_steps(d.data()));
  EXPECT_FALSE(frozen.freeze_steps(d.data()));
  NonlinearSensitivity own(model, kStroke, kRest, coarse);
  EXPECT_LT(departure(frozen), 1e-13);
  EXPECT_GT(departure(own), 1e-10);
}

// compute(d, until) stops the rest window after the step holding `until` (time_domain's solver
// reads nothing later): every |eta| and gradient up to there is the whole window's to the last
// bit, window peaks inside that span too, complete() tells the truncated from the whole, and
// complete_rest() makes it the whole.
TEST(NonlinearSensitivity, ARestWindowCutAfterTheLastReadTimeChangesNothingBefore) {
  const SloshingModel model = thesis_model();
  NonlinearOptions o;
  o.steps_per_period = 20.0;  // time_domain's scheme
  const double period = 2.0 * std::numbers::pi / model.omega1();
  for (const Durations& d : random_durations(4, max_step(model))) {
    NonlinearSensitivity whole(model, kStroke, kRest, o);
    NonlinearSensitivity cut(model, kStroke, kRest, o);
    whole.freeze_steps(d.data());
    cut.freeze_steps(d.data());
    const double until = kMotionTime + 1.03 * period;
    whole.compute(d.data());
    cut.compute(d.data(), until);
    EXPECT_TRUE(whole.complete());
    EXPECT_FALSE(cut.complete());
    std::vector<double> times;
    for (int j = 0; j <= 200; ++j) times.push_back(until * j / 200.0);
    std::vector<double> v_whole, v_cut;
    std::vector<std::array<double, kSegments>> g_whole, g_cut;
    whole.abs_eta_at(times, &v_whole, &g_whole);
    cut.abs_eta_at(times, &v_cut, &g_cut);
    for (std::size_t j = 0; j < times.size(); ++j) {
      EXPECT_EQ(v_whole[j], v_cut[j]) << times[j];
      EXPECT_EQ(g_whole[j], g_cut[j]) << times[j];
    }
    const WindowPeak a = whole.window_peak(kMotionTime + 1e-12, until);
    const WindowPeak b = cut.window_peak(kMotionTime + 1e-12, until);
    EXPECT_EQ(a.value, b.value);
    EXPECT_EQ(a.time, b.time);
    EXPECT_EQ(a.gradient, b.gradient);
    // complete_rest() integrates the rest of the window from the saved state at T: the whole
    // window's response to the last bit, peaks and gradients included.
    cut.complete_rest();
    EXPECT_TRUE(cut.complete());
    times.clear();
    for (int j = 0; j <= 400; ++j) times.push_back((kMotionTime + kRest) * j / 400.0);
    whole.abs_eta_at(times, &v_whole, &g_whole);
    cut.abs_eta_at(times, &v_cut, &g_cut);
    EXPECT_EQ(v_whole, v_cut);
    EXPECT_EQ(g_whole, g_cut);
    const WindowPeak c = whole.window_peak(kMotionTime + 1e-12, kMotionTime + kRest);
    const WindowPeak e = cut.window_peak(kMotionTime + 1e-12, kMotionTime + kRest);
    EXPECT_EQ(c.value, e.value);
    EXPECT_EQ(c.gradient, e.gradient);
    // A cut at T keeps one rest step; without `until` the whole window is integrated again.
    cut.compute(d.data(), kMotionTime);
    EXPECT_FALSE(cut.complete());
    cut.compute(d.data());
    EXPECT_TRUE(cut.complete());
  }
}

// compute(d, until, false) integrates the values alone (SLSQP's line-search trial points and the
// dense checks read no gradient): every |eta|, window peak and its time is that of the full
// computation to the last bit, the truncated rest window completed included.
TEST(NonlinearSensitivity, ValuesAloneAreTheSameBitsAsWithTheirGradients) {
  const SloshingModel model = thesis_model();
  NonlinearOptions o;
  o.steps_per_period = 20.0;  // time_domain's scheme
  const double period = 2.0 * std::numbers::pi / model.omega1();
  const double until = kMotionTime + 0.77 * period;
  for (const Durations& d : random_durations(4, max_step(model))) {
    NonlinearSensitivity full(model, kStroke, kRest, o);
    NonlinearSensitivity values(model, kStroke, kRest, o);
    full.freeze_steps(d.data());
    values.freeze_steps(d.data());
    full.compute(d.data(), until);
    values.compute(d.data(), until, false);
    EXPECT_TRUE(full.has_gradients());
    EXPECT_FALSE(values.has_gradients());
    std::vector<double> times;
    for (int j = 0; j <= 300; ++j) times.push_back(until * j / 300.0);
    std::vector<double> v_full, v_values;
    std::vector<std::array<double, kSegments>> g_full;
    full.abs_eta_at(times, &v_full, &g_full);
    values.abs_eta_at(times, &v_values, nullptr);
    EXPECT_EQ(v_full, v_values);
    full.complete_rest();
    values.complete_rest();
    EXPECT_TRUE(values.complete());
    for (const auto& [a, b] : {std::pair{0.0, kMotionTime}, std::pair{kMotionTime + 1e-12, until},
                               std::pair{kMotionTime + 1e-12, kMotionTime + kRest}}) {
      const WindowPeak f = full.window_peak(a, b);
      const WindowPeak v = values.window_peak(a, b);
      EXPECT_EQ(f.value, v.value) << a << " " << b;
      EXPECT_EQ(f.time, v.time) << a << " " << b;
      EXPECT_EQ(v.gradient, (std::array<double, kSegments>{})) << a << " " << b;
    }
  }
}

// A solver run frozen at d sees a smooth response while every segment keeps at most its frozen
// count (freeze_steps: one step more than d takes); a segment grown by more than a step takes
// more, and outgrows_frozen_steps says so (time_domain then runs the solver again from there).
TEST(NonlinearSensitivity, OutgrowingTheFrozenStepCountsIsReported) {
  const SloshingModel model = thesis_model();
  NonlinearOptions coarse;
  coarse.steps_per_period = 8.0;
  const double h =
      std::min(coarse.max_step, 2.0 * std::numbers::pi / model.omega1() / coarse.steps_per_period);
  NonlinearSensitivity sens(model, kStroke, kRest, coarse);
  const Durations d = uniform_durations(kMotionTime);
  EXPECT_FALSE(sens.outgrows_frozen_steps(d.data(), d.data()));
  for (std::size_t k = 0; k < kSegments; ++k) {
    // The count of d_k is ceil(d_k / h); the frozen one is that plus one.
    const double frozen = std::ceil(d[k] / h) + 1.0;
    Durations within = d;
    within[k] = frozen * h * (1.0 - 1e-9);  // still the frozen count
    Durations beyond = d;
    beyond[k] = frozen * h * (1.0 + 1e-6);  // one step more than frozen
    Durations shrunk = d;
    shrunk[k] = 0.5 * d[k];
    EXPECT_FALSE(sens.outgrows_frozen_steps(d.data(), within.data())) << k;
    EXPECT_TRUE(sens.outgrows_frozen_steps(d.data(), beyond.data())) << k;
    EXPECT_FALSE(sens.outgrows_frozen_steps(d.data(), shrunk.data())) << k;
  }
}

// eq. 2.35 re-typed from SPEC §2 (tests/support), with this model's parameters.
double reference_xbar_dd(const SloshingModel& m, double x, double v, double a) {
  return test::eq235_xbar_dd(m.omega[0], m.zeta, m.C, m.alpha, m.radius, x, v, a);
}

// Both the default scheme and time_domain's (20 steps per period of mode 1).
class NonlinearSensitivityPeaks : public ::testing::TestWithParam<double> {};

TEST_P(NonlinearSensitivityPeaks, MatchAnIndependentTenTimesFinerRk4) {
  const SloshingModel model = thesis_model();
  const double h = max_step(model);
  NonlinearOptions options;
  options.steps_per_period = GetParam();
  NonlinearSensitivity sens(model, kStroke, kRest, options);
  std::vector<Durations> cases = random_durations(2, h);
  cases.push_back(test::kAsymmetricDurations);
  for (const Durations& d : cases) {
    const SevenSegmentLaw law(d, kStroke);
    const test::TrapezoidAcceleration acc{d, law.A(), law.B()};
    const double T = law.motion_time();
    const test::Rk4Trajectory ref = test::rk4_solve(
        [&](double t, double x, double v) { return reference_xbar_dd(model, x, v, acc(t)); },
        T + kRest, h / 10.0);
    sens.compute(d.data());
    const double motion = sens.window_peak(0.0, T).value;
    const double rest = sens.window_peak(T, T + kRest).value;
    const double ref_motion = test::parabola_peak(ref, model.K, 0.0, T);
    const double ref_rest = test::parabola_peak(ref, model.K, T, T + kRest);
    EXPECT_GT(ref_motion, 5e-3);
    // Observed agreement 5e-9 relative (1 ms RK4 on the breakpoint-aligned grid vs 0.1 ms).
    EXPECT_NEAR(motion, ref_motion, 1e-7 * ref_motion);
    EXPECT_NEAR(rest, ref_rest, 1e-7 * std::max(ref_rest, ref_motion));
  }
}

INSTANTIATE_TEST_SUITE_P(StepsPerPeriod, NonlinearSensitivityPeaks, ::testing::Values(40.0, 20.0));

}  // namespace test_nonlinear_sensitivity
}  // namespace slosh
