#pragma once

#include <optional>
#include <string>

#include "slosh/core/model/format.hpp"
#include "slosh/core/model/uncertainty.hpp"

namespace slosh::detail {

/// The sentence saying that an uncertainty range of the fill height reaches, at its low end, a
/// fill the models do not describe while the nominal fill is within them: a cylinder's fill ratio
/// h/R below kMinFillRatio (the shallow-liquid regime), or a rectangular tank's fill height over
/// an excited direction's side below kRectangularMinDepthRatio (its nonlinear model's range).
/// The range scales the nominal fill's models (their frequencies and damping only, SPEC §10), so
/// its figures near that end are not a model of that fill. nullopt when no range is given or its
/// low end is within the models.
[[nodiscard]] std::optional<std::string> fill_range_beyond_models(const Format& format,
                                                                  const Uncertainty& uncertainty);

}  // namespace slosh::detail
