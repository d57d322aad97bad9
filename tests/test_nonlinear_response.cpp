// The nonlinear fundamental-mode model (thesis eq. 2.35): its small-amplitude limit is the
// one-mode linear model, and its integration error is checked against an independent fine RK4.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/response/response.hpp"
#include "support/fixtures.hpp"
#include "support/random_format.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_nonlinear_response {

constexpr double kXi1 = 1.841184;

TEST(NonlinearResponse, TinyExcitationReducesToTheOneModeLinearModel) {
  ModelOptions options;
  options.modes = 1;
  const SloshingModel model = make_sloshing_model(thesis_format(), options);
  const SevenSegmentLaw law(test::kAsymmetricDurations, 1e-6);  // a micrometre stroke: x / R ~ 1e-6
  const LinearResponse linear(model, law.law(), 1.0);
  const NonlinearResponse nonlinear(model, law.law(), 1.0);
  const double x_scale = linear.peaks().motion.value / model.eta_gain[0];
  for (int i = 1; i < 400; ++i) {
    const double t = 0.005 * i + 1.3e-4;  // off the integration grid: exercises dense output
    const double x1 = linear.mode_state(0, t).x;
    EXPECT_NEAR(nonlinear.state(t).x * model.radius, x1, 1e-5 * x_scale) << t;
  }
  // Same x_1, different height formulas: eta_nl / eta_lin = K / (R eta_gain_1) = xi_1^2 / 4.
  const SloshPeaks pl = linear.peaks(), pn = nonlinear.peaks();
  EXPECT_NEAR(pn.motion.value / pl.motion.value, kXi1 * kXi1 / 4.0, 1e-4);
  EXPECT_NEAR(pn.rest.value / pl.rest.value, kXi1 * kXi1 / 4.0, 1e-4);
  EXPECT_NEAR(pn.motion.time, pl.motion.time, 1e-3);
}

// eq. 2.35 re-typed from SPEC §2 (tests/support), with this model's parameters.
double reference_xbar_dd(const SloshingModel& m, double x, double v, double a) {
  return test::eq235_xbar_dd(m.omega[0], m.zeta, m.C, m.alpha, m.radius, x, v, a);
}

void expect_accurate(const Format& format, const MotionLaw& law, double rest) {
  const SloshingModel model = make_sloshing_model(format, {});
  const NonlinearResponse response(model, law, rest);
  const double h = 5e-6;
  const test::Rk4Trajectory ref = test::rk4_solve(
      [&](double t, double x, double v) {
        return reference_xbar_dd(model, x, v, law.at(t).acceleration);
      },
      law.duration() + rest, h);
  double worst = 0.0, peak = 0.0;
  for (std::size_t i = 0; i < ref.t.size(); i += 37) {
    const double eta_ref = model.K * ref.x[i];
    worst = std::max(worst, std::abs(response.eta(ref.t[i]) - eta_ref));
    peak = std::max(peak, std::abs(eta_ref));
  }
  // SPEC: error on eta below 0.1 % of the peak; the integrator does two orders better.
  EXPECT_LT(worst, 1e-5 * peak) << law.name();
  EXPECT_GT(peak, 5e-3) << law.name();
  const SloshPeaks p = response.peaks();
  EXPECT_NEAR(std::max(p.motion.value, p.rest.value), peak, 1e-5 * peak);
}

TEST(NonlinearResponse, MatchesAFineIndependentRk4OnTheThesisFormat) {
  expect_accurate(thesis_format(), SevenSegmentLaw(uniform_durations(1.0), 0.8).law(), 1.0);
  expect_accurate(thesis_format(), SevenSegmentLaw(test::kAsymmetricDurations, 0.8).law(), 1.0);
}

TEST(NonlinearResponse, MatchesAFineIndependentRk4OnHarshLaws) {
  // 0.8 m in 0.6 s: peak accelerations above 10 m/s^2, strongly nonlinear sloshing.
  Durations fast = uniform_durations(0.6);
  expect_accurate(thesis_format(), SevenSegmentLaw(fast, 0.8).law(), 1.0);
  expect_accurate(thesis_format(), make_modified_trapezoid_law(0.8, 0.7), 0.5);
  expect_accurate(thesis_format(), make_poly5_law(0.5, 0.7), 0.5);
}

