#pragma once
// Minimum motion time (SPEC §9): the shortest motion time T, on a 1 ms grid, at which a strategy's
// verified plan meets the sloshing limits (eta_motion, eta_rest) and the machine limits. Pure
// numerics: no JSON, no logging. Every candidate T is judged on what plan() returns for it (its
// status and its predictions on the dense accurate simulation), never on an optimiser's grid.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "slosh/core/enum_names.hpp"
#include "slosh/core/invalid_input.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh {

/// Which model the sloshing limits of the search apply to.
enum class LimitModel {
  kNonlinear,  ///< the nonlinear fundamental-mode model (the one the thesis validated)
  kLinear,     ///< the multi-mode linear model
  kBoth,       ///< the larger of the two predictions
};

template <>
struct EnumNames<LimitModel> {
  static constexpr std::array<EnumName<LimitModel>, 3> table{{
      {LimitModel::kNonlinear, "nonlinear"},
      {LimitModel::kLinear, "linear"},
      {LimitModel::kBoth, "both"},
  }};
};
[[nodiscard]] inline std::string to_string(LimitModel value) {
  return std::string(name_of(value));
}

/// Default upper end of the search [s].
inline constexpr double kDefaultMotionTimeMax{5.0};
/// Default margin kept below the free board when eta_motion_max is not given [m].
inline constexpr double kDefaultFreeBoardMargin{0.005};
/// Grid of T_min [s].
inline constexpr double kMinTimeResolution{1e-3};

/// Options of min_time(). Defaults are SPEC §9's.
struct MinTimeOptions {
  /// The options every plan of the search runs with: the strategy's options, the machine limits
  /// (plan.limits), the rest window. plan.eta_rest_max is overwritten by eta_rest_max below (so
  /// time_domain plans for the search's limit); plan.time_limit is the wall-clock budget of the
  /// whole search of one strategy [s] (default 5 s); each plan gets what remains of it.
  PlanOptions plan;
  /// Upper end of the search [s]: no T above it is tried. Default 5 s; (0, 3600].
  double motion_time_max{kDefaultMotionTimeMax};
  /// Largest eta_motion [m]. Default: the free board, container height - fill height -
  /// free_board_margin; required when the container height is not given. (0, 10] m.
  std::optional<double> eta_motion_max;
  /// Margin below the free board for the default eta_motion_max [m]. Default 5 mm; [0, 10] m.
  double free_board_margin{kDefaultFreeBoardMargin};
  /// Largest eta_rest over the rest window (plan.rest_time) [m]. Default 3 mm; (0, 10] m.
  double eta_rest_max{0.003};
  /// The model the two eta limits apply to. Default kNonlinear.
  LimitModel model{LimitModel::kNonlinear};
  /// Step of the coarse scan up from the lower bound [s]. Default 40 ms; [1 ms, 1 s].
  double scan_step{0.04};
  /// A scanned local minimum of the excess (max of eta / its limit over both limits) at or below
  /// this is refined by a golden-section search on the 1 ms grid between its two neighbours,
  /// until a feasible T is found or the bracket is 2 ms; a warm-started plan below the least
  /// feasible T so far whose excess is above this is kept without a plan from the planner's own
  /// starts (a far miss, see min_time()) [-]. Default 2; [1, 1000].
  double refine_excess{2.0};
  /// Most plans solved by one strategy's search (scan, bisection and curve) [-]. Default 40;
  /// [3, 10000]. When it runs out the result is kTimeLimit: before T_min is bracketed to 1 ms
  /// with the best bound so far; after that with T_min (t_min_final) and a partial curve.
  int max_plans{40};
  /// The curve of eta over T reaches this factor times T_min [-]. Default 1.5; [1, 10].
  double curve_factor{1.5};
  /// The path the law moves along (SPEC §14: a rotary table's arc, a track's curves); unset: the
  /// straight line of the format's stroke. With a path every T is planned by plan_on_path (the
  /// format's stroke is the path's length): the eta limits apply to the planar models' peaks,
  /// maximised over the wall, and the machine limits to the path (a_max on the total horizontal
  /// acceleration, v_max on s', j_max on the tangential jerk). With plan.robustness the
  /// returned plan's report sweeps the planar models (robustness_report_on_path).
  std::optional<PlanarPath> path;

  /// eta_motion_max, or its default from the free board; nullopt when neither is available.
  [[nodiscard]] std::optional<double> eta_motion_limit(const Format& format) const;
  /// The first option outside its allowed set for `format` (motion_time ignored: the plan
  /// options are checked at motion_time_max), naming the option, its value and the allowed set
  /// in core names and SI units; nullopt when all hold.
  [[nodiscard]] std::optional<InvalidInput> validate(const Format& format) const;
};

