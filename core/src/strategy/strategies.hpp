#pragma once
// The optimising strategies of SPEC §5 and the multi-start machinery they share (internal).

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "solve/duration_space.hpp"

namespace slosh::detail {

/// Wall-clock deadline of a plan.
inline constexpr double kLongestBudget{365.0 * 24.0 * 3600.0};  // [s]
class Deadline {
 public:
  /// `seconds` beyond a year (or infinite) is a year: the clock's integer count cannot hold more.
  /// `stop` (PlanOptions::stop, may be null) set true ends the time at once.
  explicit Deadline(double seconds, const std::atomic<bool>* stop = nullptr)
      : end_(std::chrono::steady_clock::now() +
             std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                 std::chrono::duration<double>(std::min(seconds, kLongestBudget)))),
        stop_(stop) {}
  [[nodiscard]] double remaining() const {
    if (stop_ != nullptr && stop_->load(std::memory_order_relaxed)) return 0.0;
    return std::chrono::duration<double>(end_ - std::chrono::steady_clock::now()).count();
  }
  [[nodiscard]] bool expired() const { return remaining() <= 0.0; }
  /// The stop flag (may be null), for the solvers to read within a run.
  [[nodiscard]] const std::atomic<bool>* stop_flag() const { return stop_; }

 private:
  std::chrono::steady_clock::time_point end_;
  const std::atomic<bool>* stop_;
};

/// What every strategy needs: the problem data, the references its objectives are scaled by, and
/// the deadline.
struct StrategyContext {
  const Format& format;
  const PlanOptions& options;
  const SloshingModel& model;
  DurationSpace space;
  const Deadline& deadline;
  /// X_ref: the uniform law's largest |X| over the band [(1 - band) w1, (1 + band) w1] (SPEC §5
  /// "Reference levels"; |X_uniform(w1)| alone collapses near the uniform law's zeros) [m/s].
  double x_ref{};
  double jerk_ref{};        ///< jerk integral of the uniform law [m^2/s^5]
  double eta_ref{};         ///< nonlinear eta_motion of the uniform law [m]
  double eta_motion_max{};  ///< time_domain kRest bound [m] (option or eta_ref)
  /// The model the spectral strategies and the filters design at: the nominal model, or with an
  /// active uncertainty the middle of its frequency and damping range.
  SloshingModel design_model{};
  /// The models time_domain's constraints hold at and auto judges by: the nominal model alone,
  /// or sample_models() of the uncertainty range.
  std::vector<SloshingModel> sample_models{};
  /// The models a robust plan is verified at: the points of `sweep` (kRobustnessPoints evenly over
  /// the uncertainty range at its least damping, the robustness report's grid); the nominal model
  /// alone otherwise.
  /// time_domain adds a model of it to its sample models where its bound is broken (exchange).
  std::vector<SloshingModel> check_models{};
  /// min_jerk_band's relative half band around design_model.omega1() [-] (the option, widened to
  /// cover the uncertainty range).
  double band{};
  /// multi_notch's relative side-notch offset around design_model.omega1() [-] (the option, or
  /// the uncertainty range's half width when wider).
  double p_notch{};
  /// The uncertainty's range when active.
  std::optional<UncertaintyRange> range{};
  /// With a range: the robustness report's sweep over it (check_models are its points).
  RobustnessSweep sweep{};
  /// band_check_grid of the design band (set_design builds it once per plan).
  std::vector<double> band_grid{};
  /// The uniform law's durations and its prediction on both models at the nominal model, made
  /// once per plan by plan() and shared by everything that needs the uniform law's figures (the
  /// baseline comparison, auto's baseline candidate); null when the caller did not make it.
  const LawPrediction* uniform_prediction{nullptr};
  /// Why a rectangular tank's nonlinear model does not hold for that uniform law (its nonlinear
  /// figures are then the linear model's), or empty.
  std::string uniform_out_of_range{};

