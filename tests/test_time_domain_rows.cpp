// time_domain's starting samples cover the motion and only the first period of mode 1 of the
// rest window (the energy argument of docs/models.md: no maximum of |eta| after the first
// turning point past T exceeds it), while its constraint is eta_rest <= eta_rest_max over the
// whole window. A seeded property test over random formats, rest windows of 1-3 s and half of
// them with a limit on the peak acceleration: every plan that says its limits are met meets
// eta_rest over the whole window on an independent RK4 of eq. 2.35 (re-typed from SPEC §2, a
// tenth of the planner's step), reports the eta the reference finds, and keeps the limit; a plan
// that says infeasible breaks the bound on the reference. SLOSH_PROPERTY_FORMATS=N runs N
// formats instead of 10.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/random_format.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_time_domain_rows {

constexpr int kDefaultFormats{10};
constexpr std::uint32_t kSeed{3013};
/// Relative excess over eta_rest_max the planner's verification tolerates (its dense check's
/// 1e-7) plus the reference's own error [-].
constexpr double kBoundSlack{1e-6};

struct Case {
  Format format;
  PlanOptions options;
};

std::string name_of(const Case& c) {
  char buf[240];
  std::snprintf(buf, sizeof buf,
                "R %.6g mm, h %.6g mm, s %.6g mm, T %.10g s, rest %.4g s, a_max %.6g",
                c.format.container.radius * 1e3, c.format.fill_height * 1e3, c.format.stroke * 1e3,
                c.format.motion_time, c.options.rest_time, c.options.limits.a_max.value_or(0.0));
  return buf;
}

TEST(TimeDomainRows, PlansMeetEtaRestOverTheWholeRestWindowOverRandomFormats) {
  std::mt19937 rng(kSeed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int count = test::property_format_count(kDefaultFormats);
  int met = 0;
  for (int k = 0; k < count; ++k) {
    Case cs;
    cs.format = test::random_format(rng);
    cs.options.robustness = false;
    cs.options.rest_time = 1.0 + 2.0 * u(rng);
    const double uniform_a =
        49.0 / 12.0 * cs.format.stroke / (cs.format.motion_time * cs.format.motion_time);
    const double a_factor = 1.0 + 0.5 * u(rng);
    if (k % 2 == 1) cs.options.limits.a_max = uniform_a * a_factor;
    SCOPED_TRACE(name_of(cs));
    const PlanResult r = plan(cs.format, Strategy::kTimeDomain, cs.options);
    ASSERT_TRUE(r.durations.has_value()) << r.message;

    // The reference: eq. 2.35 by RK4 at 1/4000 of a period (its steps cross the kinks of the
    // acceleration, where RK4 errs by (w h)^3), the peaks refined by a parabola through the best
    // sample and its neighbours.
    const SloshingModel& m = r.model;
    const SevenSegmentLaw law(*r.durations, cs.format.stroke);
    const test::TrapezoidAcceleration acc{*r.durations, law.A(), law.B()};
    const double T = cs.format.motion_time;
    const double rest = cs.options.rest_time;
    const double step = 2.0 * std::numbers::pi / m.omega1() / 4000.0;
    const test::Rk4Trajectory ref = test::rk4_solve(
        [&](double t, double x, double v) {
          return test::eq235_xbar_dd(m.omega[0], m.zeta, m.C, m.alpha, m.radius, x, v, acc(t));
        },
        T + rest, step);
    const double ref_motion = test::parabola_peak(ref, m.K, 0.0, T);
    const double ref_rest = test::parabola_peak(ref, m.K, T, T + rest);
    const double bound = cs.options.eta_rest_max;
    if (r.status == SolveStatus::kOptimal || r.status == SolveStatus::kAcceptable) {
      ++met;
      EXPECT_LE(ref_rest, bound * (1.0 + kBoundSlack));
      EXPECT_NEAR(r.prediction.nonlinear.rest.value, ref_rest, 1e-6 * ref_motion);
      EXPECT_NEAR(r.prediction.nonlinear.motion.value, ref_motion, 1e-6 * ref_motion);
      if (cs.options.limits.a_max) {
        EXPECT_LE(std::max(law.A(), law.B()), *cs.options.limits.a_max * (1.0 + 1e-9));
      }
    } else if (r.status == SolveStatus::kInfeasible) {
      EXPECT_GT(ref_rest, bound * (1.0 - kBoundSlack)) << r.message;
    }
  }
  // The campaign exercises plans that meet the bound, not only unreachable ones.
  EXPECT_GT(met, count / 2);
}

}  // namespace test_time_domain_rows
}  // namespace slosh
