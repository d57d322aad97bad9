// The nonlinear fundamental-mode model (thesis eq. 2.35): its small-amplitude limit is the
// one-mode linear model, and its integration error is checked against an independent fine RK4.

#include <gtest/gtest.h>

#include <cmath>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/response/response.hpp"
#include "support/fixtures.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace {

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

// eq. 2.35 re-typed from SPEC §2.
double reference_xbar_dd(const SloshingModel& m, double x, double v, double a) {
  const double w = m.omega[0], z = m.zeta, C = m.C, alpha = m.alpha;
  return -(2.0 * w * z * (v + C * C * x * x * v) + C * C * x * v * v +
           w * w * x * (1.0 + alpha * x * x) + a / m.radius) /
         (1.0 + C * C * x * x);
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

TEST(NonlinearResponse, HermiteDenseOutputIsContinuousAndSmooth) {
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

}  // namespace
}  // namespace slosh