  /// A rectangular tank's model (SPEC §15), or null for the cylinder. `model` is then its most
  /// excited direction driven by the motion (driven_directions); the plan's laws are verified
  /// on this model's walls and corners (rectangular_prediction).
  const RectangularModel* rectangular{nullptr};
  /// True when the motion drives both of a turned tank's directions (set_directions): the
  /// strategies act on each direction's first mode (direction_omega, weighed by
  /// direction_weight); design_model, at the middle of the two (reached from the most excited
  /// direction's by direction_engagement), serves min_jerk_band's band and the filters under an
  /// uncertainty range only.
  bool over_directions{false};
  /// Set before set_design: a turned tank's design for its most excited direction alone (as on
  /// the axis), which plan() weighs against the design over both directions on the tank.
  bool one_direction{false};
  /// With over_directions: the two directions' first-mode frequencies [rad/s] and damping ratios
  /// [-], the most excited direction first (the shaper cancels each).
  std::array<double, 2> direction_omega{};
  std::array<double, 2> direction_zeta{};
  /// With over_directions: each direction's first-mode residual gain relative to the most
  /// excited one's (its wave per unit |X_a(omega_1)|: 1, then the other's share) [-].
  std::array<double, 2> direction_weight{1.0, 0.0};
  /// With over_directions: how far the second direction enters the filters' and min_jerk_band's
  /// designs, direction_engagement of its share (1: fully; toward 0 the design nears the most
  /// excited direction's own) [-].
  double direction_engagement{1.0};
  /// With over_directions: the directions' names ("length", "width"), most excited first.
  std::array<const char*, 2> direction_name{"length", "width"};

  /// True when the plan must hold over an uncertainty range.
  [[nodiscard]] bool robust() const { return range.has_value(); }
};

/// Sets the context's design model, sample models, band and p_notch from its options (call once,
/// after construction, before set_references).
void set_design(StrategyContext& context);

/// A tank turned to the motion (both directions excited): each direction's first mode, damping,
/// share and name, the band over both, and time_domain's models (rectangular_plan.cpp).
/// Nothing for a cylinder or a tank square to the motion. Called by set_design.
void set_directions(StrategyContext& context);

/// A first mode a spectral strategy notches: its frequency [rad/s] and weight [-].
struct NotchTarget {
  double omega{};
  double weight{1.0};
  const char* name{nullptr};  ///< the tank direction's name, or null for the one model
};

/// The first modes notch and multi_notch cancel: the design model's, or on a turned tank each
/// excited direction's (at the middle of an uncertainty range's scale), weighed by its share of
/// the residual wave (direction_weight).
[[nodiscard]] std::vector<NotchTarget> notch_targets(const StrategyContext& context);

/// The frequencies the law of `strategy` notches [rad/s]: notch's targets, multi_notch's three
/// per target (empty for the other strategies).
[[nodiscard]] std::vector<double> notched_frequencies(const StrategyContext& context,
                                                      Strategy strategy);

/// The relative half band around the middle of `range` that reaches (1 + band) scale_hi (and
/// covers (1 - band) scale_lo) [-].
[[nodiscard]] double widened_band(double band, const UncertaintyRange& range);

/// Outcome of one strategy, before verification.
struct StrategyOutcome {
  SolveStatus status{SolveStatus::kFailed};
  Durations durations{};
  double objective{};
  int evaluations{};
  int starts{};
  std::string solver;  ///< solver name for the report
  std::string detail;  ///< a sentence about the result (notch depth, best reachable value, ...)
};

/// Best point over several starts: the feasible one with the lowest objective (ties: the earlier
/// start), or the least infeasible when none is feasible.
struct MultiStartResult {
  NlpResult best;
  int best_start{-1};  ///< index of the start whose run gave `best` (-1: none)
  bool feasible{false};
  bool timed_out{false};
  int evaluations{};
  int starts{};
};

