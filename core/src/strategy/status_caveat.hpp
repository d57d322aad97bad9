#pragma once

#include <string>
#include <vector>

#include "slosh/core/strategy/planner.hpp"

namespace slosh::detail {

/// Why a plan whose law meets its constraints is still not `optimal`, from its warnings: the
/// liquid spills over the free board, the law sloshes more than the uniform law
/// (worse_than_baseline), or the motion is too short for any law to act on the tank's mode (a
/// plan of a shaping strategy then promises nothing). Empty when none holds. The uniform law
/// (`strategy` baseline) reduces nothing by definition, so only the spill counts for it.
std::string optimal_caveat(const std::vector<std::string>& warnings, Strategy strategy);

/// SPEC §5 "Honest status": an `optimal` plan with a caveat becomes `acceptable` (its
/// constraints still hold) and `detail` leads with the caveat.
void apply_optimal_caveat(SolveStatus& status, std::string& detail,
                          const std::vector<std::string>& warnings, Strategy strategy);

}  // namespace slosh::detail
