#include "slosh/core/law/cam_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>

#include "text.hpp"

namespace slosh {

namespace {

std::string seconds(double v) {
  return detail::significant(v, 6) + " s";
}

// The state of `law` (duration T, switch times `switches`) at a sample time t in [0, T): on a
// switch time (up to rounding of the sample time), evaluated exactly there; MotionLaw::at is
// right-continuous, so the jerk is the one of the segment that starts (also at t = 0).
KinematicState state_at_sample(const MotionLaw& law, const std::vector<double>& switches,
                               double t) {
  double t_eval = t;
  // The latest switch time within the tolerance (a plateau shorter than the tolerance is
  // skipped: its successor is what the motion does during the cycle).
  const auto after = std::upper_bound(switches.begin(), switches.end(), t + kCamTimeTolerance);
  if (after != switches.begin() && t - *std::prev(after) <= kCamTimeTolerance) {
    t_eval = *std::prev(after);
  }
  return law.at(t_eval);
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
    const KinematicState s = state_at_sample(law, switches, t);
    table.push_back({t, s.position, s.velocity, s.acceleration, s.jerk});
  }
  return table;
}

namespace {

// 10 significant digits (the API's number_text).
std::string master_number(double v) {
  return detail::significant(v, 10);
}

std::string_view master_input_name(MasterAxisInput input) {
  switch (input) {
    case MasterAxisInput::kPeriod:
      return "master period";
    case MasterAxisInput::kStart:
      return "master start";
    case MasterAxisInput::kEnd:
      return "master end";
    case MasterAxisInput::kStep:
      break;
  }
  return "master step";
}

MasterAxisRefusal master_refusal(MasterAxisInput input, double value, const InputBounds& bounds) {
  MasterAxisRefusal r{input, value, bounds, false, {}};
  const bool interval = std::isfinite(bounds.lo) && std::isfinite(bounds.hi);
  r.message = std::string(master_input_name(input)) + " = " + master_number(value) +
              " must be finite and " + (interval ? "in " : "") + r.allowed() + " (master units)";
  return r;
}

// A grid point within the tolerance of `x`.
bool near_grid(double grid_point, double x, double step) {
  return std::abs(grid_point - x) <= kMasterGridTolerance * step;
}

}  // namespace

std::string MasterAxisRefusal::allowed() const {
  return bounds_text(bounds, master_number);
}

std::optional<MasterAxisRefusal> check_master_axis(const MasterAxis& axis, std::size_t max_rows) {
  if (!positive().contains(axis.period)) {
    return master_refusal(MasterAxisInput::kPeriod, axis.period, positive());
  }
  const InputBounds start{0.0, axis.period, false, true};
  if (!start.contains(axis.start))
    return master_refusal(MasterAxisInput::kStart, axis.start, start);
  const InputBounds end{axis.start, axis.period, true, false};
  if (!end.contains(axis.end)) return master_refusal(MasterAxisInput::kEnd, axis.end, end);
  // A shorter motion span makes the derivatives per master unit (v / w, a / w^2, j / w^3)
  // overflow to inf (hostile review: a period of 1e-300 gave nan and inf cells).
  if (axis.end - axis.start < kMinMasterSpan) {
    return master_refusal(MasterAxisInput::kEnd, axis.end,
                          InputBounds{axis.start + kMinMasterSpan, axis.period, false, false});
  }
  if (!positive().contains(axis.step)) {
    return master_refusal(MasterAxisInput::kStep, axis.step, positive());
  }
  // ceil(period / step) grid points below the period, plus start, end and period.
  const double grid_rows = static_cast<double>(max_rows - std::min(max_rows, kMasterExtraRows));
  if (!(axis.period / axis.step <= grid_rows)) {
    const InputBounds rows{axis.period / grid_rows, std::numeric_limits<double>::infinity(), false,
                           false};
    MasterAxisRefusal r{MasterAxisInput::kStep, axis.step, rows, true, {}};
    r.message = "master step = " + master_number(axis.step) + " gives more than " +
                std::to_string(max_rows) + " rows over the master period " +
                master_number(axis.period) + ": it must be " + r.allowed() + " (master units)";
    return r;
  }
  return std::nullopt;
}

std::vector<double> master_positions(const MasterAxis& axis) {
  if (const auto refusal = check_master_axis(axis)) {
    throw std::invalid_argument(refusal->message);
  }
  // The anchors, increasing and distinct (start < end <= period).
  std::vector<double> anchors{axis.start, axis.end};
  if (axis.period > axis.end) anchors.push_back(axis.period);
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(axis.period / axis.step) + kMasterExtraRows + 1);
  const auto push = [&out](double x) {
    if (out.empty() || out.back() < x) out.push_back(x);
  };
  std::size_t next = 0;  // the first anchor not yet written
  for (std::size_t k = 0; next < anchors.size(); ++k) {
    const double x = static_cast<double>(k) * axis.step;
    // Anchors before this grid point (off the grid) come first.
    while (next < anchors.size() && anchors[next] < x && !near_grid(x, anchors[next], axis.step)) {
      push(anchors[next++]);
    }
    if (next == anchors.size()) break;
    if (near_grid(x, anchors[next], axis.step)) {
      push(anchors[next++]);  // the grid point is the anchor itself
    } else {
      push(x);
    }
  }
  return out;
}

bool on_master_grid(double x, double step) {
  return near_grid(std::round(x / step) * step, x, step);
}

bool master_grid_is_equidistant(const MasterAxis& axis) {
  return on_master_grid(axis.start, axis.step) && on_master_grid(axis.end, axis.step) &&
         on_master_grid(axis.period, axis.step);
}

std::vector<MasterCamSample> sample_master_cam_table(const MotionLaw& law, double stroke,
                                                     const MasterAxis& axis) {
  const double T = law.duration();
  if (!(T > 0.0) || !std::isfinite(T)) {
    throw std::invalid_argument("a master-axis cam table needs a law of positive duration, not " +
                                seconds(T));
  }
  const std::vector<double> thetas = master_positions(axis);
  const std::vector<double> switches = law.breakpoints();
  const double speed = (axis.end - axis.start) / T;  // master units per second
  std::vector<MasterCamSample> table;
  table.reserve(thetas.size());
  for (const double theta : thetas) {
    if (theta < axis.start) {
      table.push_back({theta, 0.0, 0.0, 0.0, 0.0});
      continue;
    }
    const double t = (theta - axis.start) / speed;
    if (theta >= axis.end || t >= T - kCamTimeTolerance) {
      table.push_back({theta, stroke, 0.0, 0.0, 0.0});
      continue;
    }
    const KinematicState s = state_at_sample(law, switches, t);
    table.push_back({theta, s.position, s.velocity / speed, s.acceleration / (speed * speed),
                     s.jerk / (speed * speed * speed)});
  }
  return table;
}

}  // namespace slosh
