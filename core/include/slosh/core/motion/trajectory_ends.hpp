#pragma once
// Whether a sampled trajectory starts and ends at rest. Both planar models take the liquid at
// rest at the first sample and drive it with the samples' acceleration alone, which is zero
// before the first sample and after the last: a container already moving at the first sample is
// taken as if it had moved at that constant speed for ever (the wave of the acceleration that
// brought it there is missing), and one still moving at the last sample as if it went on at
// that speed through the rest window (the wave of stopping it is missing). Neither is refused
// (a log cut out of a longer run is a fair question); the answer warns.

#include <string>
#include <vector>

#include "slosh/core/motion/sampled_trajectory.hpp"

namespace slosh {

/// Speed of the container (x, y, z) at an end sample above which it is told as moving [m/s]:
/// a pose logged to 1 um at 1 kHz differentiates to at most 1 mm/s of rounding.
inline constexpr double kMovingEndSpeed{1e-3};
/// Turning rate at an end sample above which the container is told as turning [rad/s] (1°/s).
inline constexpr double kTurningEndRate{0.017453292519943295};

/// One warning for each end of `trajectory` where its speed exceeds kMovingEndSpeed or its
/// turning rate kTurningEndRate, naming the end, its sample time, the speed and the rate. The
/// verdict is the samples' (rest_runs in sample_smoothing.hpp): a coordinate whose samples hold
/// still at that end (a log rounded to 0.1 mm that repeats its last value for 25 samples) is at
/// rest there, whatever slope a spline might give it; the others move at their splines' slopes.
[[nodiscard]] std::vector<std::string> moving_end_warnings(const SampledTrajectory& trajectory);

}  // namespace slosh
