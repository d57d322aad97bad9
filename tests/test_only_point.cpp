// When the lower bounds fill the motion time (T = 4 min_ramp without plateau minimums, where a
// min-time search without machine limits starts) the durations have one admissible point: every
// optimising spectral strategy returns it with one evaluation per solve (there is nothing to
// search), and its verdict is that point's, checked here on the closed-form spectrum.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh {
namespace test_only_point {

/// Largest |X| over [(1 - band) w1, (1 + band) w1] on 4001 points (a reference for the
/// min_jerk_band verdict; the planner refines its maxima, this grid only brackets them).
double band_max(const Durations& d, double stroke, double w1, double band) {
  double best = 0.0;
  for (int k = 0; k <= 4000; ++k) {
    const double w = (1.0 - band) * w1 + 2.0 * band * w1 * k / 4000.0;
    best = std::max(best, std::abs(seven_segment_spectrum(d, stroke, w)));
  }
  return best;
}

TEST(OnlyPoint, LowerBoundsThatFillTheMotionTimeAreSolvedWithoutASearch) {
  Format f = thesis_format();
  PlanOptions o;
  o.robustness = false;
  f.motion_time = 4.0 * o.min_ramp;
  const Durations only{o.min_ramp, 0.0, o.min_ramp, 0.0, o.min_ramp, 0.0, o.min_ramp};
  const SloshingModel model = make_sloshing_model(f, o.model);
  const double w1 = model.omega1();
  for (const Strategy s : {Strategy::kNotch, Strategy::kMultiNotch, Strategy::kMinJerkBand}) {
    SCOPED_TRACE(to_string(s));
    const PlanResult r = plan(f, s, o);
    ASSERT_TRUE(r.durations.has_value()) << r.message;
    for (std::size_t i = 0; i < kSegments; ++i) EXPECT_EQ((*r.durations)[i], only[i]);
    // One evaluation per solve: the starts are that point, nothing is searched (the solvers
    // spent 14-54 starts and 170-700 evaluations here).
    EXPECT_GE(r.solver.starts, 1);
    EXPECT_LE(r.solver.iterations, r.solver.starts);
    if (s == Strategy::kMinJerkBand) {
      // |X| <= tol_rel X_ref on the band, X_ref the uniform law's band maximum.
      const double x_ref = band_max(uniform_durations(f.motion_time), f.stroke, w1, o.band);
      const bool meets = band_max(only, f.stroke, w1, o.band) <= o.tol_rel * x_ref;
      EXPECT_EQ(r.status == SolveStatus::kInfeasible, !meets) << r.message;
    } else {
      // Unconstrained but for the bounds (notch falls back to the deepest notch): usable.
      EXPECT_TRUE(r.status == SolveStatus::kOptimal || r.status == SolveStatus::kAcceptable)
          << r.message;
    }
  }
}

}  // namespace test_only_point
}  // namespace slosh
