#include "slosh/core/law/cam_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace slosh {

namespace {

std::string seconds(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g s", v);
  return buffer;
}

}  // namespace

std::size_t cam_cycles(double motion_time, double period) {
  if (!(period >= kCamMinPeriod) || !std::isfinite(period)) {
    throw std::invalid_argument("cam table period " + seconds(period) + " is below the minimum " +
                                seconds(kCamMinPeriod));
  }
  const double cycles = std::ceil((motion_time - kCamTimeTolerance) / period);
  if (!(cycles + 1.0 <= static_cast<double>(kCamMaxSamples))) {
    throw std::invalid_argument("a cam table of " + seconds(motion_time) + " every " +
                                seconds(period) + " has more than " +
                                std::to_string(kCamMaxSamples) + " samples");
  }
  return static_cast<std::size_t>(std::max(0.0, cycles));
}

std::vector<CamSample> sample_cam_table(const MotionLaw& law, double stroke, double period) {
  const double T = law.duration();
  const std::size_t cycles = cam_cycles(T, period);
  const std::vector<double> switches = law.breakpoints();
  std::vector<CamSample> table;
  table.reserve(cycles + 1);
  for (std::size_t k = 0; k <= cycles; ++k) {
    const double t = static_cast<double>(k) * period;
    if (t >= T - kCamTimeTolerance) {
      table.push_back({t, stroke, 0.0, 0.0, 0.0});
      continue;
    }
    // On a switch time (up to rounding of k * period), evaluate exactly there: MotionLaw::at is
    // right-continuous, so the jerk is the one of the segment that starts (also at t = 0).
    double t_eval = t;
    // The latest switch time within the tolerance (a plateau shorter than the tolerance is
    // skipped: its successor is what the motion does during the cycle).
    const auto after = std::upper_bound(switches.begin(), switches.end(), t + kCamTimeTolerance);
    if (after != switches.begin() && t - *std::prev(after) <= kCamTimeTolerance) {
      t_eval = *std::prev(after);
    }
    const KinematicState s = law.at(t_eval);
    table.push_back({t, s.position, s.velocity, s.acceleration, s.jerk});
  }
  return table;
}

}  // namespace slosh
