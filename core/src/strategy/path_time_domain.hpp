#pragma once
// time_domain along a planar path (internal to the core): min eta_motion s.t. eta_rest <= bound
// (or the reverse) on the planar nonlinear model, the height maximised over the wall, with exact
// gradients from PlanarSensitivity; the machine limit on the total horizontal acceleration as
// sampled constraints closed by exchange.

#include <vector>

#include "slosh/core/motion/planar_path.hpp"
#include "strategy/strategies.hpp"

namespace slosh::detail {

/// `c` is the context of the format whose stroke is the path length (its eta_ref the uniform
/// law's planar nonlinear eta_motion); `seeds` extra starts after the uniform law.
[[nodiscard]] StrategyOutcome solve_path_time_domain(const StrategyContext& c,
                                                     const PlanarPath& path,
                                                     const std::vector<Durations>& seeds);

}  // namespace slosh::detail
