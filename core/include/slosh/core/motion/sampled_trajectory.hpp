#pragma once
// A sampled spatial trajectory (a robot's log or a commanded pose table): times, positions and
// the heading about the vertical axis, through smoothing cubic splines (SPEC §14): each
// coordinate's samples are smoothed against the noise estimated from them (sample_smoothing.hpp;
// a clean commanded table is kept to round-off, a log's rounding does not become acceleration),
// then interpolated by the not-a-knot cubic spline (the end pieces are the cubics through the
// four nearest smoothed samples, so a motion that starts or stops with an acceleration step
// keeps it). The acceleration the models need is the splines' second derivative: continuous and
// piecewise linear between samples, so a simulation steps from sample to sample exactly on its
// pieces.

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

#include "slosh/core/motion/planar_kinematics.hpp"

namespace slosh {

/// Raw samples. `z` and `theta` may be empty (then 0 throughout); otherwise every vector has
/// the size of `t`.
struct TrajectorySamples {
  std::vector<double> t;      ///< [s], strictly increasing
  std::vector<double> x;      ///< [m]
  std::vector<double> y;      ///< [m]
  std::vector<double> z;      ///< [m], up
  std::vector<double> theta;  ///< heading about the vertical axis [rad], continuous
};

/// Least samples per period of the first sloshing mode a trajectory must have [-]: the cubic
/// spline's second derivative then follows a motion at the mode's frequency to about 1 % of its
/// acceleration amplitude (the error of a cubic spline's second derivative is ~ (w h)^2 / 12,
/// w h = 2 pi / 20).
inline constexpr double kSamplesPerFirstPeriod{20.0};
/// Shortest time step between two samples, as a fraction of the first mode's period [-]: 1e-9
/// of ~0.1..1 s is far below any drive's log period (1 us at 1 MHz), and above it the spline's
/// accelerations and the models' steps stay finite (steps of 1e-300 s overflow both).
inline constexpr double kMinStepPerFirstPeriod{1e-9};

/// Cubic spline of one coordinate: second derivatives at the knots.
struct CubicSpline {
  std::vector<double> value;   ///< smoothed samples
  std::vector<double> second;  ///< second derivative at each knot (not-a-knot ends)
};

/// A validated trajectory.
class SampledTrajectory {
 public:
  /// Throws InvalidMotion for fewer than 4 samples ("t"), vectors of different sizes (the
  /// vector's name), a non-finite value ("x[12]"), or times not strictly increasing ("t[12]").
  explicit SampledTrajectory(TrajectorySamples samples);

  /// Throws InvalidMotion ("t[i]") when two samples are further apart than a
  /// 1/kSamplesPerFirstPeriod of the first mode's period 2 pi / omega1, saying the rate needed,
  /// or closer than kMinStepPerFirstPeriod of that period, saying the minimum step.
  void check_sampling(double omega1) const;
  /// Samples per second a trajectory needs for a first mode of omega1 [rad/s].
  [[nodiscard]] static double required_rate(double omega1);

  [[nodiscard]] const TrajectorySamples& samples() const { return samples_; }
  [[nodiscard]] std::size_t size() const { return samples_.t.size(); }
  [[nodiscard]] double start_time() const { return samples_.t.front(); }
  [[nodiscard]] double end_time() const { return samples_.t.back(); }
  /// True when z or theta is not constant.
  [[nodiscard]] bool has_vertical_motion() const { return vertical_; }
  [[nodiscard]] bool turns() const { return turns_; }
  /// The interval i with t[i] <= t < t[i+1] (clamped to the first and last).
  [[nodiscard]] std::size_t interval_at(double t) const;
  /// Pose and derivatives at t from the splines (clamped to [start, end]: at rest outside).
  [[nodiscard]] PlanarKinematics at(double t) const;
  /// at() on interval i.
  [[nodiscard]] PlanarKinematics at(std::size_t i, double t) const;
  /// The vertical acceleration at sample i (0 < i < size() - 1) as the samples give it [m/s^2]:
  /// the second divided difference of the smoothed z over samples i - 1, i, i + 1, which is the
  /// spline's acceleration averaged over those two intervals with a hat weight peaking at t[i].
  /// Where the motion has an acceleration step (a descent stopped at once) the spline, which
  /// keeps its acceleration continuous, overshoots the step between its knots and at the knots
  /// beside it (-10.2 m/s^2 for a step from -9 to 0 at 500 Hz); the average does not (-9.0),
  /// and on a smooth motion it is the spline's own value to (w h)^2 / 12.
  [[nodiscard]] double sample_vertical_acceleration(std::size_t i) const;

 private:
  TrajectorySamples samples_;
  CubicSpline x_, y_, z_, theta_;
  bool vertical_{};
  bool turns_{};
};

/// Reads the measured runs' pose CSV: a header `t_s,x_m,y_m,z_m,qx,qy,qz,qw` (positions in
/// metres, orientation a unit quaternion; a UTF-8 byte order mark before it is skipped) and one
/// sample a line. The heading is theta = 2 atan2(qz, qw), unwrapped to a continuous angle. A
/// quaternion whose norm is within 1e-3 of 1 (a log printed to 3 decimals) is normalised. Throws
/// InvalidMotion naming the line ("line 17") for a wrong header, a missing or non-numeric field,
/// a norm further from 1, or a quaternion that tilts the container (|qx| or |qy| above 1e-3:
/// only rotations about the vertical axis are modelled). `source` names the input in the
/// messages.
[[nodiscard]] TrajectorySamples read_pose_csv(std::istream& in, const std::string& source);

}  // namespace slosh
