#pragma once

#include <string>
#include <vector>

#include "slosh/core/strategy/planner.hpp"
#include "slosh/core/warning.hpp"

namespace slosh::detail {

/// Why a plan whose law meets its constraints is still not `optimal`: the reasons of its
/// warnings' kinds whose StatusEffect applies to `strategy` (warning_kinds(); the uniform law,
/// `strategy` baseline, reduces nothing by definition, so only the kinds that are the law's own
/// outcome count for it), each once, in the table's order. Empty when none applies.
std::string optimal_caveat(const std::vector<Warning>& warnings, Strategy strategy);

/// SPEC §5 "Honest status": an `optimal` plan with a caveat becomes `acceptable` (its
/// constraints still hold), and the `detail` of such a plan, or of one `acceptable` already,
/// leads with "not optimal: <caveat>" (once).
void apply_optimal_caveat(SolveStatus& status, std::string& detail,
                          const std::vector<Warning>& warnings, Strategy strategy);

}  // namespace slosh::detail