/// The motion time the plan options of a search are validated at [s]: motion_time_max, or what
/// the ramps and plateau minimums of `plan` need (4 min_ramp + plateau minimums) when that is
/// longer. A search range shorter than the ramps is no invalid option but an empty search
/// (min_time() answers kInfeasible, naming the time they need).
[[nodiscard]] double plan_validation_time(double motion_time_max, const PlanOptions& plan);

/// Closed-form minimum time of a rest-to-rest move of `stroke` [m] under symmetric limits on
/// |acceleration| `a_max` [m/s^2], |velocity| `v_max` [m/s] and |jerk| `j_max` [m/s^3] (an unset
/// limit is unbounded): the time-optimal jerk-limited (7-segment, "double S") profile. 0 when no
/// limit is set. Every law the planner can return obeys the same limits, so no plan exists below
/// it [s].
[[nodiscard]] double kinematic_lower_bound(double stroke, const MachineLimits& limits);

/// The same bound along `path` [s]: the tangential motion obeys the line's limits over the path
/// length (|s''| is at most the total horizontal acceleration); on a path of arcs only, where the
/// normal acceleration s'^2 / rho <= a_max holds everywhere, the speed is also at most
/// sqrt(a_max rho_min).
[[nodiscard]] double kinematic_lower_bound(const PlanarPath& path, const MachineLimits& limits);

/// One T the search planned, with the verified predictions of its plan.
struct MinTimePoint {
  double motion_time{};  ///< T [s]
  SolveStatus plan_status{SolveStatus::kFailed};
  bool feasible{false};      ///< the plan is optimal/acceptable and meets both eta limits
  LawPrediction prediction;  ///< of the plan's law (zero when the plan refused its inputs)
  double eta_motion{};       ///< eta_motion on the limit model [m]
  double eta_rest{};         ///< eta_rest on the limit model [m]
  /// max(eta_motion / eta_motion_max, eta_rest / eta_rest_max) [-]; infinity for a plan that
  /// refused its inputs. Feasible points have <= 1.
  double excess{};
  /// Along a path with limits.a_max: the plan law's largest total horizontal acceleration
  /// sqrt(s''^2 + (s'^2/rho)^2) over a_max [-] (> 1: the law breaks the machine limit); 0 on a
  /// line or without a_max. For the same law shape stretched to T' it scales as (T/T')^2, which
  /// the scan uses to step past motion times where the law cannot meet a_max.
  double a_max_ratio{};
  /// The PlanOptions::warm_start this T was planned with (the durations of a neighbouring
  /// point; see min_time()); nullopt: planned from the planner's own starts. plan() of the format
  /// at motion_time with the search's plan options and this warm start returns the same plan.
  std::optional<Durations> warm_start;
  /// The plan's seven durations, when its law is a 7-segment law [s].
  std::optional<Durations> durations;
  /// A rectangular tank's nonlinear model did not hold for the plan's law: its nonlinear figures
  /// (and eta_motion, eta_rest on that model) are the linear ones standing in.
  bool linear_stood_in{false};
};