/// How a multi-start spends its starts; the default runs every start to its end.
struct StartPolicy {
  /// Leave a run (NLopt) once its point is within kKnownOptimumBasin of the range of every
  /// duration of an optimum an earlier start reached: SLSQP from there ends at that optimum, so
  /// the rest of the run (its last 10-20 % of evaluations) would find nothing new.
  bool leave_known_optima{false};
  /// Starts from this index on are optional: they end after `patience` optional starts in a row
  /// that do not lower the best feasible objective (by more than 1e-9 relative). -1: none.
  int optional_from{-1};
  int patience{2};
  /// The problem is invariant under reversing the order of the 7 durations (its objective and
  /// constraints, as multi_notch's |X|^2 and the machine limits are: the reversed law is the
  /// mirrored motion, A and B swapped): with leave_known_optima, a run is also left at the mirror
  /// image of an optimum already reached, which has the same objective. Used only where the
  /// bounds are symmetric too and the durations are the solver's variables.
  bool mirror_symmetric{false};
  /// With leave_known_optima: a run is also left within this fraction of the range of every
  /// duration of a known optimum at least kPoorOptimum times the lowest one held, once its
  /// objective is within kApproachRatio of that optimum's: it is descending into a basin whose
  /// optimum (or a twin of it next to it) cannot be the answer, and SLSQP's last iterations there
  /// find nothing new. The basins of the low optima keep kKnownOptimumBasin alone (their twins,
  /// a few 1e-4 apart in the objective, decide the answer). 0: off.
  double approach_basin{0.0};
  /// Moves the end point of a run that ended outside the constraints onto what it can reach
  /// without a solve (an epigraph's level raised onto its rows), returning whether it moved; the
  /// run then goes again from there, up to `restarts` times while it stays outside. SLSQP stops
  /// once its objective stalls, also while infeasible: an epigraph level pushed to its lower
  /// bound 0 under rows it does not meet yet stalls there at once. It is given a point of the
  /// full problem (7 durations, then the extra variables) also where multi_start solves in the
  /// one-jerk family's coordinates. Empty: off.
  std::function<bool(std::vector<double>&)> repair;
  int restarts{0};
};

/// Relative distance (of each duration's range) within which a run has reached a known optimum.
inline constexpr double kKnownOptimumBasin{1e-3};
/// See StartPolicy::approach_basin: |f| at most this many times the known optimum's [-].
inline constexpr double kApproachRatio{1.5};
/// ... and only at optima at least this many times the lowest known objective [-].
inline constexpr double kPoorOptimum{10.0};

[[nodiscard]] MultiStartResult multi_start(const NlpProblem& problem,
                                           const std::vector<std::vector<double>>& starts,
                                           const StrategyContext& context,
                                           const NlpOptions& options,
                                           const StartPolicy& policy = {});

/// Why a feasible point of `best` (a run that did not converge, or ended outside its constraint
/// tolerance and was polished onto the admissible set) is only acceptable: "the solver stopped at
/// a point that meets the constraints without converging (<its words>), so the objective may not
/// be minimal", or "the solver ended <v> outside a constraint (<its words>); polished ...". A
/// strategy's outcome leads with it.
[[nodiscard]] std::string not_converged(const NlpResult& best);

/// The outcome of a multi-start: polished best point and translated status (time_limit with the
/// first start when time ran out before any feasible point; infeasible when none was feasible).
[[nodiscard]] StrategyOutcome outcome_from(const MultiStartResult& m,
                                           const StrategyContext& context);

/// Name of the solver a context uses ("nlopt-slsqp" or "ipopt").
[[nodiscard]] std::string solver_name(const StrategyContext& context);

/// The solver settings of time_domain, on a line and along a path: tolerances of 1e-9 of
/// eta / eta_ref (far below a micrometre), 400 iterations.
[[nodiscard]] NlpOptions time_domain_options();

