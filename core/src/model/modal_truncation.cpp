#include "slosh/core/model/modal_truncation.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "slosh/core/constants.hpp"
#include "slosh/core/response/rectangular_response.hpp"

namespace slosh {

namespace {

std::string digits(double v, int count) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*g", count, v);
  return b;
}

}  // namespace

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
