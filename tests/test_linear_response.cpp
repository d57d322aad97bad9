// The exact linear response against an independent fine-step RK4 solve of SPEC §2's mode
// equations, and its peaks against a dense scan.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/response/response.hpp"
#include "support/fixtures.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_linear_response {

// Reference eta(t) on a grid: every mode integrated by RK4 with step h from rest.
struct ReferenceEta {
  std::vector<test::Rk4Trajectory> modes;
  std::vector<double> gains;
  double at(double t) const {
    double eta = 0.0;
    for (std::size_t m = 0; m < modes.size(); ++m) eta += gains[m] * modes[m].x_at(t);
    return eta;
  }
};

template <typename Accel>
ReferenceEta reference_eta(const SloshingModel& model, const Accel& a, double t_end, double h) {
  ReferenceEta r;
  r.gains = model.eta_gain;
  for (int m = 0; m < model.modes(); ++m) {
    const double w = model.omega[m], z = model.zeta;
    r.modes.push_back(test::rk4_solve(
        [&](double t, double x, double v) { return -a(t) - 2.0 * z * w * v - w * w * x; }, t_end,
        h));
  }
  return r;
}

TEST(LinearResponse, SevenSegmentMatchesFineStepRk4) {
  ModelOptions options;
  options.modes = 3;
  const SloshingModel model = make_sloshing_model(thesis_format(), options);
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.8);
  const test::TrapezoidAcceleration a{law.durations(), law.A(), law.B()};
  const LinearResponse exact(model, law.law(), 1.0);
  const double h = 2e-6;  // the reference grid; compare on its nodes only
  const ReferenceEta ref = reference_eta(model, a, 2.0, h);
  double worst = 0.0, peak = 0.0;
  for (std::size_t i = 0; i < ref.modes[0].t.size(); i += 97) {
    const double t = ref.modes[0].t[i];
    double eta_ref = 0.0;
    for (int m = 0; m < 3; ++m) {
      eta_ref += model.eta_gain[m] * ref.modes[m].x[i];
      EXPECT_NEAR(exact.mode_state(m, t).x, ref.modes[m].x[i], 1e-9) << "mode " << m << " t " << t;
      EXPECT_NEAR(exact.mode_state(m, t).x_dot, ref.modes[m].v[i], 1e-8)
          << "mode " << m << " t " << t;
    }
    worst = std::max(worst, std::abs(exact.eta(t) - eta_ref));
    peak = std::max(peak, std::abs(eta_ref));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(peak, 0.01);  // a real excitation: centimetres of sloshing
}

TEST(LinearResponse, HarmonicPiecesMatchRk4) {
  // The cycloidal law exercises the harmonic particular solution.
  ModelOptions options;
  options.modes = 2;
  const SloshingModel model = make_sloshing_model(thesis_format(), options);
  const MotionLaw law = make_cycloidal_law(0.5, 0.7);
  const LinearResponse exact(model, law, 0.8);
  const double T = 0.7, s = 0.5;
  const auto a = [&](double t) {
    return t <= 0.0 || t >= T
               ? 0.0
               : 2.0 * std::numbers::pi * s / (T * T) * std::sin(2.0 * std::numbers::pi * t / T);
  };
  const ReferenceEta ref = reference_eta(model, a, 1.5, 2e-6);
  for (double t : {0.1, 0.35, 0.7, 0.9, 1.23, 1.5}) {
    EXPECT_NEAR(exact.eta(t), ref.at(t), 1e-9) << t;
  }
}

