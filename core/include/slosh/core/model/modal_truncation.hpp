#pragma once
// Whether a rectangular tank's modal sum, truncated at the model's modes, resolves a motion: the
// modes it leaves out must answer the motion quasi-statically (docs/models.md, "Modal sum not
// converged").

#include <vector>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/model/rectangular_tank.hpp"
#include "slosh/core/warning.hpp"

namespace slosh {

/// Share of the motion time above which the period of the first mode left out makes the
/// truncated sum unreliable [-]: that mode, and the higher ones, then answer the motion
/// dynamically and leave waves of their own after it.
inline constexpr double kLeftOutPeriodShare{0.5};

/// A `modal_sum_not_converged` warning per direction of `model` (the tank's, `fill_height` its
/// fill) whose first mode left out (n = modes + 1, the model's frequency scale applied) has a
/// period over kLeftOutPeriodShare of `motion_time` [s]; the directions the motion drives only
/// (both when `both`, else those the orientation drives along a straight motion).
[[nodiscard]] std::vector<Warning> modal_truncation_warnings(const RectangularTank& tank,
                                                             double fill_height,
                                                             const RectangularModel& model,
                                                             double motion_time, bool both);

/// Share of a window's peak of the modes kept above which the first mode left out, simulated
/// alone for the law, makes the truncated sum unreliable [-].
inline constexpr double kLeftOutWaveShare{0.1};
/// Least wave of that mode that counts [m]: a share of a wave far below a millimetre (a slow
/// move's residual) changes no figure that matters (as worse_than_baseline's 0.5 mm).
inline constexpr double kLeftOutWaveFloor{0.5e-3};

/// modal_truncation_warnings of a straight motion by `law` (the tank's orientation drives the
/// directions), with its own evidence too: the first mode left out, simulated alone for the law
/// (its frequency and wall gain from the theory, the model's scales applied), against the modes
/// kept, per window; over kLeftOutWaveShare of their peak in either window (and over
/// kLeftOutWaveFloor), the sum is not
/// converged whatever the periods say (a long shallow tank in a slower motion).
[[nodiscard]] std::vector<Warning> modal_truncation_warnings(const RectangularTank& tank,
                                                             double fill_height,
                                                             const RectangularModel& model,
                                                             const MotionLaw& law,
                                                             double rest_time);

}  // namespace slosh
