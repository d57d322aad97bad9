#pragma once
// The uncertainty and robustness blocks of a plan (SPEC §10) in the API's units: percent for the
// frequency error delta, Hz and rad/s for omega_1, mm for eta. The plan, its compact view and the
// rows of plan tables read them from here.

#include <nlohmann/json.hpp>

#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/model/uncertainty.hpp"
#include "slosh/core/strategy/robustness.hpp"

namespace slosh::api {

/// "robustness" of a plan: the report of `report` on the plan's `model` (its f1 is scaled):
///   sweep   {delta_pct: [lo, hi], points: n, zeta, rest_time_s, eta_rest_max_mm,
///            eta_motion_max_mm (null when not given)}
///   points  [{delta_pct, f1_hz, linear: {eta_motion_mm, eta_rest_mm}, nonlinear: {...},
///             holds_linear, holds_nonlinear}], sorted by delta (n points, plus delta = 0 when the
///            grid misses it)
///   holds   {linear, nonlinear}: {from_pct, to_pct, from_is_sweep_end, to_is_sweep_end}, or null
///            when the limits do not hold at delta = 0
///   worst   {linear, nonlinear}: {eta_motion_mm, eta_rest_mm}, the largest over the sweep
[[nodiscard]] nlohmann::json robustness_json(const RobustnessReport& report,
                                             const SloshingModel& model);

/// "uncertainty" of a plan with an active Uncertainty `given` (echoed in the request's units:
/// omega_error_pct, fill_height_mm and viscosity_pa_s, null when not given, sample_points, null
/// unless `samples_read`: the strategy reads it) and the range it implies: omega1_rad_s, f1_hz,
/// scale and zeta, each [lo, hi].
[[nodiscard]] nlohmann::json uncertainty_json(const UncertaintyRange& range,
                                              const Uncertainty& given, bool samples_read);

/// The robustness of a compact plan, from the full plan's "robustness", on the nonlinear model and
/// rounded to hundredths (the compact plan stays under 1 kB): {holds_pct: [from_pct, to_pct] or
/// null, worst_mm: [eta_motion, eta_rest] (the largest over the sweep)}.
[[nodiscard]] nlohmann::json compact_robustness(const nlohmann::json& robustness);

/// The figures of a plan-table row, from the full plan's "robustness" (null when absent):
/// holds_from_pct, holds_to_pct (nonlinear model; null when the limits do not hold at delta = 0)
/// and worst_eta_rest_mm (nonlinear model, the largest over the sweep).
[[nodiscard]] nlohmann::json robustness_row_figures(const nlohmann::json* robustness);

}  // namespace slosh::api