TEST(LinearResponse, UndampedResonantHarmonicMatchesRk4) {
  // Cycloidal law whose harmonic frequency is exactly omega_1 with zeta = 0: the secular
  // particular solution tau (U cos + V sin).
  ModelOptions options;
  options.modes = 1;
  options.damping = DampingCorrelation::kExplicit;
  options.explicit_zeta = 0.0;
  const SloshingModel model = make_sloshing_model(thesis_format(), options);
  const double T = 2.0 * std::numbers::pi / model.omega[0];
  const double s = 0.1;
  const MotionLaw law = make_cycloidal_law(s, T);
  const LinearResponse exact(model, law, 0.5);
  const auto a = [&](double t) {
    return t <= 0.0 || t >= T
               ? 0.0
               : 2.0 * std::numbers::pi * s / (T * T) * std::sin(2.0 * std::numbers::pi * t / T);
  };
  const ReferenceEta ref = reference_eta(model, a, T + 0.5, 1e-6);
  for (double t : {0.05, T / 2, T, T + 0.25, T + 0.5}) {
    EXPECT_NEAR(exact.eta(t), ref.at(t), 1e-9) << t;
  }
}

TEST(LinearResponse, PeaksAreTheMaximaOfTheContinuousResponse) {
  const SloshingModel model = make_sloshing_model(thesis_format(), {});
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.8);
  const LinearResponse r(model, law.law(), 1.0);
  const SloshPeaks p = r.peaks();
  // Dense independent scan at 10 us.
  double motion = 0.0, rest = 0.0;
  for (int i = 0; i <= 200000; ++i) {
    const double t = 1e-5 * i;
    (t <= 1.0 ? motion : rest) = std::max(t <= 1.0 ? motion : rest, std::abs(r.eta(t)));
  }
  EXPECT_GE(p.motion.value, motion - 1e-12);
  EXPECT_LT(p.motion.value - motion, 1e-8 * motion);
  EXPECT_GE(p.rest.value, rest - 1e-12);
  EXPECT_LT(p.rest.value - rest, 1e-8 * rest);
  EXPECT_NEAR(std::abs(r.eta(p.motion.time)), p.motion.value, 1e-15);
  EXPECT_LE(p.motion.time, 1.0);
  EXPECT_GE(p.rest.time, 1.0);
  EXPECT_LE(p.rest.time, 2.0);
}

TEST(LinearResponse, StartsAtRestAndDecaysAtTheDampingRate) {
  ModelOptions options;
  options.modes = 1;
  const SloshingModel model = make_sloshing_model(thesis_format(), options);
  const SevenSegmentLaw law(uniform_durations(1.0), 0.8);
  const LinearResponse r(model, law.law(), 30.0);
  EXPECT_EQ(r.eta(0.0), 0.0);
  // After the motion the free response decays as exp(-zeta w t): compare energy envelopes.
  const auto energy = [&](double t) {
    const ModeState s = r.mode_state(0, t);
    return s.x_dot * s.x_dot + model.omega[0] * model.omega[0] * s.x * s.x;
  };
  const double e1 = energy(2.0), e2 = energy(22.0);
  // The energy of a lightly damped oscillator oscillates by O(zeta) within a period.
  EXPECT_NEAR(std::log(e2 / e1), -2.0 * model.zeta * model.omega[0] * 20.0, 2e-2);
}

}  // namespace test_linear_response
}  // namespace slosh

namespace slosh {
namespace test_linear_response {

TEST(PeakFinder, TheTieRuleDecidesWhichOfTwoEqualPeaksIsFound) {
  // Two equal plateaus, [0.1, 0.3] and [0.7, 0.9], and zero between: the first golden-section
  // probes (0.382, 0.618) are both 0, and only the tie rule picks the side (the band maximum of
  // the spectral strategies drops the lower end, as it always did; the responses' peak finder the
  // upper one).
  auto f = [](double x) { return (x >= 0.1 && x <= 0.3) || (x >= 0.7 && x <= 0.9) ? 1.0 : 0.0; };
  const Peak lower = refine_max(f, 0.0, 1.0, 1e-9, 200, TieRule::kDiscardUpper);
  const Peak upper = refine_max(f, 0.0, 1.0, 1e-9, 200, TieRule::kDiscardLower);
  EXPECT_EQ(lower.value, 1.0);
  EXPECT_EQ(upper.value, 1.0);
  EXPECT_GE(lower.time, 0.1);
  EXPECT_LE(lower.time, 0.3);
  EXPECT_GE(upper.time, 0.7);
  EXPECT_LE(upper.time, 0.9);
  EXPECT_EQ(refine_max(f, 0.0, 1.0, 1e-9, 200).time, lower.time);  // the default rule
}

TEST(PeakFinder, FlatStretchesNeedNoRefinement) {
  int calls = 0;
  const Peak p = find_max(
      [&](double t) {
        ++calls;
        return t < 0.5 ? 1.0 : 1.0 - (t - 0.5);
      },
      0.0, 1.0, 1e-3);
  EXPECT_EQ(p.value, 1.0);
  EXPECT_LE(p.time, 0.5);
  EXPECT_LT(calls, 1100);
  // A narrow peak between samples is still refined to its true top.
  const Peak q = find_max([](double t) { return std::exp(-std::pow((t - 0.5123) / 0.002, 2)); },
                          0.0, 1.0, 1e-3);
  EXPECT_NEAR(q.time, 0.5123, 1e-8);
  EXPECT_NEAR(q.value, 1.0, 1e-14);
}

}  // namespace test_linear_response
}  // namespace slosh

