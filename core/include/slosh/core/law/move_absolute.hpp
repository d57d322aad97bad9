#pragma once
// The hand-off of a one-jerk 7-segment law to a PLCopen MC_MoveAbsolute block with a jerk limit
// (SPEC §11): the five numbers whose jerk-limited profile is the law.

#include <optional>

#include "slosh/core/law/seven_segment.hpp"

namespace slosh {

/// Relative spread of the four ramp jerks up to which a 7-segment law is one-jerk [-]: the chart
/// of the family keeps them equal to round-off; 1e-9 leaves room for polish's last ulps.
inline constexpr double kOneJerkTolerance{1e-9};

/// What a jerk-limited point-to-point block needs to run a one-jerk 7-segment law (SI units).
/// Its time-optimal profile under these limits is the law: ramps of velocity / acceleration, an
/// acceleration plateau while the velocity climbs to `velocity`, a cruise at `velocity`, and the
/// mirror with `deceleration`.
struct MoveAbsoluteProfile {
  double distance{};      ///< stroke [m]
  double velocity{};      ///< peak velocity v_peak [m/s]
  double acceleration{};  ///< A [m/s^2]
  double deceleration{};  ///< B [m/s^2]
  double jerk{};          ///< J = A / dT1 = B / dT5 [m/s^3]
};

/// The profile of a 7-segment law whose four ramp jerks agree within kOneJerkTolerance
/// (dT1 = dT3 and dT5 = dT7 and A / dT1 = B / dT5); nullopt otherwise, or when the law does not
/// build (non-finite A or B).
[[nodiscard]] std::optional<MoveAbsoluteProfile> move_absolute_profile(const Durations& d,
                                                                       double stroke);

}  // namespace slosh
