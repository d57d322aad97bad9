#pragma once
// Starts that keep the machine limits: the limits a plan can keep (the options' own where they
// are reachable, else the least reachable values) and each start moved onto the set they admit
// before a strategy solves from it (internal to the core).

#include <vector>

#include "strategy/strategies.hpp"

namespace slosh::detail {

/// The limits a strategy holds and its starts inside them.
struct AdmissibleStarts {
  /// The options' machine limits; a limit that cannot be met (with the others) raised to the
  /// least value reachable, so a law that keeps `limits` is as close to the options as any.
  MachineLimits limits;
  /// True when `limits` differ from the options' (some limit is not reachable).
  bool relaxed{false};
  /// The starts, each projected onto the set `limits` admit (bounds, sum T, every limit): a start
  /// inside is kept as it is, one outside is moved to the nearest admissible point (least sum of
  /// squared duration changes). Distinct, in the order of the starts given.
  std::vector<Durations> starts;
};

/// Relative excess over a machine limit a point that keeps it may have: the solvers' feasibility
/// tolerance (10 x NlpOptions::constraint_tolerance), far below the verification's 1e-6 [-].
inline constexpr double kLimitSlack{1e-8};

/// True when the durations keep every limit of `limits` to `slack` (relative) [-].
[[nodiscard]] bool keeps_limits(const DurationSpace& space, const MachineLimits& limits,
                                const Durations& d, double slack);

/// The limits the context can keep and `starts` projected onto the set they admit. Without
/// machine limits, or with every start inside them, the starts are returned as they are and no
/// solver runs.
[[nodiscard]] AdmissibleStarts admissible_starts(const StrategyContext& context,
                                                 const std::vector<Durations>& starts);

/// `starts` and, for a fresh plan (no warm start), the design space's symmetric families and
/// `random` seeded random starts (DurationSpace::starts), each moved onto the set the machine
/// limits admit and added once: where a time-domain search from its first starts falls short.
[[nodiscard]] std::vector<Durations> with_families(const StrategyContext& context,
                                                   std::vector<Durations> starts, int random);

}  // namespace slosh::detail
