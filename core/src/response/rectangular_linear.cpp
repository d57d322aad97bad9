#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

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

LinearResponse LinearResponse::combined(const LinearResponse& a, double gain_a,
                                        const LinearResponse& b, double gain_b) {
  if (a.piece_begin_ != b.piece_begin_ || a.end_time_ != b.end_time_) {
    throw std::invalid_argument("LinearResponse::combined: the responses' pieces differ");
  }
  LinearResponse sum = a;
  const std::size_t ma = a.gains_.size(), mb = b.gains_.size();
  sum.gains_.clear();
  for (double g : a.gains_) sum.gains_.push_back(gain_a * g);
  for (double g : b.gains_) sum.gains_.push_back(gain_b * g);
  sum.coefficients_.clear();
  sum.coefficients_.reserve(a.coefficients_.size() + b.coefficients_.size());
  for (std::size_t k = 0; k < a.piece_begin_.size(); ++k) {
    const auto ka = static_cast<std::ptrdiff_t>(k * ma), kb = static_cast<std::ptrdiff_t>(k * mb);
    sum.coefficients_.insert(sum.coefficients_.end(), a.coefficients_.begin() + ka,
                             a.coefficients_.begin() + ka + static_cast<std::ptrdiff_t>(ma));
    sum.coefficients_.insert(sum.coefficients_.end(), b.coefficients_.begin() + kb,
                             b.coefficients_.begin() + kb + static_cast<std::ptrdiff_t>(mb));
  }
  sum.peak_step_ = std::min(a.peak_step_, b.peak_step_);
  return sum;
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
    // values (the corners) the highest point at t is |eta_L| + |eta_W| = max(|eta_L + eta_W|,
    // |eta_L - eta_W|): the larger peak of the two corner responses, each scanned exactly as one
    // response with both directions' modes (docs/models.md).
    const SloshPeaks plus = LinearResponse::combined(*length_, 1.0, *width_, 1.0).peaks();
    const SloshPeaks minus = LinearResponse::combined(*length_, 1.0, *width_, -1.0).peaks();
    p.highest.motion = plus.motion.value >= minus.motion.value ? plus.motion : minus.motion;
    p.highest.rest = plus.rest.value >= minus.rest.value ? plus.rest : minus.rest;
  }
  return p;
}

}  // namespace slosh
