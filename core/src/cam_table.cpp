#include "slosh/core/cam_table.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace slosh {

std::size_t cam_cycles(double motion_time, double period) {
  if (!(period >= kCamMinPeriod) || !std::isfinite(period)) {
    throw std::invalid_argument("cam table period " + std::to_string(period) +
                                " s is below the minimum " + std::to_string(kCamMinPeriod) + " s");
  }
  const double cycles = std::ceil((motion_time - kCamTimeTolerance) / period);
  if (!(cycles + 1.0 <= static_cast<double>(kCamMaxSamples))) {
    throw std::invalid_argument("a cam table of " + std::to_string(motion_time) + " s every " +
                                std::to_string(period) + " s has more than " +
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
    // right-continuous, so the jerk is the one of the segment that starts.
    double t_eval = t;
    const auto next = std::lower_bound(switches.begin(), switches.end(), t);
    if (next != switches.end() && *next - t <= kCamTimeTolerance) t_eval = *next;
    if (next != switches.begin() && t - *std::prev(next) <= kCamTimeTolerance) {
      t_eval = *std::prev(next);
    }
    // At t = 0 the law starts (MotionLaw::at returns the rest state before and at 0).
    const KinematicState s =
        t_eval <= 0.0 && !law.pieces().empty() ? law.pieces().front().at(0.0) : law.at(t_eval);
    table.push_back({t, s.position, s.velocity, s.acceleration, s.jerk});
  }
  return table;
}

}  // namespace slosh
