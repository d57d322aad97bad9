#pragma once
// Every kind of warning a plan can carry in "warnings": core's one table (slosh/core/warning.hpp),
// from which the full plan's warning_codes, the compact view's codes, the OpenAPI description of
// the member and the honest status all come, so a new kind is documented where it is added.

#include <span>
#include <string_view>

#include "slosh/core/warning.hpp"

namespace slosh::api {

/// One kind of plan warning: its code, how its sentence begins, what it means.
using PlanWarningKind = WarningKindInfo;

/// The time_limited_candidates warning's code: an auto plan with a candidate out of its budget.
inline constexpr std::string_view kTimeLimitedCandidates = "time_limited_candidates";

/// Every kind, in the order the OpenAPI description lists them.
[[nodiscard]] std::span<const PlanWarningKind> plan_warning_kinds();

}  // namespace slosh::api
