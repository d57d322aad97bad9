#pragma once
// Whether a sampled trajectory starts and ends at rest. Both planar models take the liquid at
// rest at the first sample and drive it with the samples' acceleration alone, which is zero
// before the first sample and after the last: a container already moving at the first sample is
// taken as if it had moved at that constant speed for ever (the wave of the acceleration that
// brought it there is missing), and one still moving at the last sample as if it went on at
// that speed through the rest window (the wave of stopping it is missing). The heading is not
// extended alike: the spin term takes the turning rate itself, which is 0 outside the samples,
// so a container turning at the first sample starts turning at once there (the liquid spins up
// from rest) and one turning at the last sample stops turning at once there (the liquid's spin
// then runs down on its own through the rest window). Neither is refused (a log cut out of a
// longer run is a fair question); the answer warns and says which of these it computed.
//
// The end's speed is not the spline's end slope alone: a smoothing spline's slope at a free end
// follows the last few samples' noise (a half-cosine at rest with noise of 0.05 mm at 500 Hz
// ended its spline at up to 18 mm/s). The samples' own estimate is the slope of the least-squares
// cubic through them over the end's stretch (kEndFitPeriods of the first mode's period, at least
// kMinEndFitSamples samples), counted only when it exceeds kEndFitSignificance standard errors
// of that slope, the error estimated from the scatter of the fit's residuals. That fit has its
// own blind spot: over the stretch a cubic does not follow a fast motion's higher terms, and
// their misfit is smooth, not scatter (a descent at rest with 9 m/s^2 at its start fits to
// 5.4 mm/s). So an end is told as moving only when both show it: the fit's speed (or rate) and
// the spline's, the one the models are driven by, each above the threshold; the warning quotes
// the fit's.

#include <cstddef>
#include <string>
#include <vector>

#include "slosh/core/motion/sampled_trajectory.hpp"

namespace slosh {

/// Speed of the container (x, y, z) at an end sample above which it is told as moving [m/s]:
/// a pose logged to 1 um at 1 kHz differentiates to at most 1 mm/s of rounding, and stopping
/// from 1 mm/s at once leaves a wave of 0.09 mm in the thesis cup (R 48.5 mm, 82 mm of water;
/// a creep of 0.5 mm/s, 0.045 mm), below what a wall height is read to.
inline constexpr double kMovingEndSpeed{1e-3};
/// Turning rate at an end sample above which the container is told as turning [rad/s] (1°/s).
inline constexpr double kTurningEndRate{0.017453292519943295};
/// Stretch of samples the end's speed is fitted over, in periods of the first mode [-]: the
/// liquid answers the container's speed changes on the scale of that period, so a quarter of it
/// is the speed a stop would take away; over it a cubic follows a move of the mode's own pace,
/// and the fit averages the noise of 20 or more samples (41 at 500 Hz in the thesis cup: a
/// slope's standard error of ~4 mm/s for noise of 0.05 mm).
inline constexpr double kEndFitPeriods{0.25};
/// Least samples of the end's fit [-]: 8 residual degrees of freedom for the cubic's 4.
inline constexpr std::size_t kMinEndFitSamples{12};
/// Standard errors a fitted end slope must exceed to count [-]: Gaussian noise exceeds 4 of
/// them about once in 16 000 ends.
inline constexpr double kEndFitSignificance{4.0};

/// A coordinate's rate at one end of its samples: the least-squares cubic's slope there and its
/// standard error [unit of v per s].
struct EndRate {
  double rate{};
  double standard_error{};
};

/// The least-squares cubic through the samples (t, v) within `window` [s] of the end (`last`:
/// the last sample; else the first), at least kMinEndFitSamples of them (all when fewer): its
/// slope at the end sample and that slope's standard error from the residuals' scatter (0 when
/// the fit has no residual degree of freedom).
[[nodiscard]] EndRate end_rate(const std::vector<double>& t, const std::vector<double>& v,
                               bool last, double window);

/// One warning for each end of `trajectory` where its speed exceeds kMovingEndSpeed or its
/// turning rate kTurningEndRate, naming the end, its sample time (on the samples' clock), the
/// speed, the rate and what the models computed for each. A speed (a rate) counts when both the
/// end fits' (end_rate over kEndFitPeriods of the first mode's period 2 pi / omega1, a
/// coordinate's slope counted only when it exceeds kEndFitSignificance of its standard errors)
/// and the splines' slopes at the end sample exceed the threshold; the fits' is quoted. A
/// coordinate whose samples hold still at that end (rest_runs in sample_smoothing.hpp: a log
/// rounded to 0.1 mm that repeats its last value for 25 samples) is at rest there for both.
[[nodiscard]] std::vector<std::string> moving_end_warnings(const SampledTrajectory& trajectory,
                                                           double omega1);

}  // namespace slosh