[[nodiscard]] StrategyOutcome solve_notch(const StrategyContext& context);
[[nodiscard]] StrategyOutcome solve_multi_notch(const StrategyContext& context);
/// How notch and multi_notch use their starts: kEconomical (the default) by their StartPolicy
/// (runs left at known optima; notch's random starts only while they find lower optima), kEvery
/// every start to its end (the plain multi-start, the path the tests compare kEconomical with).
enum class StartUse { kEconomical, kEvery };
[[nodiscard]] StrategyOutcome solve_notch(const StrategyContext& context, StartUse uses);
[[nodiscard]] StrategyOutcome solve_multi_notch(const StrategyContext& context, StartUse uses);
[[nodiscard]] StrategyOutcome solve_min_jerk_band(const StrategyContext& context);
/// Which of the n_band rows (and the exchange's points) min_jerk_band's band-constrained solves
/// carry: kActive (the default) those that can be active near the current point, the rest
/// checked at each solution and added when above their bound; kAll every row (the plain
/// formulation, kept as the independent path the tests compare kActive against).
enum class BandRowSelection { kActive, kAll };
[[nodiscard]] StrategyOutcome solve_min_jerk_band(const StrategyContext& context,
                                                  BandRowSelection rows);
/// `seeds` are extra starts (the spectral optima), tried after the uniform law.
[[nodiscard]] StrategyOutcome solve_time_domain(const StrategyContext& context,
                                                const std::vector<Durations>& seeds);

/// Outcome of a filtering strategy (closed form, no solver): kOptimal when the law meets every
/// limit and option that applies to it, kInfeasible otherwise (the law is still returned, or the
/// uniform law when none exists).
struct FilterOutcome {
  SolveStatus status{SolveStatus::kFailed};
  MotionLaw law;
  std::optional<Durations> durations;
  std::optional<FilterDesign> design;
  std::string detail;  ///< how the law was built, or why it does not meet the constraints
};

[[nodiscard]] FilterOutcome design_fir_chain(const StrategyContext& context);
[[nodiscard]] FilterOutcome design_shaper(const StrategyContext& context);
[[nodiscard]] FilterOutcome design_iir(const StrategyContext& context);

/// When the machine limits alone cannot be met, a sentence naming the first unreachable limit and
/// the least value reachable; empty when the limits are jointly reachable.
[[nodiscard]] std::string explain_limits(const StrategyContext& context);

/// The first machine limit that the peaks exceed by more than `slack` (relative), as a sentence
/// ("the law's peak velocity 1.4 m/s exceeds limits.v_max = 1 m/s"); empty when all hold.
[[nodiscard]] std::string limit_violation(const MachineLimits& limits, double a_peak, double v_peak,
                                          double j_peak, double slack);

/// min z s.t. every quantity of the limit rows [first, first + rows) is <= z times its limit,
/// from the space's starts: best.objective <= 1 when those limits hold together (best.x then
/// meets them).
[[nodiscard]] MultiStartResult least_limit_scale(const StrategyContext& context, int first,
                                                 int rows);

/// Band frequencies of min_jerk_band [rad/s].
[[nodiscard]] std::vector<double> band_frequencies(double omega1, double band, int count);

/// The largest |X| of a 7-segment law over the continuous band: on `grid` (sorted), then by
/// golden section around every local maximum of it.
struct BandPeak {
  double value{};  ///< |X| [m/s]
  double omega{};  ///< where [rad/s]
};
[[nodiscard]] BandPeak band_peak(const Durations& d, double stroke,
                                 const std::vector<double>& grid);

/// Relative excess of the band maximum over tol_rel X_ref that still meets the band [-].
inline constexpr double kBandTolerance{1e-6};

/// "|X| <= 20 % of X_ref on the band is not reachable in 1.04 s: the best is 34 % ...".
[[nodiscard]] std::string band_limit_sentence(const StrategyContext& context, double best_ratio);

/// The grid band_peak checks min_jerk_band's band on: the context's band around its design
/// frequency (its band_grid, built once by set_design).
[[nodiscard]] const std::vector<double>& band_check_grid(const StrategyContext& context);
/// The same grid for the band (1 -+ band) omega checked from n_band points.
[[nodiscard]] std::vector<double> band_check_grid(double omega, double band, int n_band);

