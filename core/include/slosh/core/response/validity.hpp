#pragma once

#include <string>
#include <vector>

#include "slosh/core/response/simulation.hpp"

namespace slosh {

/// validity_warnings (simulation.hpp) with the linear wave left after the motion,
/// `eta_rest_linear` [m]: a rectangular tank's linear-theory check judges the larger of
/// eta_motion and eta_rest (a shallow fill rings on after the motion, and its wave there can
/// exceed the one during it) and quotes both when the rest one is larger.
[[nodiscard]] std::vector<std::string> validity_warnings(
    const Format& format, double peak_abs_acceleration, double eta_motion_linear,
    double eta_motion_nonlinear, bool nonlinear_in_range, double eta_rest_linear);

}  // namespace slosh
