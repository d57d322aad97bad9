// The rectangular tank's nonlinear model: every excited direction's dominant mode as the
// third-order oscillator of make_rectangular_direction_model and the second mode it drives
// (RectangularNonlinearDirection), inside the model's range only
// (rectangular_nonlinear_validity); outside it the linear answer with the reason.

#include <algorithm>
#include <cmath>
#include <vector>

#include "slosh/core/response/peak_finder.hpp"
#include "slosh/core/response/rectangular_nonlinear_direction.hpp"
#include "slosh/core/response/rectangular_nonlinear_validity.hpp"
#include "slosh/core/response/rectangular_response.hpp"

namespace slosh {

namespace {

RectangularNonlinearPeaks linear_instead(const RectangularModel& model, const MotionLaw& law,
                                         double rest_time, std::string warning) {
  return {RectangularLinearResponse(model, law, rest_time).peaks(), false, std::move(warning)};
}

}  // namespace

RectangularNonlinearPeaks rectangular_nonlinear_peaks(const RectangularModel& model,
                                                      const MotionLaw& law, double rest_time,
                                                      const NonlinearOptions& options) {
  if (auto v = rectangular_nonlinear_validity(model); !v.valid) {
    return linear_instead(model, law, rest_time, std::move(v.reason));
  }
  const AxisComponents c = axis_components(model.orientation_deg);
  std::vector<RectangularNonlinearDirection> directions;
  RectangularNonlinearPeaks out;
  if (c.along_length != 0.0) {
    directions.emplace_back(model.along_length, law.scaled(c.along_length), rest_time, options);
    out.peaks.along_length = directions.back().peaks();
  }
  if (c.along_width != 0.0) {
    directions.emplace_back(model.along_width, law.scaled(c.along_width), rest_time, options);
    out.peaks.along_width = directions.back().peaks();
  }
  if (auto v = rectangular_nonlinear_validity(model, wave_heights(out.peaks)); !v.valid) {
    return linear_instead(model, law, rest_time, std::move(v.reason));
  }
  if (directions.size() == 1) {
    out.peaks.highest = directions.front().peaks();
    return out;
  }
  // Both directions: the highest corner (highest_corner), searched on the continuous responses.
  const RectangularNonlinearDirection& l = directions[0];
  const RectangularNonlinearDirection& w = directions[1];
  auto highest = [&l, &w](double t) {
    return highest_corner(l.eta_odd(t), l.eta_even(t), w.eta_odd(t), w.eta_even(t));
  };
  const double step = std::min(l.peak_step(), w.peak_step());
  const double T = law.duration();
  out.peaks.highest = {find_max(highest, 0.0, T, step), find_max(highest, T, T + rest_time, step)};
  return out;
}

}  // namespace slosh
