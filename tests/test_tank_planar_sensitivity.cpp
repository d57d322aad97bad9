// The tank's sensitivity integrator (what time_domain optimises along a path for a rectangular
// tank): its heights against the verification's RectangularPlanarResponse, and its gradients
// against Richardson-extrapolated central differences of that response (integrated finely, so
// its own discretisation stays far below the differences), on turning and fixed tanks.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "response/tank_planar_sensitivity.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/response/rectangular_planar.hpp"
#include "slosh/core/strategy/rectangular_path_plan.hpp"
#include "support/sanitizers.hpp"

namespace slosh {
namespace test_tank_planar_sensitivity {

struct TankCase {
  PlanarPath path;
  RectangularTank tank;
  double fill;
  RectangularPlanarModel which;
  int modes{3};  // the pass's state is sized to at most 3 modes or to 5
};

/// The verification's response of the law d, integrated at 160 steps per period.
RectangularPlanarResponse fine_response(const TankCase& c, const RectangularModel& m,
                                        const Durations& d, double rest) {
  PlanarOptions o;
  o.steps_per_period = 160.0;
  o.max_step = 0.005;
  const PlanarDrive drive(c.path, SevenSegmentLaw(d, c.path.length()).law());
  return RectangularPlanarResponse(m, drive, tank_frame_angle(c.path, c.tank.orientation_deg), rest,
                                   c.which, o);
}

// A turning tank on a table (the liquid's spin included), a tank keeping its orientation on a
// line-arc-line track, the nonlinear and the linear model; perturbed laws; times in the motion
// and the rest window away from the kinks of the absolute values.
TEST(TankPlanarSensitivity, HeightsAndGradientsMatchTheVerificationsResponse) {
  SLOSH_SKIP_WHEN_SANITIZED(
      "dense dual-number checks of a tank along a path (200 s there, 4 s in release)");
  const double rest = 1.0;
  const std::vector<TankCase> cases = {
      {PlanarPath::arc(0.3, std::numbers::pi / 2, true),
       {0.1, 0.08, 0.0},
       0.05,
       RectangularPlanarModel::kNonlinear},
      {PlanarPath({PathElement::line(0.15), PathElement::arc(0.2, 1.2), PathElement::line(0.1)},
                  0.4, false),
       {0.12, 0.08, 30.0},
       0.05,
       RectangularPlanarModel::kNonlinear},
      {PlanarPath::arc(0.25, -2.0, true), {0.12, 0.1, 60.0}, 0.04, RectangularPlanarModel::kLinear},
      {PlanarPath::arc(0.3, std::numbers::pi / 2, true),
       {0.1, 0.08, 20.0},
       0.05,
       RectangularPlanarModel::kNonlinear,
       5},
  };
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t n = 0; n < cases.size(); ++n) {
    const TankCase& c = cases[n];
    Format f = thesis_format();
    RectangularModelOptions options;
    options.modes = c.modes;
    const RectangularModel m = make_rectangular_model(c.tank, c.fill, f.fluid, options);
    Durations d = uniform_durations(1.3);
    for (double& x : d) x *= 0.8 + 0.4 * u(rng);
    detail::TankPlanarSensitivity sens(m, c.path, tank_frame_angle(c.path, c.tank.orientation_deg),
                                       rest, c.which, 40.0);
    sens.freeze_steps(d.data());
    sens.compute(d.data());
    const RectangularPlanarResponse ref = fine_response(c, m, d, rest);
    std::vector<double> times;
    while (times.size() < 6) {
      const double t = (0.05 + 0.9 * u(rng)) * (sens.motion_time() + rest);
      const double smallest = std::min(
          {std::abs(ref.eta_length(t)), std::abs(ref.eta_width(t)), std::abs(ref.eta_even(t))});
      if (c.which == RectangularPlanarModel::kLinear || smallest > 1e-2 * ref.eta_highest(t)) {
        if (std::abs(ref.eta_length(t)) > 1e-2 * ref.eta_highest(t) &&
            std::abs(ref.eta_width(t)) > 1e-2 * ref.eta_highest(t)) {
          times.push_back(t);
        }
      }
    }
    std::vector<double> values;
    std::vector<std::array<double, kSegments>> gradients;
    sens.eta_at(times, values, gradients);
    for (std::size_t k = 0; k < times.size(); ++k) {
      EXPECT_NEAR(values[k] / ref.eta_highest(times[k]), 1.0, 1e-6) << n << " t " << times[k];
      EXPECT_NEAR(sens.eta_highest(times[k]), values[k], 1e-12) << n;
    }
    // Richardson: (4 D(h / 2) - D(h)) / 3 of the central differences D of the fine response.
    const double h = 2e-4;
    for (std::size_t i = 0; i < kSegments; ++i) {
      auto central = [&](double step, double t) {
        Durations up = d, down = d;
        up[i] += step;
        down[i] -= step;
        return (fine_response(c, m, up, rest).eta_highest(t) -
                fine_response(c, m, down, rest).eta_highest(t)) /
               (2.0 * step);
      };
      for (std::size_t k = 0; k < times.size(); ++k) {
        const double coarse = central(h, times[k]), fine = central(h / 2, times[k]);
        const double want = (4.0 * fine - coarse) / 3.0;
        EXPECT_NEAR(gradients[k][i], want, 2e-4 * std::abs(want) + 1e-7)
            << "case " << n << " d" << i << " t " << times[k];
      }
    }
  }
}

// A following row: peak_time over a span is the largest height the dense output gives there
// (located as the verification locates its peaks), and every window peak is one.
TEST(TankPlanarSensitivity, PeakTimesAreTheLargestHeightsOfTheirSpan) {
  const PlanarPath path = PlanarPath::arc(0.3, std::numbers::pi / 2, true);
  const RectangularModel m = make_rectangular_model({0.1, 0.08, 0.0}, 0.05, thesis_format().fluid);
  const double rest = 1.0;
  const Durations d = uniform_durations(1.4);
  detail::TankPlanarSensitivity sens(m, path, tank_frame_angle(path, 0.0), rest,
                                     RectangularPlanarModel::kNonlinear, 12.0);
  sens.compute(d.data());
  const double T = sens.motion_time();
  const double window = 0.1;
  const std::vector<detail::PlanarWindowPeak> peaks = sens.window_peaks(0.0, T + rest, window);
  ASSERT_EQ(peaks.size(), static_cast<std::size_t>(std::ceil((T + rest) / window - 1e-9)));
  for (std::size_t w = 0; w < peaks.size(); ++w) {
    const double lo = static_cast<double>(w) * window;
    const double hi = std::min(lo + window, T + rest);
    double sampled = 0.0;
    for (int i = 0; i <= 2000; ++i)
      sampled = std::max(sampled, sens.eta_highest(lo + (hi - lo) * i / 2000.0));
    EXPECT_GE(peaks[w].value, sampled * (1.0 - 1e-9)) << w;
    EXPECT_NEAR(sens.eta_highest(peaks[w].time), peaks[w].value, 1e-15) << w;
    EXPECT_EQ(sens.peak_time(lo, hi), peaks[w].time) << w;
  }
}

}  // namespace test_tank_planar_sensitivity
}  // namespace slosh
