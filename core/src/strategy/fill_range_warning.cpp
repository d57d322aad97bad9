#include "strategy/fill_range_warning.hpp"

#include <utility>
#include <vector>

#include "slosh/core/constants.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "slosh/core/response/simulation.hpp"
#include "text.hpp"

namespace slosh::detail {

namespace {

/// "fill height range 20 to 60 mm: at its low end " (as given: a low end of 14.99 mm is not
/// rounded onto the limit).
std::string range_head(const std::array<double, 2>& range) {
  return "fill height range " + precise(range[0] * 1e3) + " to " + precise(range[1] * 1e3) +
         " mm: at its low end ";
}

constexpr const char* kScaledTail =
    "; the range's figures are the nominal fill's models with their frequencies and damping "
    "scaled (SPEC §10), so the worst case and the robustness figures near that end are not "
    "reliable";

}  // namespace

std::optional<std::string> fill_range_beyond_models(const Format& format,
                                                    const Uncertainty& uncertainty) {
  if (!uncertainty.fill_height) return std::nullopt;
  const std::array<double, 2>& range = *uncertainty.fill_height;
  const double low = range[0];
  const double nominal = format.fill_height;
  if (!format.container.rectangular) {
    const double R = format.container.radius;
    if (!below_limit(low / R, kMinFillRatio) || below_limit(nominal / R, kMinFillRatio)) {
      return std::nullopt;
    }
    return range_head(range) + "the fill ratio h/R = " + fixed_below(low / R, kMinFillRatio) +
           " is below " + fixed(kMinFillRatio, 1) +
           ", the shallow-liquid regime, which is not modelled" + kScaledTail;
  }
  const RectangularTank& t = *format.container.rectangular;
  const AxisComponents c = axis_components(t.orientation_deg);
  const std::pair<const char*, double> sides[] = {
      {"length", c.along_length != 0.0 ? t.length : 0.0},
      {"width", c.along_width != 0.0 ? t.width : 0.0}};
  std::vector<std::string> shallow;
  for (const auto& [name, side] : sides) {
    if (side == 0.0) continue;  // not excited by the motion
    if (!below_limit(low / side, kRectangularMinDepthRatio) ||
        below_limit(nominal / side, kRectangularMinDepthRatio)) {
      continue;
    }
    shallow.push_back("fill height / " + std::string(name) + " = " +
                      fixed_below(low / side, kRectangularMinDepthRatio));
  }
  if (shallow.empty()) return std::nullopt;
  std::string text = range_head(range) + shallow.front();
  if (shallow.size() > 1) text += " and " + shallow.back();
  return text + (shallow.size() > 1 ? " are" : " is") + " below " +
         fixed(kRectangularMinDepthRatio, 2) +
         " (shallow fill), where the rectangular nonlinear model does not hold" + kScaledTail;
}

}  // namespace slosh::detail