namespace slosh {
namespace test_linear_response {

// The peak search of the linear response (sampled by complex rotation piece by piece, refined
// by Newton's method, the rest window ended by the energy bound) against two independent
// computations on seeded random formats and laws: find_max() over eta(t) on the whole of both
// windows (the plain sampled-and-golden-section search), and fine-step RK4 of the mode
// equations with a parabola through the three nodes around the largest |eta|.

struct RandomCase {
  SloshingModel model;
  MotionLaw law;
  double rest{};
  std::optional<test::TrapezoidAcceleration> trapezoid;  // for the RK4 check
  std::string what;
};

RandomCase random_case(std::mt19937& rng, int k) {
  auto draw = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  Format f = thesis_format();
  f.container.radius = draw(0.03, 0.1);
  f.fill_height = draw(0.4, 2.5) * f.container.radius;
  ModelOptions o;
  o.modes = 1 + k % static_cast<int>(kMaxModes);
  if (k % 3 == 1) {
    o.damping = DampingCorrelation::kExplicit;
    o.explicit_zeta = draw(0.0, 0.3);
  }
  RandomCase c{make_sloshing_model(f, o), {}, draw(0.3, 3.0), std::nullopt, ""};
  const double T = draw(0.5, 1.6), stroke = draw(0.2, 1.0);
  switch (k % 4) {
    case 0:
    case 1: {
      Durations d{};
      double sum = 0.0;
      for (double& x : d) sum += (x = draw(0.02, 1.0));
      for (double& x : d) x *= T / sum;
      const SevenSegmentLaw law(d, stroke);
      c.law = law.law();
      c.trapezoid = test::TrapezoidAcceleration{law.durations(), law.A(), law.B()};
      break;
    }
    case 2:
      c.law = make_cycloidal_law(stroke, T);
      break;
    default:
      c.law = make_modified_trapezoid_law(stroke, T);
      break;
  }
  c.what = "case " + std::to_string(k) + " modes " + std::to_string(o.modes) + " zeta " +
           std::to_string(c.model.zeta) + " T " + std::to_string(T) + " rest " +
           std::to_string(c.rest);
  return c;
}

TEST(LinearResponsePeaks, EqualTheSampledGoldenSectionSearchOnSeededRandomLaws) {
  std::mt19937 rng(20261127);
  for (int k = 0; k < 60; ++k) {
    const RandomCase c = random_case(rng, k);
    const LinearResponse r(c.model, c.law, c.rest);
    const SloshPeaks fast = r.peaks();
    auto abs_eta = [&r](double t) { return std::abs(r.eta(t)); };
    const double w_max = *std::max_element(c.model.omega.begin(), c.model.omega.end());
    const double step = std::min(kMaxPeakStep, 2.0 * std::numbers::pi / w_max / kSamplesPerPeriod);
    const double T = r.motion_time();
    const Peak motion = find_max(abs_eta, 0.0, T, step);
    const Peak rest = find_max(abs_eta, T, T + c.rest, step);
    EXPECT_NEAR(fast.motion.value, motion.value, 1e-9 * motion.value) << c.what;
    EXPECT_NEAR(fast.rest.value, rest.value, 1e-9 * rest.value) << c.what;
    // The times are where |eta| takes those values, inside their windows.
    EXPECT_NEAR(abs_eta(fast.motion.time), fast.motion.value, 1e-12 * fast.motion.value);
    EXPECT_NEAR(abs_eta(fast.rest.time), fast.rest.value, 1e-12 * fast.rest.value);
    EXPECT_GE(fast.motion.time, 0.0);
    EXPECT_LE(fast.motion.time, T);
    EXPECT_GE(fast.rest.time, T);
    EXPECT_LE(fast.rest.time, T + c.rest);
  }
}

/// max |eta| over the RK4 nodes in [a, b], refined by the parabola through the best node and its
/// neighbours (when both lie in the window).
double rk4_window_max(const std::vector<double>& eta, const std::vector<double>& t, double a,
                      double b) {
  std::size_t best = 0;
  double value = -1.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < a || t[i] > b) continue;
    if (std::abs(eta[i]) > value) value = std::abs(eta[best = i]);
  }
  if (best == 0 || best + 1 >= t.size() || t[best - 1] < a || t[best + 1] > b) return value;
  const double y0 = std::abs(eta[best - 1]), y1 = value, y2 = std::abs(eta[best + 1]);
  const double den = y0 - 2.0 * y1 + y2;
  return den < 0.0 ? y1 - 0.125 * (y2 - y0) * (y2 - y0) / den : y1;
}

