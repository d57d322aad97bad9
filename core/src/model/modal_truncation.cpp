#include "slosh/core/model/modal_truncation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "slosh/core/constants.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh {

namespace {

std::string digits(double v, int count) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*g", count, v);
  return b;
}

/// The direction's model with its first mode left out in place of the modes kept.
SloshingModel left_out_mode(const SloshingModel& m, double side, double fill_height) {
  const int n = m.modes() + 1;
  const double omega_scale = m.omega1() / rectangular_frequency(side, fill_height, 1);
  const double gain_scale = m.eta_gain.front() / rectangular_wall_gain(side, fill_height, 1);
  SloshingModel one = m;
  one.omega = {omega_scale * rectangular_frequency(side, fill_height, n)};
  one.mass = {rectangular_sloshing_mass(m.fluid_mass, side, fill_height, n)};
  one.eta_gain = {gain_scale * rectangular_wall_gain(side, fill_height, n)};
  return one;
}

}  // namespace

std::vector<Warning> modal_truncation_warnings(const RectangularTank& tank, double fill_height,
                                               const RectangularModel& model, const MotionLaw& law,
                                               double rest_time) {
  std::vector<Warning> out =
      modal_truncation_warnings(tank, fill_height, model, law.duration(), false);
  const AxisComponents c = axis_components(model.orientation_deg);
  struct Direction {
    const char* name;
    double side;
    const SloshingModel& m;
    double component;
  };
  for (const Direction& d : {Direction{"length", tank.length, model.along_length, c.along_length},
                             Direction{"width", tank.width, model.along_width, c.along_width}}) {
    if (d.component == 0.0 || d.m.omega.empty()) continue;
    const std::string head = "modal sum not converged along the " + std::string(d.name) + ": ";
    const bool said = std::any_of(out.begin(), out.end(),
                                  [&head](const Warning& w) { return w.text.rfind(head, 0) == 0; });
    if (said) continue;
    const MotionLaw driven = law.scaled(d.component);
    const SloshPeaks kept = LinearResponse(d.m, driven, rest_time).peaks();
    const SloshingModel one = left_out_mode(d.m, d.side, fill_height);
    const SloshPeaks left = LinearResponse(one, driven, rest_time).peaks();
    const double motion_share = left.motion.value / kept.motion.value;
    const double rest_share = left.rest.value / kept.rest.value;
    const bool rest = rest_share >= motion_share;
    const double share = rest ? rest_share : motion_share;
    const double wave = rest ? left.rest.value : left.motion.value;
    if (!(share > kLeftOutWaveShare) || !(wave > kLeftOutWaveFloor)) continue;
    out.push_back(
        {WarningKind::kModalSumNotConverged,
         head + "the first mode the model leaves out (n = " + std::to_string(d.m.modes() + 1) +
             ", " + digits(one.omega1() / (2.0 * std::numbers::pi), 3) +
             " Hz), simulated alone for this law, reaches " + digits(wave * 1e3, 3) + " mm " +
             (rest ? "after" : "during") + " the motion, " + digits(100.0 * share, 3) +
             " % of the " + std::to_string(d.m.modes()) + " modes' " +
             digits((rest ? kept.rest.value : kept.motion.value) * 1e3, 3) +
             " mm: the linear figures are not reliable (more modes, up to 5 in "
             "options.model.modes, help only while the first left out stays small)"});
  }
  return out;
}

std::vector<Warning> modal_truncation_warnings(const RectangularTank& tank, double fill_height,
                                               const RectangularModel& model, double motion_time,
                                               bool both) {
  std::vector<Warning> out;
  const AxisComponents c = axis_components(model.orientation_deg);
  struct Direction {
    const char* name;
    double side;
    const SloshingModel& m;
    bool driven;
  };
  for (const Direction& d :
       {Direction{"length", tank.length, model.along_length, both || c.along_length != 0.0},
        Direction{"width", tank.width, model.along_width, both || c.along_width != 0.0}}) {
    if (!d.driven || d.m.omega.empty()) continue;
    const int kept = d.m.modes();
    // The model's frequency scale (a calibration's omega_scale) applies to every mode.
    const double scale = d.m.omega1() / rectangular_frequency(d.side, fill_height, 1);
    const double omega = scale * rectangular_frequency(d.side, fill_height, kept + 1);
    const double period = 2.0 * std::numbers::pi / omega;
    if (!(period > kLeftOutPeriodShare * motion_time)) continue;
    out.push_back(
        {WarningKind::kModalSumNotConverged,
         "modal sum not converged along the " + std::string(d.name) + ": the first mode the " +
             "model leaves out (n = " + std::to_string(kept + 1) + ", " +
             digits(omega / (2.0 * std::numbers::pi), 3) + " Hz) has a period of " +
             digits(period, 3) + " s, over half the motion time " + digits(motion_time, 3) +
             " s, so it and the higher modes answer the motion dynamically and their waves are "
             "missing: the linear figures are not reliable (the side " +
             digits(d.side * 1e3, 4) + " mm is long against the " +
             digits(std::sqrt(kGravity * fill_height) * motion_time * 1e3, 4) +
             " mm a shallow-water wave travels in the motion; more modes, up to 5 in "
             "options.model.modes, help only while the first left out stays fast)"});
  }
  return out;
}

}  // namespace slosh
