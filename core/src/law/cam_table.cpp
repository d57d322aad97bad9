#include "slosh/core/law/cam_table.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

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

// The decimal step of `period`: m / 10^p with the fewest places p (<= 9) that give the period
// back, so that sample k's time k m / 10^p is the double nearest that decimal (0.009 s, not
// 9 x 0.001 = 0.009000000000000001, which a controller's import or a diff trips on); nullopt
// when the period is no such decimal (then k x period).
struct DecimalStep {
  double units{};  // m
  double scale{};  // 10^p
};
std::optional<DecimalStep> decimal_step(double period) {
  double scale = 1.0;
  for (int places = 0; places <= 9; ++places, scale *= 10.0) {
    const double units = std::round(period * scale);
    if (units >= 1.0 && units < 9.0e15 && units / scale == period) return DecimalStep{units, scale};
  }
  return std::nullopt;
}

double sample_time(std::size_t k, double period, const std::optional<DecimalStep>& step) {
  const auto kd = static_cast<double>(k);
  return step ? kd * step->units / step->scale : kd * period;
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
  const std::optional<DecimalStep> step = decimal_step(period);
  for (std::size_t k = 0; k <= cycles; ++k) {
    const double t = sample_time(k, period, step);
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

// The refusal of `value` outside `bounds`, its digits set so that the value reads differently
// from the bounds.
MasterAxisRefusal master_refusal(MasterAxisInput input, double value, const InputBounds& bounds) {
  MasterAxisRefusal r{input, value, bounds, false, std::nullopt, 10, {}};
  r.digits = bounds_digits(value, bounds);
  const bool interval = std::isfinite(bounds.lo) && std::isfinite(bounds.hi);
  r.message = std::string(master_input_name(input)) + " = " + r.value_text() +
              " must be finite and " + (interval ? "in " : "") + r.allowed() + " (master units)";
  return r;
}

// A grid point within the tolerance of `x`.
bool near_grid(double grid_point, double x, double step) {
  return std::abs(grid_point - x) <= kMasterGridTolerance * step;
}

// The largest start whose end can lie kMinMasterSpan after it and still within the period
// (period >= kMinMasterSpan): start + kMinMasterSpan <= period, start < period.
double latest_start(double period) {
  double start = period - kMinMasterSpan;
  while (start > 0.0 && start + kMinMasterSpan > period) {
    start = std::nextafter(start, 0.0);
  }
  return start < period ? start : std::nextafter(period, 0.0);
}

// The refusal of the start or the end of an axis whose period is valid; nullopt when both are
// in range. Each allowed set is the plain one ("[0, 360)", "(30, 360]") unless the value lies
// in it and only the shortest span refuses it: then the tighter set, which is never empty.
std::optional<MasterAxisRefusal> check_start_and_end(const MasterAxis& axis) {
  const InputBounds start{0.0, axis.period, false, true};
  if (!start.contains(axis.start)) {
    return master_refusal(MasterAxisInput::kStart, axis.start, start);
  }
  const double last = latest_start(axis.period);
  if (axis.start > last) {
    return master_refusal(MasterAxisInput::kStart, axis.start, closed_range(0.0, last));
  }
  const InputBounds end{axis.start, axis.period, true, false};
  if (!end.contains(axis.end)) return master_refusal(MasterAxisInput::kEnd, axis.end, end);
  // A shorter motion span makes the derivatives per master unit (v / w, a / w^2, j / w^3)
  // overflow to inf (a period of 1e-300 gave nan and inf cells).
  const double earliest_end = axis.start + kMinMasterSpan;  // <= period (latest_start)
  if (axis.end < earliest_end) {
    return master_refusal(MasterAxisInput::kEnd, axis.end, closed_range(earliest_end, axis.period));
  }
  return std::nullopt;
}

}  // namespace

MasterAxisError::MasterAxisError(MasterAxisRefusal refusal)
    : std::invalid_argument(refusal.message), refusal_(std::move(refusal)) {}

std::string master_number_text(double v, int digits) {
  return detail::significant(v, digits);
}

std::string master_value_text(double v) {
  if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0.0 ? "inf" : "-inf");
  std::array<char, 32> buffer{};
  const auto written = std::to_chars(buffer.data(), buffer.data() + buffer.size(), v);
  return {buffer.data(), written.ptr};
}

