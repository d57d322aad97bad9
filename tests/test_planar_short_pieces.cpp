// The planar linear model's exact peaks on very short drive pieces: a path join landing on, or
// within 1e-15..1e-6 s of, a law's breakpoint leaves a piece of that length, and a trajectory
// sampled at 20 kHz is made of 50 us pieces. Both are checked against the straight line's exact
// piecewise closed form (LinearResponse), an independent solution of the same model.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/motion/sampled_trajectory.hpp"
#include "slosh/core/response/planar_response.hpp"
#include "slosh/core/response/response.hpp"
#include "support/fixtures.hpp"

namespace slosh {
namespace test_planar_short_pieces {

// Seeded random strokes, breakpoints and offsets: a straight path of two collinear lines joined
// at s(t_k + d), d = 0 or +-10^U(-15, -6) s, gives the one-line path's linear peaks to 1e-9.
TEST(PlanarShortPieces, JoinsOnAndNearTheLawsBreakpointsGiveTheStraightLine) {
  const SloshingModel model = make_sloshing_model(thesis_format(), {});
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> stroke_of(0.2, 0.8), exponent(-15.0, -6.0);
  for (int trial = 0; trial < 24; ++trial) {
    const double stroke = stroke_of(rng);
    const MotionLaw law = SevenSegmentLaw(test::kAsymmetricDurations, stroke).law();
    const LinearResponse exact(model, law, 1.0);
    const PlanarPeaks line =
        planar_linear_peaks(model, PlanarDrive(PlanarPath::line(stroke), law), 1.0);
    const std::vector<double> steps = law.breakpoints();
    // Inner breakpoints only: a join at s = 0 or s = stroke leaves an empty line.
    const double t_k = steps[1 + rng() % (steps.size() - 2)];
    const int kind = static_cast<int>(rng() % 3);  // on, just before, just after
    const double d = kind == 0 ? 0.0 : (kind == 1 ? -1.0 : 1.0) * std::pow(10.0, exponent(rng));
    const double join = law.at(t_k + d).position;
    const PlanarPath two({PathElement::line(join), PathElement::line(stroke - join)}, 0.0, true);
    const PlanarPeaks cut = planar_linear_peaks(model, PlanarDrive(two, law), 1.0);
    const double motion = exact.peaks().motion.value, rest = exact.peaks().rest.value;
    EXPECT_NEAR(line.motion.value, motion, 1e-9 * motion);
    EXPECT_NEAR(cut.motion.value, motion, 1e-9 * motion)
        << "stroke " << stroke << " t_k " << t_k << " d " << d;
    EXPECT_NEAR(cut.rest.value, rest, 1e-9 * motion)
        << "stroke " << stroke << " t_k " << t_k << " d " << d;
  }
}

// The asymmetric 7-segment law (zero acceleration at both ends, so the natural spline's ends
// fit) sampled at 20 kHz and at 2 kHz: the spline's acceleration errs by ~ h^2 jerk jumps, far
// below 1e-5 of the wave; the peaks are the closed form's on the straight line.
TEST(PlanarShortPieces, ATrajectorySampledAt20kHzIsTheExactLine) {
  const SloshingModel model = make_sloshing_model(thesis_format(), {});
  const double stroke = 0.5;
  const MotionLaw law = SevenSegmentLaw(test::kAsymmetricDurations, stroke).law();
  const LinearResponse exact(model, law, 1.0);
  const double T = law.duration();
  for (int rate : {2000, 20000}) {
    TrajectorySamples s;
    const int n = static_cast<int>(std::lround((T + 1.0) * rate));
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / rate;
      s.t.push_back(t);
      s.x.push_back(law.at(std::min(t, T)).position);
      s.y.push_back(0.0);
    }
    const PlanarDrive drive{SampledTrajectory(s)};
    // The trajectory's motion window is all of it (1 s of rest included): compare the whole.
    const PlanarPeaks p = planar_linear_peaks(model, drive, 0.0);
    const double want = std::max(exact.peaks().motion.value, exact.peaks().rest.value);
    EXPECT_NEAR(p.motion.value, want, 1e-5 * want) << rate << " Hz";
  }
}

}  // namespace test_planar_short_pieces
}  // namespace slosh
