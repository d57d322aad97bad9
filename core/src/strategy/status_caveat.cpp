#include "status_caveat.hpp"

#include <string_view>

namespace slosh::detail {

namespace {

bool any_with(const std::vector<std::string>& warnings, std::string_view text, bool prefix) {
  for (const std::string& w : warnings) {
    const std::size_t at = w.find(text);
    if (at != std::string::npos && (!prefix || at == 0)) return true;
  }
  return false;
}

}  // namespace

std::string optimal_caveat(const std::vector<std::string>& warnings, Strategy strategy) {
  std::string caveat;
  auto add = [&caveat](const char* reason) {
    caveat += (caveat.empty() ? "" : "; ") + std::string(reason);
  };
  if (any_with(warnings, "liquid will spill", false)) {
    add("the predicted sloshing exceeds the free board (liquid will spill)");
  }
  if (strategy != Strategy::kBaseline) {
    if (any_with(warnings, "worse_than_baseline:", true)) {
      add("the law sloshes more than the uniform law (worse_than_baseline)");
    }
    if (any_with(warnings, "motion too short for the tank:", true)) {
      add("the motion is too short for any law to act on the tank's mode");
    }
  }
  return caveat;
}

void apply_optimal_caveat(SolveStatus& status, std::string& detail,
                          const std::vector<std::string>& warnings, Strategy strategy) {
  if (status != SolveStatus::kOptimal) return;
  const std::string caveat = optimal_caveat(warnings, strategy);
  if (caveat.empty()) return;
  status = SolveStatus::kAcceptable;
  detail = "not optimal: " + caveat + (detail.empty() ? "" : "; " + detail);
}

}  // namespace slosh::detail
