#include <algorithm>
#include <cmath>
#include <numbers>

#include "slosh/core/response/rectangular_response.hpp"

namespace slosh {

AxisComponents axis_components(double orientation_deg) {
  // Multiples of 90 degrees exactly: cos(pi/2) in floating point is 6e-17, which would drive
  // the direction across the motion by a round-off.
  const double quarter = orientation_deg / 90.0;
  if (quarter == std::round(quarter)) {
    switch (static_cast<int>(std::lround(quarter)) & 3) {
      case 0:
        return {1.0, 0.0};
      case 1:
        return {0.0, 1.0};
      case 2:
        return {-1.0, 0.0};
      default:
        return {0.0, -1.0};
    }
  }
  const double phi = orientation_deg * std::numbers::pi / 180.0;
  const double c = std::cos(phi), s = std::sin(phi);
  // Diagonals exactly: cos 45 and sin 45 differ by an ulp in floating point, and a square tank
  // moved diagonally must drive both directions alike.
  const double eighth = orientation_deg / 45.0;
  if (eighth == std::round(eighth)) {
    return {std::copysign(std::numbers::sqrt2 / 2.0, c),
            std::copysign(std::numbers::sqrt2 / 2.0, s)};
  }
  return {c, s};
}

namespace {

double fastest_period(const SloshingModel& m) {
  return 2.0 * std::numbers::pi / *std::max_element(m.omega.begin(), m.omega.end());
}

}  // namespace

RectangularLinearResponse::RectangularLinearResponse(const RectangularModel& model,
                                                     const MotionLaw& law, double rest_time)
    : motion_time_(law.duration()), end_time_(law.duration() + rest_time) {
  const AxisComponents c = axis_components(model.orientation_deg);
  double period = INFINITY;
  if (c.along_length != 0.0) {
    length_.emplace(model.along_length, law.scaled(c.along_length), rest_time);
    period = std::min(period, fastest_period(model.along_length));
  }
  if (c.along_width != 0.0) {
    width_.emplace(model.along_width, law.scaled(c.along_width), rest_time);
    period = std::min(period, fastest_period(model.along_width));
  }
  peak_step_ = std::min(kMaxPeakStep, period / kSamplesPerPeriod);
}

double RectangularLinearResponse::eta_length(double t) const {
  return length_ ? length_->eta(t) : 0.0;
}

double RectangularLinearResponse::eta_width(double t) const {
  return width_ ? width_->eta(t) : 0.0;
}

RectangularPeaks RectangularLinearResponse::peaks() const {
  RectangularPeaks p;
  if (length_) p.along_length = length_->peaks();
  if (width_) p.along_width = width_->peaks();
  if (!width_) {
    p.highest = p.along_length;
  } else if (!length_) {
    p.highest = p.along_width;
  } else {
    // Along a wall the other direction's wave adds its own elevation; with both at their wall
    // values (the corners) the highest point at t is |eta_L| + |eta_W|, the larger of the two
    // corner sums eta_L +- eta_W (docs/models.md).
    auto f = [this](double t) { return eta_highest(t); };
    p.highest = {find_max(f, 0.0, motion_time_, peak_step_),
                 find_max(f, motion_time_, end_time_, peak_step_)};
  }
  return p;
}

}  // namespace slosh