/// One strategy's search.
struct MinTimeResult {
  Strategy strategy{};
  /// kOptimal: T_min found (t_min; the plan at T_min) and the curve planned up to curve_factor
  /// T_min. kAcceptable: the same, but the plan at T_min is not optimal by its own warnings
  /// (not_optimal; SPEC §5 "Honest status"), and the message leads with "not optimal: ...".
  /// kInfeasible: no T from the lower bound to motion_time_max met the limits (best: the least
  /// excess reached, with its plan). kTimeLimit: the budget (time or max_plans) ran out; t_min,
  /// when set, is the best bound so far (a feasible T; the true T_min is at or below it), or T_min
  /// itself when t_min_final (the budget ran out on the curve above it, which is then partial; the
  /// message says so). kFailed: invalid input (invalid_input) or a plan that failed.
  SolveStatus status{SolveStatus::kFailed};
  std::optional<InvalidInput> invalid_input;
  std::string message;
  /// The limits the search applied [m].
  double eta_motion_max{};
  double eta_rest_max{};
  /// kinematic_lower_bound of the stroke and machine limits [s].
  double kinematic_bound{};
  /// First T scanned: the kinematic bound raised to the durations' admissibility (4 min_ramp +
  /// plateau minimums) and rounded up to the 1 ms grid [s].
  double scan_start{};
  /// The smallest feasible T found on the 1 ms grid [s] (see status).
  std::optional<double> t_min;
  /// The largest T planned below t_min that was infeasible (t_min - 1 ms after the bracketing);
  /// nullopt when t_min is the scan start (nothing below it was planned) [s].
  std::optional<double> infeasible_below;
  /// T_min is final: bracketed to 1 ms (infeasible_below is t_min - 1 ms, infeasible from the
  /// planner's own starts) or the scan start. Always for kOptimal; for kTimeLimit when the budget
  /// ran out only while the curve above T_min was planned (else t_min is a bound).
  bool t_min_final{false};
  /// Every T planned above t_min, up to curve_factor t_min, was feasible (false: a T above it is
  /// infeasible from the planner's own starts, so the feasible set is not an interval there, e.g.
  /// the residual wave of the uniform law has zeros). Nullopt without t_min, and when the budget
  /// ran out before the curve reached curve_factor t_min and no T above it had failed.
  std::optional<bool> feasible_above;
  /// Why the plan at t_min is not optimal (its warnings' caveat, e.g. "the predicted sloshing
  /// exceeds the free board (liquid will spill)": the limits hold on the limit model while the
  /// larger model spills); empty when it is, and without t_min.
  std::string not_optimal;
  /// The plan at t_min; for kInfeasible the plan of the best point reached.
  std::optional<PlanResult> plan;
  /// kInfeasible: the point of least excess reached.
  std::optional<MinTimePoint> best;
  /// Every planned T with finite predictions, ascending (the eta curve over T for plots;
  /// includes the bracketing points; a plan that refused its inputs or whose model diverged has
  /// no point here, though it counts in `plans`; nor has a warm-started plan above t_min that
  /// missed the limits above the first T that misses them from the planner's own starts, or
  /// that the budget left unconfirmed: see min_time()).
  std::vector<MinTimePoint> curve;
  int plans{};         ///< plan() calls
  double search_ms{};  ///< wall-clock time of the search [ms]
};

/// Searches the minimum motion time of `strategy` (not kAuto) for `format` (its motion_time is
/// ignored): lower bound from the stroke and the machine limits, a coarse scan up in steps of
/// scan_step, a bracketing search (regula falsi on the excess, safeguarded by bisection) to 1 ms
/// between the last infeasible and the first feasible scanned T, then the scan continued up to
/// curve_factor T_min for the curve and feasible_above. Deterministic.
/// Warm starts (the optimising strategies): a T where the plan is likely feasible (above the
/// least feasible T found so far) or far from the limits (the scan while its excess, extrapolated,
/// stays above refine_excess) is planned from the durations of a planned neighbour (the nearest
/// planned T below and above it, the one of lower excess; ties: below), recorded in its
/// MinTimePoint; every other T (the first, next to a near miss, the refinement and the
/// bracketing) from the planner's own starts. A warm-started plan that is infeasible is planned
/// again from the planner's own starts and that plan kept (its warm_start then nullopt), so an
/// infeasible point is infeasible from the planner's own starts (what a plan request at that T
/// does), except a far miss of the scan: below every feasible T found so far, a plan warm-started
/// from a far miss that misses the limits by more than refine_excess is kept as it is. Above
/// T_min one T failing from the planner's own starts decides feasible_above: the warm-started
/// failures there are planned again in ascending T only until one fails from the planner's own
/// starts too, and those above it are left off the curve (counted in `plans`).
[[nodiscard]] MinTimeResult min_time(const Format& format, Strategy strategy,
                                     const MinTimeOptions& options);

/// The headline over several strategies' searches.
struct MinTimeSummary {
  /// Index of the strategy with the least t_min among the results whose t_min is final (kOptimal,
  /// kAcceptable, or kTimeLimit with a partial curve) or a bound (kTimeLimit before T_min was
  /// final, with a usable plan at it; ties: the first), taken among those whose plan at t_min is
  /// optimal (empty not_optimal; a bound's plan itself optimal) when there is one; nullopt when
  /// none found one.
  std::optional<std::size_t> winner;
  /// The winner's t_min is a bound: its search ran out of budget before T_min was final (the line
  /// can run at it; the true minimum is at or below it).
  bool winner_bound{false};
  /// The winner's not_optimal when every final t_min's plan is not optimal; empty otherwise.
  std::string winner_not_optimal;
  /// The uniform law's (baseline) result index when it was searched and found a final T_min.
  std::optional<std::size_t> baseline;
  /// 100 (T_baseline - T_winner) / T_baseline [%], when both exist.
  std::optional<double> gain_pct;
  /// 60 / T_winner - 60 / T_baseline: motions per minute gained (motion time only) [1/min].
  std::optional<double> gain_cycles_per_min;
};

[[nodiscard]] MinTimeSummary summarize_min_time(const std::vector<MinTimeResult>& results);

}  // namespace slosh
