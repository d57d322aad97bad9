// The range of the rectangular nonlinear model (docs/models.md): depth ratio, critical depth and
// wave steepness of every excited direction, with the sentence that says which one failed.

#include "slosh/core/response/rectangular_nonlinear_validity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "slosh/core/constants.hpp"
#include "text.hpp"

namespace slosh {

using detail::fixed;
using detail::fixed_above;
using detail::fixed_below;

namespace {

const char* direction_name(TankAxis axis) {
  return axis == TankAxis::kLength ? "length" : "width";
}

RectangularNonlinearValidity invalid(RectangularNonlinearLimit limit, TankAxis axis,
                                     std::string reason) {
  return {false, limit, axis, std::move(reason)};
}

/// The checks of one excited direction, in the order of the header's contract.
RectangularNonlinearValidity check_direction(const SloshingModel& m, TankAxis axis, double height) {
  const std::string name = direction_name(axis);
  const std::string head = "rectangular nonlinear model not valid along the " + name + ": ";
  const std::string tail = "; linear model used";
  const double ratio = m.fill_height / m.radius;
  if (below_limit(ratio, kRectangularMinDepthRatio)) {
    return invalid(RectangularNonlinearLimit::kShallowDepth, axis,
                   head + "fill height / " + name + " = " +
                       fixed_below(ratio, kRectangularMinDepthRatio) + " is below " +
                       fixed(kRectangularMinDepthRatio, 2) +
                       " (shallow fill, outside the Moiseev-type modal theory of Faltinsen et "
                       "al. 2000)" +
                       tail);
  }
  if (!std::isfinite(height)) {
    return invalid(RectangularNonlinearLimit::kDiverged, axis,
                   "rectangular nonlinear model diverges along the " + name + tail);
  }
  const double steepness = rectangular_wavenumber(m.radius, 1) * height;
  if (steepness > kRectangularMaxSteepness) {
    return invalid(
        RectangularNonlinearLimit::kSteepness, axis,
        head + "the nonlinear model's wall height " + fixed(height * 1e3, 1) +
            " mm is a wave steepness k1 eta = " + fixed_above(steepness, kRectangularMaxSteepness) +
            " above " + fixed(kRectangularMaxSteepness, 2) + " (beyond the third-order theory)" +
            tail);
  }
  const double c = rectangular_frequency_correction(m.radius, m.fill_height);
  if (std::abs(c) < kRectangularCriticalFifthOrder * steepness * steepness) {
    return invalid(RectangularNonlinearLimit::kCriticalDepth, axis,
                   head + "fill height / " + name + " = " + fixed(ratio, 3) +
                       " is near the critical depth " + fixed(kRectangularCriticalDepthRatio, 4) +
                       ", where at the nonlinear model's wall height " + fixed(height * 1e3, 1) +
                       " mm (k1 eta = " + fixed(steepness, 2) +
                       ") the fifth-order frequency shift the model leaves out exceeds its "
                       "third-order one" +
                       tail);
  }
  return {};
}

}  // namespace

RectangularWaveHeights wave_heights(const RectangularPeaks& peaks) {
  // A diverged (NaN) peak in either window must reach the check as not finite, which std::max
  // does not guarantee (it keeps its first argument when a comparison with NaN is false).
  auto larger = [](const SloshPeaks& p) {
    if (!std::isfinite(p.motion.value) || !std::isfinite(p.rest.value)) {
      return std::numeric_limits<double>::infinity();
    }
    return std::max(p.motion.value, p.rest.value);
  };
  return {larger(peaks.along_length), larger(peaks.along_width)};
}

RectangularNonlinearValidity rectangular_nonlinear_validity(const RectangularModel& model,
                                                            const RectangularWaveHeights& heights) {
  const AxisComponents c = axis_components(model.orientation_deg);
  RectangularNonlinearValidity length, width;
  if (c.along_length != 0.0) {
    length = check_direction(model.along_length, TankAxis::kLength, heights.along_length);
  }
  if (c.along_width != 0.0) {
    width = check_direction(model.along_width, TankAxis::kWidth, heights.along_width);
  }
  if (length.valid) return width;
  if (width.valid) return length;
  // Both directions fail: one sentence naming each, so the user does not fix one side and meet
  // the other on the next try.
  const std::string tail = "; linear model used";
  length.reason.resize(length.reason.size() - tail.size());
  length.reason += "; " + width.reason;
  return length;
}

}  // namespace slosh
