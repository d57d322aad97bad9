#pragma once
// The hand-off of a one-jerk 7-segment law to a PLCopen MC_MoveAbsolute block with a jerk limit
// (SPEC §11): the five numbers whose jerk-limited profile is the law.

#include <optional>

#include "slosh/core/law/seven_segment.hpp"

namespace slosh {

/// How far each ramp may be from the ramp the one jerk gives (A / J, B / J) for a 7-segment law to
/// be one-jerk [s]: the chart of the family keeps them equal to round-off, and polish's snap of a
/// plateau within 1 ns of its bound moves them by nanoseconds; 10 ns is 1 % of SPEC §11's 1 µs.
inline constexpr double kOneJerkRampTolerance{1e-8};

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

/// The profile of a 7-segment law whose four ramps are those of one jerk J, each within
/// kOneJerkRampTolerance (dT1 = dT3 = A / J, dT5 = dT7 = B / J, J the mean of the four ramp
/// jerks); nullopt otherwise, or when A or B is not finite and positive.
[[nodiscard]] std::optional<MoveAbsoluteProfile> move_absolute_profile(const Durations& d,
                                                                       double stroke);

}  // namespace slosh
