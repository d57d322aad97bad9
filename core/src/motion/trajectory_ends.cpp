#include "slosh/core/motion/trajectory_ends.hpp"

#include <cmath>
#include <numbers>

#include "slosh/core/motion/sample_smoothing.hpp"
#include "text.hpp"

namespace slosh {

namespace {

/// Whether the samples v hold still at the end `last` (or the first): a run of at least
/// kMinRestSamples samples within their resolution (rest_runs).
bool holds_still(const std::vector<double>& t, const std::vector<double>& v, bool last) {
  const RestRuns runs = rest_runs(v, sample_noise(t, v));
  return (last ? runs.tail : runs.head) > 0;
}

/// The motion at the end `last` (or the first) as the samples show it: the splines' derivatives
/// there, but 0 for a coordinate whose samples hold still at that end (its smoothed spline may
/// end with a small slope there, a few mm/s on a log rounded to 0.1 mm, that the samples do not
/// show).
PlanarKinematics end_motion(const SampledTrajectory& trajectory, bool last) {
  const TrajectorySamples& s = trajectory.samples();
  PlanarKinematics k = trajectory.at(last ? trajectory.end_time() : trajectory.start_time());
  if (holds_still(s.t, s.x, last)) k.vx = 0.0;
  if (holds_still(s.t, s.y, last)) k.vy = 0.0;
  if (holds_still(s.t, s.z, last)) k.vz = 0.0;
  if (holds_still(s.t, s.theta, last)) k.theta_dot = 0.0;
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
                    detail::precise(t) + " s) the container moves at " + detail::sig3(speed * 1e3) +
                    " mm/s and turns at " + detail::sig3(rate * 180.0 / std::numbers::pi) +
                    " deg/s; ";
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