/// Sets the context's reference levels (x_ref, jerk_ref, eta_ref, eta_motion_max); eta_ref is
/// the uniform law's nonlinear eta_motion, given by the caller (it has simulated that law).
void set_references(StrategyContext& context, double eta_ref);

/// The constraint of the context's strategy the 7-segment law `d` violates, judged on the
/// verification of SPEC §2 (machine limits; the band of min_jerk_band on band_check_grid; the
/// eta bound of time_domain on the dense nonlinear response, whose peaks are `verified`): a
/// sentence naming the constraint, its limit and the value reached; empty when every constraint
/// holds.
[[nodiscard]] std::string violated_constraint(const StrategyContext& context, Strategy strategy,
                                              const Durations& d, const SloshPeaks& verified);

/// Starts as solver vectors.
[[nodiscard]] std::vector<std::vector<double>> as_vectors(const std::vector<Durations>& starts);

/// Both models' peaks of a prediction during and after the motion [m], in the order the
/// `worse_than_baseline` warning names them (nonlinear, then linear).
struct PeakFigures {
  double nonlinear_motion, nonlinear_rest, linear_motion, linear_rest;
};

template <class Prediction>
PeakFigures peak_figures(const Prediction& p) {
  return {p.nonlinear.motion.value, p.nonlinear.rest.value, p.linear.motion.value,
          p.linear.rest.value};
}

/// The figures of `law` above `reference` by more than 5 % and by more than 0.5 mm (SPEC §5
/// "Honest status"), each named with both values ("eta_rest (nonlinear) 3.1 mm vs 2.0 mm, ..."),
/// or empty: the test of every `worse_than_baseline` warning, on a line or along a path.
/// `linear_only`: the two laws' nonlinear figures do not come from one model (a rectangular
/// tank's nonlinear model holds for one of them only), so only the linear figures are compared.
[[nodiscard]] std::string worse_figures(const PeakFigures& law, const PeakFigures& reference,
                                        bool linear_only = false);

/// What a `worse_than_baseline` warning adds when it compared the linear figures alone.
inline constexpr const char* kWorseOnLinearModel =
    " (the linear figures alone: the rectangular nonlinear model holds for one of the two laws "
    "only)";

/// choose_auto on one model: as it is when the candidates' nonlinear figures all come from one
/// model; else (`in_range[k]` false: a rectangular tank's nonlinear model does not hold for
/// candidate k's law, whose nonlinear figures are then the linear model's) on every candidate's
/// linear figures, those of its worst case included, with `ranked_on_linear` set and " (linear
/// model)" after every loss that compared figures.
[[nodiscard]] AutoChoice choose_on_one_model(const std::vector<PlanCandidate>& candidates,
                                             const std::vector<bool>& in_range,
                                             const std::vector<bool>& worse_than_baseline,
                                             const std::vector<BoundVerdict>& bounds);

/// What auto's sentence adds when it ranked its candidates on the linear model.
inline constexpr const char* kRankedOnLinearModel =
    "; ranked on the linear model: the rectangular nonlinear model does not hold for every "
    "candidate's law";

/// The warnings on the uniform law of reference when a rectangular tank's nonlinear model does
/// not hold for it or for the law (`*_in_range` false: its nonlinear figures are the linear
/// model's; `reference_reason` says why for the uniform law): `reference_nonlinear_model_not_valid`
/// when the uniform law is out of range, and `reductions_on_linear_model`, naming both laws'
/// linear figures, when exactly one of them is (the reductions then compare those). Empty when
/// both figures come from one model. On a line or along a path alike.
[[nodiscard]] std::vector<Warning> reference_model_warnings(bool law_in_range,
                                                            const std::string& reference_reason,
                                                            const PeakFigures& law,
                                                            const PeakFigures& reference);

}  // namespace slosh::detail
