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
  // The four ramps' jerks A / dT1, A / dT3, B / dT5, B / dT7 agree to round-off; their mean.
  const std::array<double, 4> jerks{lv.A / d[0], lv.A / d[2], lv.B / d[4], lv.B / d[6]};
  for (double j : jerks) {
    if (!(std::abs(j - jerks[0]) <= kOneJerkTolerance * jerks[0])) return std::nullopt;
  }
  const double mean = (jerks[0] + jerks[1] + jerks[2] + jerks[3]) / 4.0;
  return MoveAbsoluteProfile{stroke, lv.v_peak, lv.A, lv.B, mean};
}

}  // namespace slosh
