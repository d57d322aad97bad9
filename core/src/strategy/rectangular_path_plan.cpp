// A rectangular tank's law verified along a path (rectangular_path_plan.hpp).

#include "slosh/core/strategy/rectangular_path_plan.hpp"

#include <numbers>
#include <vector>

#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/model/uncertainty.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/response/rectangular_planar.hpp"
#include "slosh/core/strategy/path_plan.hpp"

namespace slosh {

double tank_frame_angle(const PlanarPath& path, double orientation_deg) {
  return path.start_heading() + orientation_deg * std::numbers::pi / 180.0;
}

PathPrediction predict_tank_on_path(const RectangularModel& tank, const PlanarPath& path,
                                    const MotionLaw& law, double rest_time, std::string* warning) {
  PathPrediction p;
  const PlanarDrive drive(path, law);
  const double frame = tank_frame_angle(path, tank.orientation_deg);
  const RectangularPlanarPeaks linear =
      rectangular_planar_linear_peaks(tank, drive, frame, rest_time);
  p.linear = linear.highest;
  p.linear_directions = DirectionWaves{linear.along_length, linear.along_width};
  RectangularPlanarNonlinearPeaks nl =
      rectangular_planar_nonlinear_peaks(tank, drive, frame, rest_time);
  p.nonlinear = nl.peaks.highest;
  if (warning != nullptr) *warning = std::move(nl.warning);
  const PathAcceleration a = path_acceleration(path, law);
  p.a_total_peak = a.total;
  p.a_total_time = a.time;
  p.a_normal_peak = a.normal;
  const KinematicSummary k = law.summary();
  p.v_peak = k.v_peak;
  p.j_peak = k.j_peak;
  return p;
}

std::optional<RobustnessReport> rectangular_robustness_report_on_path(
    const RectangularModel& tank, const PlanarPath& path, const MotionLaw& law,
    const RobustnessSweep& sweep, const std::function<bool()>& out_of_time) {
  // As the line's sweep: the plan's zeta is the most excited direction's.
  const bool common = sweep.zeta != driven_directions(tank).front().model.zeta;
  auto peaks = [](const PlanarPeaks& p) {
    return SloshPeaks{{p.motion.value, p.motion.time}, {p.rest.value, p.rest.time}};
  };
  std::vector<RobustnessPoint> points;
  for (const double delta : robustness_deltas(sweep)) {
    if (out_of_time && out_of_time()) return std::nullopt;
    RectangularModel m = tank;
    const double z_l = common ? sweep.zeta : tank.along_length.zeta;
    const double z_w = common ? sweep.zeta : tank.along_width.zeta;
    m.along_length = scaled_model(tank.along_length, 1.0 + delta, z_l);
    m.along_width = scaled_model(tank.along_width, 1.0 + delta, z_w);
    const PathPrediction q = predict_tank_on_path(m, path, law, sweep.rest_time);
    RobustnessPoint p;
    p.delta = delta;
    p.linear = peaks(q.linear);
    p.nonlinear = peaks(q.nonlinear);
    points.push_back(p);
  }
  return judged_report(sweep, std::move(points));
}

}  // namespace slosh
