#include "status_caveat.hpp"

namespace slosh::detail {

std::string optimal_caveat(const std::vector<Warning>& warnings, Strategy strategy) {
  std::string caveat;
  for (const WarningKindInfo& info : warning_kinds()) {
    const bool bounded = strategy == Strategy::kTimeDomain || strategy == Strategy::kAuto;
    const bool applies = info.effect == StatusEffect::kNotOptimal ||
                         (info.effect == StatusEffect::kNotOptimalExceptBaseline &&
                          strategy != Strategy::kBaseline) ||
                         (info.effect == StatusEffect::kNotOptimalWhenBounded && bounded);
    if (!applies || !has_warning(warnings, info.kind)) continue;
    caveat += (caveat.empty() ? "" : "; ") + std::string(info.reason);
  }
  return caveat;
}

void apply_optimal_caveat(SolveStatus& status, std::string& detail,
                          const std::vector<Warning>& warnings, Strategy strategy) {
  // An acceptable plan (a local solve's, a spectral law's) says it as well: whatever made it
  // acceptable, a spill or a wave deeper than the fill is what the line engineer must read first.
  if (status != SolveStatus::kOptimal && status != SolveStatus::kAcceptable) return;
  const std::string caveat = optimal_caveat(warnings, strategy);
  if (caveat.empty() || detail.starts_with("not optimal: ")) return;
  status = SolveStatus::kAcceptable;
  detail = "not optimal: " + caveat + (detail.empty() ? "" : "; " + detail);
}

}  // namespace slosh::detail
