#pragma once
// Every kind of warning a plan can carry in "warnings", in one table: the compact view's codes,
// the OpenAPI description of the member and the planner's own texts all come from it, so a new
// kind is documented where it is added.

#include <span>
#include <string_view>

namespace slosh::api {

/// One kind of plan warning.
struct PlanWarningKind {
  /// The code: what the compact view lists for such a warning.
  std::string_view code;
  /// How the warning's text begins (the validity sentences of SPEC §2; "<code>: " for the kinds
  /// whose text leads with its code).
  std::string_view prefix;
  /// When it is given, for the OpenAPI description.
  std::string_view meaning;
};

/// The time_limited_candidates warning's code: an auto plan with a candidate out of its budget.
inline constexpr std::string_view kTimeLimitedCandidates = "time_limited_candidates";

/// Every kind, in the order the OpenAPI description lists them.
[[nodiscard]] std::span<const PlanWarningKind> plan_warning_kinds();

}  // namespace slosh::api
