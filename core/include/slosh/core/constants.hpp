#pragma once
// Physical constants and numerical tolerances of the core, each with its unit.

#include <array>
#include <cstddef>
#include <numbers>

namespace slosh {

/// Standard gravity [m/s^2] (SPEC §2).
constexpr double kGravity{9.81};

/// Radians per degree and degrees per radian: angles are radians inside, degrees at the edges.
/// True when `ratio` is below `limit` by more than rounding: a ratio of two inputs given in mm
/// and divided in m (19.2 / 80 = 0.23999999999999996) is at a limit it equals in decimal.
constexpr bool below_limit(double ratio, double limit) {
  return ratio < limit * (1.0 - 1e-12);
}

constexpr double kRadPerDeg{std::numbers::pi / 180.0};
constexpr double kDegPerRad{180.0 / std::numbers::pi};

/// Maximum number of radial sloshing modes the models carry.
constexpr std::size_t kMaxModes{5};

/// Roots xi_n of J1'(xi) = 0, first circumferential mode, radial modes n = 1..5 [-].
constexpr std::array<double, kMaxModes> kBesselRoots{1.841184, 5.331443, 8.536316, 11.706005,
                                                     14.863589};

/// Number of segments of the trapezoidal-acceleration law.
constexpr std::size_t kSegments{7};

/// Default minimum duration of the four jerk ramps (1, 3, 5, 7) [s] (SPEC §3).
constexpr double kDefaultMinRamp{0.05};

/// Tolerance on sum(durations) == T [s].
constexpr double kDurationSumTolerance{1e-9};

/// Resolution of a planned duration [s]: a segment shorter than 1 ns is exactly 0 (SPEC §11).
constexpr double kZeroDuration{1e-9};

/// Default nonlinear stiffening coefficient alpha [-] (thesis eq. 2.35).
constexpr double kDefaultAlpha{0.58};

/// Default rest window after the motion [s].
constexpr double kDefaultRestTime{1.0};

/// Largest integration / sampling step used to locate peaks [s] (SPEC §2: <= 1 ms).
constexpr double kMaxPeakStep{1e-3};

/// Minimum number of peak-search samples per period of the fastest mode [-].
constexpr double kSamplesPerPeriod{64.0};

/// Absolute tolerance on the time of a refined peak [s].
constexpr double kPeakTimeTolerance{1e-10};

}  // namespace slosh
