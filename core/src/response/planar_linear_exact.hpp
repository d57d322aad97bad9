#pragma once
// The planar linear model's peaks solved exactly piece by piece (planar_linear_exact.cpp).

#include <optional>

#include "slosh/core/response/planar_response.hpp"

namespace slosh::detail {

/// The peaks of the planar linear model, or nullopt where the exact solution does not apply
/// (vertical motion, which makes the stiffness time-dependent, or a mode not under-damped).
[[nodiscard]] std::optional<PlanarPeaks> exact_planar_linear_peaks(const SloshingModel& model,
                                                                   const PlanarDrive& drive,
                                                                   double rest_time,
                                                                   const PlanarOptions& options);

}  // namespace slosh::detail
