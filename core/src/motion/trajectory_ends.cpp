#include "slosh/core/motion/trajectory_ends.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

#include "slosh/core/motion/sample_smoothing.hpp"
#include "text.hpp"

namespace slosh {

namespace {

/// Whether the samples v hold still at the end `last` (or the first): a run of at least
/// kMinRestSamples samples within their resolution (rest_runs).
bool holds_still(const std::vector<double>& v, double noise, bool last) {
  const RestRuns runs = rest_runs(v, noise);
  return (last ? runs.tail : runs.head) > 0;
}

/// Span of samples at an end whose quadratic fit gives the end's slope [s]: long enough that a
/// log rounded to 0.1 mm at 1 kHz reads to about 1 mm/s, short enough that a changing
/// acceleration (a log cut mid-motion) moves the slope by well under 1 %.
constexpr double kEndFitSpan{0.05};
constexpr std::size_t kEndFitMinSamples{5};

/// The slope dv/dt at the end `last` (or the first) of the least-squares quadratic through the
/// samples of the last kEndFitSpan (at least kEndFitMinSamples of them), for noisy samples: the
/// smoothed spline's end slope follows the rounding steps of a logged pose (118 mm/s for a log
/// creeping at 20 mm/s, rounded to 0.1 mm); the fit averages them out and is exact for a motion
/// of constant acceleration.
double end_slope(const std::vector<double>& t, const std::vector<double>& v, bool last) {
  const std::size_t n = t.size();
  const double t_end = last ? t[n - 1] : t[0];
  std::size_t count = 0;
  while (count < n) {
    const double ti = last ? t[n - 1 - count] : t[count];
    if (count >= kEndFitMinSamples && std::abs(ti - t_end) > kEndFitSpan) break;
    ++count;
  }
  if (count < 3) return (v[n - 1] - v[0]) / (t[n - 1] - t[0]);
  const double span = std::max(std::abs((last ? t[n - count] : t[count - 1]) - t_end), 1e-12);
  // Normal equations of v = c0 + c1 u + c2 u^2 with u = (t - t_end) / span in [-1, 1].
  double m[3][4] = {};
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t i = last ? n - 1 - j : j;
    const double u = (t[i] - t_end) / span;
    const double p[3] = {1.0, u, u * u};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m[r][c] += p[r] * p[c];
      m[r][3] += p[r] * v[i];
    }
  }
  for (int col = 0; col < 3; ++col) {  // Gauss-Jordan; the matrix is symmetric positive definite
    for (int r = 0; r < 3; ++r) {
      if (r == col) continue;
      const double f = m[r][col] / m[col][col];
      for (int c = col; c < 4; ++c) m[r][c] -= f * m[col][c];
    }
  }
  return m[1][3] / m[1][1] / span;
}

/// The motion at the end `last` (or the first) as the samples show it: exact samples move at
/// their spline's slope there (it interpolates them), noisy ones at end_slope, and a coordinate
/// whose samples hold still at that end not at all (its smoothed spline may end with a small
/// slope there, a few mm/s on a log rounded to 0.1 mm, that the samples do not show).
PlanarKinematics end_motion(const SampledTrajectory& trajectory, bool last) {
  const TrajectorySamples& s = trajectory.samples();
  PlanarKinematics k = trajectory.at(last ? trajectory.end_time() : trajectory.start_time());
  const auto slope = [&](const std::vector<double>& v, double spline) {
    const double noise = sample_noise(s.t, v);
    if (holds_still(v, noise, last)) return 0.0;
    return samples_exact(noise, v) ? spline : end_slope(s.t, v, last);
  };
  k.vx = slope(s.x, k.vx);
  k.vy = slope(s.y, k.vy);
  k.vz = slope(s.z, k.vz);
  k.theta_dot = slope(s.theta, k.theta_dot);
  return k;
}

}  // namespace

std::vector<std::string> moving_end_warnings(const SampledTrajectory& trajectory) {
  std::vector<std::string> out;
  for (const bool last : {false, true}) {
    const double t = last ? trajectory.end_time() : trajectory.start_time();
    const PlanarKinematics k = end_motion(trajectory, last);
    const double speed = std::sqrt(k.vx * k.vx + k.vy * k.vy + k.vz * k.vz);
    const double rate = std::abs(k.theta_dot);
    if (!(speed > kMovingEndSpeed) && !(rate > kTurningEndRate)) continue;
    const std::string sample =
        last ? "t_s[" + std::to_string(trajectory.size() - 1) + "]" : std::string("t_s[0]");
    std::string w = std::string("the trajectory ") + (last ? "ends" : "starts") +
                    " moving: at its " + (last ? "last" : "first") + " sample (" + sample + " = " +
                    detail::significant(t, 6) + " s) the container moves at " +
                    detail::sig3(speed * 1e3) + " mm/s and turns at " +
                    detail::sig3(rate * 180.0 / std::numbers::pi) + " deg/s; ";
    w += last ? "the models see no acceleration after it, as if the container went on at that "
                "speed through the rest window: the wave of stopping it is not in the prediction "
                "(eta_rest in particular); end the trajectory at rest"
              : "the models take the liquid at rest there, as if the container had always moved "
                "at that speed: the wave of the acceleration that brought it to that speed is not "
                "in the "
                "prediction; start the trajectory at rest";
    out.push_back(std::move(w));
  }
  return out;
}

}  // namespace slosh