int bounds_digits(double value, const InputBounds& bounds) {
  constexpr int kFirst = 10;
  constexpr int kLast = std::numeric_limits<double>::max_digits10;
  // A bound as the text of `digits` significant digits reads.
  const auto printed = [](double bound, int digits) {
    if (!std::isfinite(bound)) return bound;
    return std::strtod(master_number_text(bound, digits).c_str(), nullptr);
  };
  for (int digits = kFirst; digits < kLast; ++digits) {
    const InputBounds shown{printed(bounds.lo, digits), printed(bounds.hi, digits), bounds.lo_open,
                            bounds.hi_open};
    if (!shown.contains(value)) return digits;
  }
  return kLast;
}

std::string MasterAxisRefusal::allowed() const {
  return bounds_text(bounds, [this](double v) { return master_number_text(v, digits); });
}

std::string MasterAxisRefusal::value_text() const {
  return master_value_text(value);
}

std::optional<MasterAxisRefusal> check_master_axis(const MasterAxis& axis, std::size_t max_rows) {
  const InputBounds period{kMinMasterSpan, std::numeric_limits<double>::infinity(), false, false};
  if (!period.contains(axis.period)) {
    return master_refusal(MasterAxisInput::kPeriod, axis.period, period);
  }
  if (auto refusal = check_start_and_end(axis)) return refusal;
  if (!positive().contains(axis.step)) {
    return master_refusal(MasterAxisInput::kStep, axis.step, positive());
  }
  // ceil(period / step) grid points below the period, plus start, end and period.
  const double grid_rows = static_cast<double>(max_rows - std::min(max_rows, kMasterExtraRows));
  if (!(axis.period / axis.step <= grid_rows)) {
    const InputBounds rows{axis.period / grid_rows, std::numeric_limits<double>::infinity(), false,
                           false};
    MasterAxisRefusal r{MasterAxisInput::kStep, axis.step, rows, true, std::nullopt, 10, {}};
    r.digits = bounds_digits(axis.step, rows);
    r.message = "master step = " + r.value_text() + " gives more than " + std::to_string(max_rows) +
                " rows over the master period " + master_number_text(axis.period) +
                ": it must be " + r.allowed() + " (master units)";
    return r;
  }
  return std::nullopt;
}

std::optional<MasterAxisRefusal> check_master_speed(const MasterAxis& axis, double motion_time) {
  const double speed = (axis.end - axis.start) / motion_time;
  const InputBounds speeds = closed_range(kMinMasterSpeed, kMaxMasterSpeed);
  if (speeds.contains(speed)) return std::nullopt;
  MasterAxisRefusal r{MasterAxisInput::kPeriod, axis.period, speeds, false, speed, 10, {}};
  r.digits = bounds_digits(speed, speeds);
  r.message =
      "master speed (master end - master start) / motion time = " + master_value_text(speed) +
      " master units/s (master period " + master_value_text(axis.period) + ", motion time " +
      seconds(motion_time) + ") must be finite and in " + r.allowed() + " master units/s";
  return r;
}

std::vector<double> master_positions(const MasterAxis& axis) {
  if (auto refusal = check_master_axis(axis)) throw MasterAxisError(std::move(*refusal));
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
  // The axis first (its refusals name the member), then the speed through it.
  if (auto refusal = check_master_axis(axis)) throw MasterAxisError(std::move(*refusal));
  if (auto refusal = check_master_speed(axis, T)) throw MasterAxisError(std::move(*refusal));
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