TEST(LinearResponsePeaks, MatchFineStepRk4OfTheModeEquationsOnSeededRandomSevenSegmentLaws) {
  std::mt19937 rng(7);
  int checked = 0;
  for (int k = 0; checked < 6; ++k) {
    const RandomCase c = random_case(rng, k);
    if (!c.trapezoid) continue;
    ++checked;
    const LinearResponse r(c.model, c.law, c.rest);
    const SloshPeaks fast = r.peaks();
    const double T = r.motion_time();
    const double h = 2e-5;
    std::vector<double> eta, t;
    for (int m = 0; m < c.model.modes(); ++m) {
      const double w = c.model.omega[m], z = c.model.zeta;
      const test::Rk4Trajectory x = test::rk4_solve(
          [&](double time, double pos, double vel) {
            return -(*c.trapezoid)(time)-2.0 * z * w * vel - w * w * pos;
          },
          T + c.rest, h);
      if (eta.empty()) eta.assign(x.x.size(), 0.0), t = x.t;
      for (std::size_t i = 0; i < x.x.size(); ++i) eta[i] += c.model.eta_gain[m] * x.x[i];
    }
    EXPECT_NEAR(fast.motion.value, rk4_window_max(eta, t, 0.0, T), 1e-7 * fast.motion.value)
        << c.what;
    EXPECT_NEAR(fast.rest.value, rk4_window_max(eta, t, T, T + c.rest), 1e-7 * fast.rest.value)
        << c.what;
  }
}

TEST(LinearResponsePeaks, TheRestPeakEndedByTheEnergyBoundIsTheWholeWindowMaximum) {
  // Long rest windows of lightly damped multi-mode responses, where the scan ends long before the
  // window does and the modes beat: the peak must still be the largest |eta| of the whole window,
  // which a dense scan at 0.1 ms (refined by golden section) finds independently.
  std::mt19937 rng(99);
  for (int k = 0; k < 24; ++k) {
    RandomCase c = random_case(rng, 4 * k);  // seven-segment laws, modes 1..5
    const LinearResponse r(c.model, c.law, 4.0);
    const double T = r.motion_time();
    const Peak dense = find_max([&r](double t) { return std::abs(r.eta(t)); }, T, T + 4.0, 1e-4);
    const Peak fast = r.peaks().rest;
    EXPECT_NEAR(fast.value, dense.value, 1e-9 * dense.value) << c.what;
  }
}

}  // namespace test_linear_response
}  // namespace slosh
