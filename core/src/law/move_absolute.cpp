#include "slosh/core/law/move_absolute.hpp"

#include <array>
#include <cmath>

namespace slosh {

std::optional<MoveAbsoluteProfile> move_absolute_profile(const Durations& d, double stroke) {
  if (!(d[0] > 0.0 && d[2] > 0.0 && d[4] > 0.0 && d[6] > 0.0)) return std::nullopt;
  const auto lv = plateau_levels(d, stroke);
  if (!(std::isfinite(lv.A) && lv.A > 0.0 && std::isfinite(lv.B) && lv.B > 0.0)) {
    return std::nullopt;
  }
  // One jerk: the mean of the four ramps' A / dT1, A / dT3, B / dT5, B / dT7, and each ramp within
  // kOneJerkRampTolerance of the ramp that jerk gives (A / J or B / J), which a block runs.
  const double mean = (lv.A / d[0] + lv.A / d[2] + lv.B / d[4] + lv.B / d[6]) / 4.0;
  const std::array<double, 4> ramps{lv.A / mean, lv.A / mean, lv.B / mean, lv.B / mean};
  for (std::size_t k = 0; k < 4; ++k) {
    if (!(std::abs(ramps[k] - d[2 * k]) <= kOneJerkRampTolerance)) return std::nullopt;
  }
  return MoveAbsoluteProfile{stroke, lv.v_peak, lv.A, lv.B, mean};
}

}  // namespace slosh
