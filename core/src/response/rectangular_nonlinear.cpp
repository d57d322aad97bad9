// The rectangular tank's nonlinear model: the dominant mode of every excited direction as the
// third-order oscillator of make_rectangular_direction_model (NonlinearResponse, order-8 scheme
// with dense output), inside its range only (rectangular_nonlinear_validity); outside it the
// linear answer with the reason.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "slosh/core/response/rectangular_nonlinear_validity.hpp"
#include "slosh/core/response/rectangular_response.hpp"

namespace slosh {

namespace {

/// One excited direction: its model, forcing share and name.
struct Excited {
  const SloshingModel* model;
  double component;
  TankAxis axis;
};

RectangularNonlinearPeaks linear_instead(const RectangularModel& model, const MotionLaw& law,
                                         double rest_time, std::string warning) {
  return {RectangularLinearResponse(model, law, rest_time).peaks(), false, std::move(warning)};
}

}  // namespace

RectangularNonlinearPeaks rectangular_nonlinear_peaks(const RectangularModel& model,
                                                      const MotionLaw& law, double rest_time,
                                                      const NonlinearOptions& options) {
  const AxisComponents c = axis_components(model.orientation_deg);
  std::vector<Excited> excited;
  if (c.along_length != 0.0)
    excited.push_back({&model.along_length, c.along_length, TankAxis::kLength});
  if (c.along_width != 0.0)
    excited.push_back({&model.along_width, c.along_width, TankAxis::kWidth});
  if (auto v = rectangular_nonlinear_validity(model); !v.valid) {
    return linear_instead(model, law, rest_time, std::move(v.reason));
  }

  RectangularNonlinearPeaks out;
  auto direction_peaks = [&out](TankAxis axis) -> SloshPeaks& {
    return axis == TankAxis::kLength ? out.peaks.along_length : out.peaks.along_width;
  };
  if (excited.size() == 1) {
    const Excited& d = excited.front();
    const SloshPeaks p = nonlinear_peaks(*d.model, law.scaled(d.component), rest_time, options);
    direction_peaks(d.axis) = p;
    if (auto v = rectangular_nonlinear_validity(model, wave_heights(out.peaks)); !v.valid) {
      return linear_instead(model, law, rest_time, std::move(v.reason));
    }
    out.peaks.highest = p;
    return out;
  }

  // Both directions: the corners' height is the sum of the two continuous responses (each the
  // scheme's dense output), searched as the linear corners are.
  std::vector<NonlinearResponse> responses;
  double period = INFINITY;
  for (const Excited& d : excited) {
    responses.emplace_back(*d.model, law.scaled(d.component), rest_time, options);
    direction_peaks(d.axis) = responses.back().peaks();
    period = std::min(period, 2.0 * std::numbers::pi / d.model->omega1());
  }
  if (auto v = rectangular_nonlinear_validity(model, wave_heights(out.peaks)); !v.valid) {
    return linear_instead(model, law, rest_time, std::move(v.reason));
  }
  const double step = std::min(kMaxPeakStep, period / kSamplesPerPeriod);
  auto highest = [&responses](double t) {
    return std::abs(responses[0].eta(t)) + std::abs(responses[1].eta(t));
  };
  const double T = law.duration();
  out.peaks.highest = {find_max(highest, 0.0, T, step), find_max(highest, T, T + rest_time, step)};
  return out;
}

}  // namespace slosh
