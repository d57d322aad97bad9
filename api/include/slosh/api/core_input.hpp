#pragma once
// The one mapping from the core's inputs (PlanInput, core names, SI) to the request's fields and
// the API's wording of a refusal (field names, mm, the texts the API has always returned).

#include <string>
#include <string_view>

#include "slosh/core/invalid_input.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh::api {

/// The request an input is read from: where it sits differs (rest_time_s is top level in a
/// simulate request, under options in a plan request).
enum class Endpoint { kPlan, kSimulate };

/// The request field of `input`, e.g. kMinRamp -> "options.min_ramp_s", kAMax ->
/// "options.limits.a_max", kContainerRadius -> "format.container.radius_mm"; the derived inputs
/// (model, uniform response, reference levels) are "format", the relation of the ramp and plateau
/// floors is "options".
[[nodiscard]] std::string_view api_field_path(PlanInput input, Endpoint endpoint = Endpoint::kPlan);

/// The request field of a plan option the core refused after the API's ranges passed: the
/// option's own path where it has one (options.drive_profile, options.uncertainty.<member>; a
/// band the uncertainty range widens to 0 Hz: the member that spreads omega_1), else "options"
/// (a relation between options, e.g. ramps and plateau minimums longer than T).
[[nodiscard]] std::string options_field(const InvalidInput& invalid, const PlanOptions& options);

/// The request path of the range an active `uncertainty` was given by
/// ("options.uncertainty.omega_error_pct", "...fill_height_mm" or "...viscosity_pa_s", the first
/// given): what a refusal of the whole range names, so that a recipe table names its column.
[[nodiscard]] std::string uncertainty_range_field(const Uncertainty& uncertainty);

/// The API's sentence for a refused input, as the API words it (its field names, mm for eta).
/// `format` and `options` are the request's (the relation of the floors quotes them).
[[nodiscard]] std::string input_sentence(const InvalidInput& invalid, const Format& format,
                                         const PlanOptions& options);

/// The message of a plan the planner refused: "invalid input: <sentence>; nothing was planned".
[[nodiscard]] std::string plan_refusal(const InvalidInput& invalid, const Format& format,
                                       const PlanOptions& options);

/// The message of a simulation the core refused: "<field> is refused by the simulation: <core
/// sentence>".
[[nodiscard]] std::string simulate_refusal(const InvalidInput& invalid);

}  // namespace slosh::api