TEST(NonlinearResponse, DenseOutputIsContinuousAndSmooth) {
  const SloshingModel model = make_sloshing_model(thesis_format(), {});
  const NonlinearResponse r(model, SevenSegmentLaw(test::kAsymmetricDurations, 0.8).law(), 1.0);
  // Rate of the dense output agrees with the derivative of its position.
  for (double t : {0.1234, 0.5001, 0.987, 1.4321}) {
    const double d = 1e-6;
    const double fd = (r.state(t + d).x - r.state(t - d).x) / (2 * d);
    EXPECT_NEAR(r.state(t).x_dot, fd, 1e-5 * (1.0 + std::abs(fd))) << t;
  }
  EXPECT_EQ(r.eta(0.0), 0.0);
}

TEST(NonlinearResponse, RightHandSideIsEq235) {
  const SloshingModel model = make_sloshing_model(thesis_format(), {});
  for (double x : {-0.3, 0.0, 0.2}) {
    for (double v : {-2.0, 0.5}) {
      for (double a : {-7.0, 3.0}) {
        EXPECT_NEAR(nonlinear_acceleration(model, x, v, a), reference_xbar_dd(model, x, v, a),
                    1e-12 * (1.0 + std::abs(reference_xbar_dd(model, x, v, a))));
      }
    }
  }
}

}  // namespace test_nonlinear_response
}  // namespace slosh

