#pragma once
// The cam table of a law at a motion controller's fixed cycle (SPEC §6).
//
// Sample k is the law's state at t_k = k * period, k = 0..N, where N is the first k with
// t_k >= T (within kCamTimeTolerance). Samples at or after T hold the rest state with the position
// set to the stroke exactly, so the last sample lands on the stroke even when T is not a multiple
// of the cycle. At a switch time the jerk is the one of the segment that starts there.

#include <vector>

#include "slosh/core/law/motion_law.hpp"

namespace slosh {

/// A sample time within this distance of a switch time (or of T) counts as on it [s].
constexpr double kCamTimeTolerance{1e-12};

/// Shortest controller cycle a cam table is sampled at [s].
constexpr double kCamMinPeriod{1e-5};

/// Most samples in one cam table (10 million: 2.8 h at 1 ms).
constexpr std::size_t kCamMaxSamples{10'000'000};

/// One row of a cam table (SI units).
struct CamSample {
  double t{};             ///< [s]
  double position{};      ///< [m]
  double velocity{};      ///< [m/s]
  double acceleration{};  ///< [m/s^2]
  double jerk{};          ///< [m/s^3]
};

/// Number of cycles N of a law of duration `motion_time` sampled every `period` (samples: N + 1).
[[nodiscard]] std::size_t cam_cycles(double motion_time, double period);

/// Samples `law` every `period` seconds; the samples at and after the end hold the position
/// `stroke` exactly. Throws std::invalid_argument for a period below kCamMinPeriod or a table of
/// more than kCamMaxSamples samples.
[[nodiscard]] std::vector<CamSample> sample_cam_table(const MotionLaw& law, double stroke,
                                                      double period);

}  // namespace slosh
