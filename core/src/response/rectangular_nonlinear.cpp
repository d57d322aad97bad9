// The rectangular tank's nonlinear model: the dominant mode of every excited direction as the
// third-order oscillator of make_rectangular_direction_model (NonlinearResponse, order-8 scheme
// with dense output), inside its range only; outside it the linear answer with the reason.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "slosh/core/response/rectangular_response.hpp"
#include "text.hpp"

namespace slosh {

using detail::fixed;

namespace {

const char* direction_name(TankAxis axis) {
  return axis == TankAxis::kLength ? "length" : "width";
}

/// One excited direction: its model, forcing share and name.
struct Excited {
  const SloshingModel* model;
  double component;
  TankAxis axis;
};

/// Why the nonlinear model does not hold for the format (its depth), or nullopt.
std::optional<std::string> depth_out_of_range(const Excited& d) {
  const double ratio = d.model->fill_height / d.model->radius;
  if (ratio >= kRectangularMinDepthRatio) return std::nullopt;
  return "rectangular nonlinear model not valid along the " + std::string(direction_name(d.axis)) +
         ": fill height / " + direction_name(d.axis) + " = " + fixed(ratio, 3) + " is below " +
         fixed(kRectangularMinDepthRatio, 2) +
         " (shallow fill, outside the Moiseev-type modal theory of Faltinsen et al. 2000); linear "
         "model used";
}

/// Why the response leaves the model's range (the steepness k_1 eta of the direction's peak, or
/// a diverged integration), or nullopt.
std::optional<std::string> response_out_of_range(const Excited& d, const SloshPeaks& p) {
  const double peak = std::max(p.motion.value, p.rest.value);
  const std::string where = "along the " + std::string(direction_name(d.axis));
  if (!std::isfinite(peak)) {
    return "rectangular nonlinear model diverges " + where + "; linear model used";
  }
  const double steepness = rectangular_wavenumber(d.model->radius, 1) * peak;
  if (steepness <= kRectangularMaxSteepness) return std::nullopt;
  return "rectangular nonlinear model not valid " + where + ": wall height " +
         fixed(peak * 1e3, 1) + " mm is a wave steepness k1 eta = " + fixed(steepness, 2) +
         " above " + fixed(kRectangularMaxSteepness, 2) +
         " (beyond the third-order theory); linear model used";
}

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
  for (const Excited& d : excited) {
    if (auto why = depth_out_of_range(d)) return linear_instead(model, law, rest_time, *why);
  }

  RectangularNonlinearPeaks out;
  auto direction_peaks = [&out](TankAxis axis) -> SloshPeaks& {
    return axis == TankAxis::kLength ? out.peaks.along_length : out.peaks.along_width;
  };
  if (excited.size() == 1) {
    const Excited& d = excited.front();
    const SloshPeaks p = nonlinear_peaks(*d.model, law.scaled(d.component), rest_time, options);
    if (auto why = response_out_of_range(d, p)) {
      return linear_instead(model, law, rest_time, *why);
    }
    direction_peaks(d.axis) = p;
    out.peaks.highest = p;
    return out;
  }

  // Both directions: the corners' height is the sum of the two continuous responses (each the
  // scheme's dense output), searched as the linear corners are.
  std::vector<NonlinearResponse> responses;
  double period = INFINITY;
  for (const Excited& d : excited) {
    responses.emplace_back(*d.model, law.scaled(d.component), rest_time, options);
    if (auto why = response_out_of_range(d, responses.back().peaks())) {
      return linear_instead(model, law, rest_time, *why);
    }
    direction_peaks(d.axis) = responses.back().peaks();
    period = std::min(period, 2.0 * std::numbers::pi / d.model->omega1());
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
