#pragma once
// The 7-segment trapezoidal-acceleration law (thesis sec. 3.2, 4.2.1; SPEC §3).
//
// Segments: 0 -> +A (1), +A (2), +A -> 0 (3), 0 (4), 0 -> -B (5), -B (6), -B -> 0 (7).
// A and B follow from zero final velocity (A d3 = B d4) and the stroke:
//   v_peak = A d3 = B d4 = s / (c4 - c3),
// where d3, d4 are the areas of the unit positive / negative lobes and c3, c4 their centroids.
// This is the closed form of thesis eq. 4.31-4.34 after eliminating the 2x2 system.

#include <array>
#include <optional>
#include <string>

#include "slosh/core/constants.hpp"
#include "slosh/core/law/motion_law.hpp"

namespace slosh {

using Durations = std::array<double, kSegments>;

/// Admissibility rules of a set of durations.
struct AdmissibilityRules {
  double motion_time{1.0};                      ///< required sum T [s]
  double min_ramp{kDefaultMinRamp};             ///< lower bound of segments 1, 3, 5, 7 [s]
  double sum_tolerance{kDurationSumTolerance};  ///< |sum - T| allowed [s]
};

/// Checks the durations; returns nullopt when admissible, else a reason naming the value and the
/// rule ("durations_s[2] = 0.01 s is below the minimum ramp 0.05 s").
[[nodiscard]] std::optional<std::string> check_admissible(const Durations& d,
                                                          const AdmissibilityRules& rules);

/// The durations with every segment shorter than kZeroDuration set to exactly 0 and the sum equal
/// to `motion_time` to the last bit (summed left to right; the difference goes to the longest
/// segment). For durations that already sum to T within round-off (SPEC §11).
[[nodiscard]] Durations clean_durations(Durations d, double motion_time);

/// Puts the difference between `motion_time` and the left-to-right sum of `d` on segment `into`
/// until the sum is `motion_time` to the last bit (at most a few ulps move); a segment that is
/// exactly 0 stays 0. Durations are >= 0.
void close_sum(Durations& d, double motion_time, std::size_t into);

/// close_sum() keeping every segment inside [lower, upper] (a segment on its lower bound may only
/// grow): when no value of d[into] gives the sum T (the rounding of the partial sums steps over
/// it), an ulp or two on another segment with room changes that rounding first. A sum that no
/// such move closes stays within a few ulps of T, the bounds kept.
void close_sum(Durations& d, double motion_time, std::size_t into, const Durations& lower,
               const Durations& upper);

/// A, B and the peak velocity of a set of durations for a stroke.
struct PlateauLevels {
  double A{};       ///< positive plateau [m/s^2]
  double B{};       ///< magnitude of the negative plateau [m/s^2]
  double v_peak{};  ///< velocity during segment 4 [m/s]
};

/// Closed-form A and B (no admissibility check; non-finite when the lobes degenerate).
template <typename T>
struct PlateauLevelsT {
  T A;
  T B;
  T v_peak;
};
template <typename T>
[[nodiscard]] PlateauLevelsT<T> plateau_levels(const std::array<T, kSegments>& d, T stroke);

/// The law with its durations, switch times and levels.
class SevenSegmentLaw {
 public:
  /// Builds the law; throws std::invalid_argument when the durations give non-finite or
  /// non-positive A or B.
  SevenSegmentLaw(const Durations& durations, double stroke);

  [[nodiscard]] const Durations& durations() const { return durations_; }
  [[nodiscard]] std::array<double, kSegments + 1> switch_times() const;
  [[nodiscard]] double A() const { return levels_.A; }
  [[nodiscard]] double B() const { return levels_.B; }
  [[nodiscard]] double v_peak() const { return levels_.v_peak; }
  [[nodiscard]] double stroke() const { return stroke_; }
  [[nodiscard]] double motion_time() const;
  /// Jerk of each segment [m/s^3] (0 on plateaus).
  [[nodiscard]] std::array<double, kSegments> jerks() const;
  /// Integral of j^2 over the motion = sum of J_i^2 dT_i [m^2/s^5].
  [[nodiscard]] double jerk_integral() const;
  [[nodiscard]] const MotionLaw& law() const { return law_; }

 private:
  Durations durations_;
  double stroke_;
  PlateauLevels levels_;
  MotionLaw law_;
};

/// Uniform durations T/7 (the thesis baseline); the cruise dT4 carries the last ulps that make the
/// left-to-right sum T exactly.
[[nodiscard]] Durations uniform_durations(double motion_time);

}  // namespace slosh