namespace slosh {
namespace test_nonlinear_response {

// A seven-segment law of random admissible durations summing to T (ramps >= 50 ms).
MotionLaw random_seven_segment(std::mt19937& rng, double stroke, double T) {
  std::uniform_real_distribution<double> u(0.2, 1.0);
  Durations w{};
  double total = 0.0;
  for (double& wi : w) total += (wi = u(rng));
  Durations d{};
  const double room = T - 4.0 * 0.05;
  for (std::size_t i = 0; i < kSegments; ++i) {
    d[i] = (i % 2 == 0 ? 0.05 : 0.0) + room * w[i] / total;
  }
  return SevenSegmentLaw(d, stroke).law();
}

// x of a fine reference trajectory at t in step i (cubic Hermite from x and x' at its ends:
// error ~ (omega h)^4, far below the bar at h = 20 us).
double reference_x(const test::Rk4Trajectory& r, std::size_t i, double t) {
  const double h = r.t[i + 1] - r.t[i];
  const double s = (t - r.t[i]) / h;
  const double u = 1.0 - s;
  return (1.0 + 2.0 * s) * u * u * r.x[i] + s * u * u * h * r.v[i] +
         s * s * (3.0 - 2.0 * s) * r.x[i + 1] - s * s * u * h * r.v[i + 1];
}

// Largest |K x| of a fine reference trajectory over [a, b]: the window's ends and every turning
// point inside (a sign change of x' between two samples, located by linear interpolation of x').
double reference_peak(const test::Rk4Trajectory& r, double K, double a, double b) {
  const double h = r.t[1] - r.t[0];
  const std::size_t last = r.t.size() - 2;
  auto step_of = [&](double t) { return std::min(last, static_cast<std::size_t>(t / h)); };
  double best =
      std::max(std::abs(reference_x(r, step_of(a), a)), std::abs(reference_x(r, step_of(b), b)));
  for (std::size_t i = step_of(a); i <= step_of(b); ++i) {
    const double v0 = r.v[i], v1 = r.v[i + 1];
    if ((v0 < 0.0) == (v1 < 0.0)) continue;
    const double t = std::clamp(r.t[i] + h * v0 / (v0 - v1), a, b);
    best = std::max(best, std::abs(reference_x(r, step_of(t), t)));
  }
  return K * best;
}

// Both peaks of the response against a fine RK4 (20 us steps) on seeded random formats and laws,
// each within 1e-6 of its own value.
TEST(NonlinearResponse, PeaksMatchAFineRk4OnRandomFormatsWithinOnePpm) {
  std::mt19937 rng(20261126u);
  for (int k = 0; k < 24; ++k) {
    const Format f = test::random_format(rng);
    const MotionLaw law = random_seven_segment(rng, f.stroke, f.motion_time);
    const SloshingModel model = make_sloshing_model(f, {});
    const double rest = 1.0;
    const test::Rk4Trajectory ref = test::rk4_solve(
        [&](double t, double x, double v) {
          return reference_xbar_dd(model, x, v, law.at(t).acceleration);
        },
        law.duration() + rest, 2e-5);
    const double T = law.duration();
    const double ref_motion = reference_peak(ref, model.K, 0.0, T);
    const double ref_rest = reference_peak(ref, model.K, T, T + rest);
    const SloshPeaks p = NonlinearResponse(model, law, rest).peaks();
    const SloshPeaks q = nonlinear_peaks(model, law, rest);
    EXPECT_NEAR(p.motion.value, ref_motion, 1e-6 * ref_motion) << "format " << k;
    EXPECT_NEAR(p.rest.value, ref_rest, 1e-6 * ref_rest) << "format " << k;
    EXPECT_NEAR(q.rest.value, ref_rest, 1e-6 * ref_rest) << "format " << k;
  }
}

// The rest window's search ends by the energy bound (docs/models.md): the eta_rest it finds is
// the maximum over the whole window, here searched densely on the kept trajectory (0.5 ms
// samples, golden-section refinement), also for rest windows of several seconds.
// The rest of the rest window is integrated on the first read of the trajectory; reads from
// several threads at once, through the response and through a copy made before any read, all see
// the trajectory of a response read alone.
TEST(NonlinearResponse, TheTrajectoryCompletedOnFirstReadIsTheSameFromEveryThreadAndCopy) {
  const SloshingModel model = make_sloshing_model(thesis_format(), {});
  const MotionLaw law = SevenSegmentLaw(test::kAsymmetricDurations, 0.8).law();
  const NonlinearResponse alone(model, law, 1.5);
  std::vector<double> times, expected;
  for (int i = 0; i <= 260; ++i) times.push_back(0.01 * i);
  for (double t : times) expected.push_back(alone.eta(t));
  const NonlinearResponse shared(model, law, 1.5);
  const NonlinearResponse copy = shared;  // NOLINT(performance-unnecessary-copy-initialization)
  std::vector<std::vector<double>> seen(4);
  std::vector<std::thread> threads;
  for (std::size_t k = 0; k < seen.size(); ++k) {
    threads.emplace_back([&, k] {
      const NonlinearResponse& r = k % 2 == 0 ? shared : copy;
      for (double t : times) seen[k].push_back(r.eta(t));
    });
  }
  for (std::thread& t : threads) t.join();
  for (const std::vector<double>& s : seen) EXPECT_EQ(s, expected);
  EXPECT_EQ(shared.steps(), alone.steps());
  EXPECT_EQ(copy.steps(), alone.steps());
}

TEST(NonlinearResponse, EarlyStoppedRestPeakIsTheWholeWindowMaximum) {
  std::mt19937 rng(7u);
  for (int k = 0; k < 16; ++k) {
    const Format f = test::random_format(rng);
    const MotionLaw law = random_seven_segment(rng, f.stroke, f.motion_time);
    const SloshingModel model = make_sloshing_model(f, {});
    const double rest = k % 2 == 0 ? 1.0 : 4.5;
    const NonlinearResponse full(model, law, rest);
    const double T = law.duration();
    const Peak whole = find_max([&](double t) { return std::abs(full.eta(t)); }, T, T + rest, 5e-4);
    const SloshPeaks early = nonlinear_peaks(model, law, rest);
    EXPECT_NEAR(early.rest.value, whole.value, 1e-9 * whole.value) << "format " << k;
    EXPECT_EQ(early.rest.value, full.peaks().rest.value);
    EXPECT_EQ(early.motion.value, full.peaks().motion.value);
  }
}

}  // namespace test_nonlinear_response
}  // namespace slosh
