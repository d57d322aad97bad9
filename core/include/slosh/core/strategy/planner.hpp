#pragma once
// The planner: a format, a strategy and options in, the optimised 7-segment law (or a filtered law
// of the JDSMC paper) with its verified sloshing predictions out (SPEC §5-§6). Pure numerics: no
// JSON, no logging.

#include <array>
#include <atomic>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "slosh/core/enum_names.hpp"
#include "slosh/core/invalid_input.hpp"

#include "slosh/core/law/filtered_laws.hpp"
#include "slosh/core/law/move_absolute.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/model/uncertainty.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/solve/nlp_solver.hpp"
#include "slosh/core/strategy/path_report.hpp"
#include "slosh/core/strategy/robustness.hpp"
#include "slosh/core/warning.hpp"

namespace slosh {

/// What the caller optimises (SPEC §5).
enum class Strategy {
  kBaseline,     ///< uniform durations T/7, no optimisation
  kNotch,        ///< |X(w1)|^2 -> 0; among the zeros, the least jerk integral
  kMultiNotch,   ///< b1 |X(w-)|^2 + b2 |X(w1)|^2 + b3 |X(w+)|^2, w+- = (1 +- p) w1
  kMinJerkBand,  ///< min int j^2 dt s.t. |X(w)| <= tol_rel X_ref on the band around w1
  kTimeDomain,   ///< min eta_motion (or eta_rest) of the nonlinear model, constraint on the other
  kFirChain,     ///< three rectangular FIR filters on a step, T3 = damped period (JDSMC sec. 3.4)
  kShaper,       ///< base law of duration T - delay convolved with an input shaper (sec. 3.1, 4)
  kIir,          ///< base law through the IIR filter of eq. 8/9, delay compensated (sec. 3.3, 4)
  kAuto,         ///< run the others (not iir), verify each, pick by SPEC §5's rule
};

template <>
struct EnumNames<Strategy> {
  static constexpr std::array<EnumName<Strategy>, 9> table{{
      {Strategy::kBaseline, "baseline"},
      {Strategy::kNotch, "notch"},
      {Strategy::kMultiNotch, "multi_notch"},
      {Strategy::kMinJerkBand, "min_jerk_band"},
      {Strategy::kTimeDomain, "time_domain"},
      {Strategy::kFirChain, "fir_chain"},
      {Strategy::kShaper, "shaper"},
      {Strategy::kIir, "iir"},
      {Strategy::kAuto, "auto"},
  }};
};
[[nodiscard]] inline std::string to_string(Strategy value) {
  return std::string(name_of(value));
}
/// Strategy from its API name ("baseline", "notch", ...); nullopt when unknown.
[[nodiscard]] inline std::optional<Strategy> parse_strategy(std::string_view name) {
  return enum_from_name<Strategy>(name);
}

/// Objective of the time-domain strategy.
enum class TimeDomainObjective {
  kMotion,  ///< minimise eta_motion subject to eta_rest <= eta_rest_max (thesis sec. 3.4.3)
  kRest,    ///< minimise eta_rest subject to eta_motion <= eta_motion_max
};
template <>
struct EnumNames<TimeDomainObjective> {
  static constexpr std::array<EnumName<TimeDomainObjective>, 2> table{{
      {TimeDomainObjective::kMotion, "motion"},
      {TimeDomainObjective::kRest, "rest"},
  }};
};
[[nodiscard]] inline std::string to_string(TimeDomainObjective value) {
  return std::string(name_of(value));
}

/// Which NLP solver runs a strategy.
enum class SolverChoice {
  kAuto,   ///< the measured best per strategy (NLopt SLSQP everywhere, see planner.cpp)
  kNlopt,  ///< NLopt SLSQP
  kIpopt,  ///< Ipopt, interior point with limited-memory BFGS
};

template <>
struct EnumNames<SolverChoice> {
  static constexpr std::array<EnumName<SolverChoice>, 3> table{{
      {SolverChoice::kAuto, "auto"},
      {SolverChoice::kNlopt, "nlopt"},
      {SolverChoice::kIpopt, "ipopt"},
  }};
};
[[nodiscard]] inline std::string to_string(SolverChoice value) {
  return std::string(name_of(value));
}

/// What the drive runs (SPEC §11).
enum class DriveProfile {
  kFree,          ///< any 7-segment law: four ramp jerks of their own (a cam table runs it)
  kMoveAbsolute,  ///< one jerk J for the four ramps, dT1 = dT3 = A / J, dT5 = dT7 = B / J: what a
                  ///< PLCopen MC_MoveAbsolute block with a jerk limit runs
};
template <>
struct EnumNames<DriveProfile> {
  static constexpr std::array<EnumName<DriveProfile>, 2> table{{
      {DriveProfile::kFree, "free"},
      {DriveProfile::kMoveAbsolute, "move_absolute"},
  }};
};
[[nodiscard]] inline std::string to_string(DriveProfile value) {
  return std::string(name_of(value));
}

/// Machine limits; an unset limit is not enforced.
struct MachineLimits {
  std::optional<double> a_max;  ///< peak |acceleration| = max(A, B) [m/s^2]
  std::optional<double> v_max;  ///< peak velocity [m/s]
  std::optional<double> j_max;  ///< peak |jerk| over the four ramps [m/s^3]
};

/// Options of plan(). Defaults are the thesis' settings (SPEC §5).
struct PlanOptions {
  /// Sloshing model: modes of the linear model, damping correlation, alpha.
  ModelOptions model;
  /// Relative offset p of the side notches of multi_notch, w+- = (1 +- p) w1 [-]. Default 0.15.
  double p_notch{0.15};
  /// Weights b1, b2, b3 of multi_notch on |X(w-)|^2, |X(w1)|^2, |X(w+)|^2 [-]. Default 1, 1, 1.
  std::array<double, 3> weights{1.0, 1.0, 1.0};
  /// Half width of the min_jerk_band band relative to w1 [-]: [(1 - band) w1, (1 + band) w1].
  /// Default 0.15.
  double band{0.15};
  /// Number of evenly spaced band frequencies the min_jerk_band constraint starts from [-]. The
  /// planner adds points where a 16x finer check finds the band exceeded. Default 51.
  int n_band{51};
  /// Band tolerance relative to X_ref, the uniform law's largest |X| over the band (SPEC §5
  /// "Reference levels") [-]. Default 0.2.
  double tol_rel{0.2};
  /// Largest eta_rest of time_domain with objective kMotion [m]. Default 3 mm.
  double eta_rest_max{0.003};
  /// Largest eta_motion of time_domain with objective kRest [m]. Default: the uniform law's
  /// nonlinear eta_motion (never slosh more during the move than the baseline).
  std::optional<double> eta_motion_max;
  /// Objective of time_domain. Default kMotion.
  TimeDomainObjective objective{TimeDomainObjective::kMotion};
  /// Rest window after the motion [s]. Default 1 s.
  double rest_time{kDefaultRestTime};
  /// Minimum duration of the ramps 1, 3, 5, 7 [s]. Default 0.05 s.
  double min_ramp{kDefaultMinRamp};
  /// Force the constant-velocity segment 4 to zero (thesis campaign). Default false.
  bool fix_constant_velocity_zero{false};
  /// Lower bounds on the plateau durations dT2 and dT6 [s]. Default 0, 0.
  std::array<double, 2> plateau_min{0.0, 0.0};
  /// Machine limits. Default none.
  MachineLimits limits;
  /// The law family. kMoveAbsolute: notch, multi_notch, min_jerk_band and time_domain optimise in
  /// the one-jerk family's own coordinates (ramp ta, ramp tb, cruise; exact gradients by the chain
  /// rule), the plan carries PlanResult::move_absolute, fir_chain holds only when its law is a
  /// one-jerk 7-segment law, and shaper and iir are refused (their laws are not 7-segment laws);
  /// auto runs the strategies that hold. Default kFree.
  DriveProfile drive_profile{DriveProfile::kFree};
  /// The range the plan must hold over (SPEC §10). When active: time_domain minimises the worst
  /// eta_motion over Uncertainty::sample_points models of the range (sample_models) subject to
  /// its eta bound at every one; min_jerk_band's band is widened to [(1 - band) omega_lo,
  /// (1 + band) omega_hi] (X_ref taken on it); notch and multi_notch are centred on the middle of
  /// [omega_lo, omega_hi], multi_notch's side notches at least at its ends; fir_chain, shaper and
  /// iir are designed at the middle frequency and damping of the range (on a turned tank
  /// fir_chain and iir keep one filter per direction, each at its range's middle frequency),
  /// and the shaper type (when
  /// `shaper_for_range`) is the shortest whose residual stays <= `residual` over the range; auto
  /// compares its candidates by their worst case over the sample models. Default: none.
  Uncertainty uncertainty;
  /// Attach PlanResult::robustness (the sweep of SPEC §10). Default true.
  bool robustness{true};
  /// Solver. Default kAuto.
  SolverChoice solver{SolverChoice::kAuto};
  /// Wall-clock budget of the whole plan [s], for both solvers (Ipopt's through its intermediate
  /// callback, not CPU time). When it runs out the best admissible point found so far is
  /// returned with status kTimeLimit. Default 5 s.
  double time_limit{5.0};
  /// The caller's cancellation flag (e.g. its client went away): once it reads true the plan ends
  /// as when time_limit runs out (kTimeLimit with the best admissible point so far), checked
  /// wherever the time limit is (between starts and phases). Must outlive the call. Default none.
  const std::atomic<bool>* stop{nullptr};
  /// Base law of shaper and iir, planned over T minus the filter's delay. Default poly5 (the
  /// paper's recommendation for shaping, sec. 7).
  BaseLaw base{BaseLaw::kPoly5};
  /// Shaper family of `shaper`. Default ZV (the least acceleration for a prescribed time).
  ShaperType shaper{ShaperType::kZV};
  /// With an active uncertainty, `shaper` chooses the family for the range instead of using
  /// `shaper` (the caller did not name one). Default true.
  bool shaper_for_range{true};
  /// Residual vibration V the EI shaper admits at omega1 [-]. Default 0.05.
  double residual{kDefaultEiResidual};
  /// Order of the IIR filter of `iir`. Default third (no initial peak, paper sec. 3.3).
  IirOrder iir_order{IirOrder::kThird};
  /// Pole tau of the IIR filter [1/s]: larger is shorter delay and a law closer to the inversion
  /// of the model. Default 50.
  double iir_tau{kDefaultIirTau};
  /// Sample period of the IIR law (the controller cycle the difference equation runs at) [s].
  /// Default 1 ms.
  double iir_sample_period{kDefaultIirSamplePeriod};
  /// Warm start: the 7 durations of a neighbouring plan [s], e.g. at another motion time (each
  /// finite and >= 0, their sum > 0; scaled to the motion time, then mapped into the bounds).
  /// When set, notch, multi_notch, min_jerk_band and time_domain start from it and from the
  /// uniform law only, instead of their deterministic multi-start, and time_domain takes no
  /// spectral seeds: continuation, as the min-time search plans neighbouring T (SPEC §9). Such a
  /// plan is only as global as its start. The other strategies ignore it. Default none.
  std::optional<Durations> warm_start;

  /// The first option outside its allowed set for `format` (in the order the members are
  /// declared, the relation 4 min_ramp + plateau minimums <= T right after min_ramp), naming the
  /// option, its value and the allowed set in core names and SI units; nullopt when all hold.
  [[nodiscard]] std::optional<InvalidInput> validate(const Format& format) const;
  /// validate() as a bool (Ceres' Options::IsValid): on failure writes the refusal to `error`
  /// (when not null) and returns false; on success leaves `error` untouched.
  [[nodiscard]] bool is_valid(const Format& format, InvalidInput* error) const;
};

/// Largest n_band plan() accepts [-].
inline constexpr int kMaxBandPoints{2001};
/// Ranges plan() accepts (wider than the API's; beyond them it returns an invalid-input result).
inline constexpr double kMinPlanRadius{1e-4};  ///< [m]
inline constexpr double kMinPlanLength{1e-9};  ///< fill height and stroke [m]
inline constexpr double kMaxPlanLength{1e3};   ///< radius, fill height and stroke [m]
inline constexpr double kMinPlanTime{1e-3};    ///< motion time [s]
inline constexpr double kMaxPlanTime{3600.0};  ///< motion time and rest window [s]

/// Why plan() would refuse `format` and `options` before building anything: the first format
/// quantity outside the planner's ranges above, then validate_model_options, then
/// PlanOptions::validate; nullopt when they are valid.
[[nodiscard]] std::optional<InvalidInput> validate_plan_input(const Format& format,
                                                              const PlanOptions& options);

/// Solver figures of a plan.
struct SolverReport {
  std::string name;    ///< "nlopt-slsqp", "ipopt" or "none"
  int iterations{};    ///< objective evaluations over all starts and phases
  int starts{};        ///< starts solved
  double objective{};  ///< objective of the returned point, in the strategy's scaled units
  double solve_ms{};   ///< wall-clock time of the optimisation [ms]
};

/// Verified predictions of one law (dense accurate simulation, SPEC §2).
struct LawPrediction {
  SloshPeaks linear;
  SloshPeaks nonlinear;
  KinematicSummary kinematics;
  /// A rectangular tank's linear waves of each direction alone (the validity warnings judge each
  /// on its own side); nullopt for the cylinder.
  std::optional<DirectionWaves> linear_directions;
};

/// How a filtering strategy built its law (the figures an engineer checks against the paper).
struct FirChainDesign {
  double t1{}, t2{}, t3{};  ///< filter durations [s], T3 = damped period of mode 1
  bool trapezoidal{false};  ///< conditions (14) hold: the law is the 7-segment law
};
struct ShaperDesign {
  BaseLaw base{};
  InputShaper shaper;      ///< impulse times [s] and amplitudes
  double base_duration{};  ///< T - delay [s]
  double residual{};       ///< residual vibration of mode 1 after the impulses [-]
};
struct IirDesign {
  BaseLaw base{};
  IirFilter filter;            ///< order, tau, sample period and coefficients
  double base_duration{};      ///< [s]
  double delay{};              ///< the filter's delay on the last pass [s]
  double filtered_duration{};  ///< [s], within one sample of T
  int iterations{};            ///< filter passes of the delay compensation
  double correction{};         ///< rest-to-rest correction relative to the peak acceleration [-]
};
using FilterDesign = std::variant<FirChainDesign, ShaperDesign, IirDesign>;

/// Reduction of `value` relative to `baseline`, 100 (1 - value / baseline) [%]; 0 when the
/// baseline is not positive (the figure the plan's message and the API's reductions report).
[[nodiscard]] double reduction_percent(double baseline, double value);

/// Why `strategy` cannot plan under `profile` (shaper and iir under kMoveAbsolute: their laws are
/// not 7-segment laws), as an invalid input kDriveProfile; nullopt when it can.
[[nodiscard]] std::optional<InvalidInput> drive_profile_refusal(Strategy strategy,
                                                                DriveProfile profile);

/// True for the strategies that hold `PlanOptions::band` (min_jerk_band, and auto, which runs it).
[[nodiscard]] bool uses_band(Strategy strategy);

/// Why `strategy` cannot plan with this band under the uncertainty range (kBand): min_jerk_band
/// widens its band to [w_lo - band w_hi, (1 + band) w_hi] (centred on the range's middle), and a
/// lower edge at or below 0 Hz is no band. nullopt for the strategies without a band, whatever
/// `band` is.
[[nodiscard]] std::optional<InvalidInput> band_refusal(Strategy strategy, const Format& format,
                                                       const PlanOptions& options);

/// True for the strategies that build a law by filtering instead of optimising 7 durations.
[[nodiscard]] bool is_filter_strategy(Strategy strategy);

/// Why `auto` did not return a candidate (SPEC §5's rule, in the order the rule applies it).
enum class CandidateLoss {
  kNone,               ///< the chosen candidate
  kNotUsable,          ///< infeasible or failed: only optimal, acceptable, time_limit compete
  kAboveBound,         ///< its verified eta breaks the eta bound (BoundVerdict) another meets,
                       ///< or (none meets it) it is above the least infeasible one returned
  kWorseThanBaseline,  ///< worse than the uniform law while a usable one that is not remains
  kMotionAboveBest,    ///< nonlinear eta_motion more than 5 % above the best competitor's
  kHigherRest,         ///< nonlinear eta_rest above the chosen candidate's
  kTieOnRest,          ///< eta_rest tied (1e-6) with the chosen one, peak acceleration not lower
};

template <>
struct EnumNames<CandidateLoss> {
  static constexpr std::array<EnumName<CandidateLoss>, 7> table{{
      {CandidateLoss::kNone, "none"},
      {CandidateLoss::kNotUsable, "not_usable"},
      {CandidateLoss::kAboveBound, "eta_above_limit"},
      {CandidateLoss::kWorseThanBaseline, "worse_than_baseline"},
      {CandidateLoss::kMotionAboveBest, "eta_motion_above_best"},
      {CandidateLoss::kHigherRest, "higher_eta_rest"},
      {CandidateLoss::kTieOnRest, "tie_on_eta_rest"},
  }};
};

/// One strategy's result inside an `auto` plan.
struct PlanCandidate {
  Strategy strategy{};
  SolveStatus status{};
  /// The seven durations when the law is a 7-segment law [s].
  std::optional<Durations> durations;
  /// The law itself (for every candidate).
  MotionLaw law;
  LawPrediction prediction;
  /// With an active uncertainty: the largest verified eta over the sample models.
  std::optional<LawPrediction> worst_case;
  bool chosen{false};
  /// Why auto did not return it (kNone for the chosen one) and that reason with its figures in
  /// one sentence (empty for the chosen one); set by run_auto from choose_auto's verdict.
  CandidateLoss lost{CandidateLoss::kNone};
  std::string lost_detail;
  /// Its `worse_than_baseline: ...` warning, as a plan of its strategy carries it (empty when it
  /// is not worse than the uniform law, and for the uniform law itself).
  std::string worse_than_baseline;
};

/// A candidate of `auto` against the eta bound of the options, on its verified (judged) figures:
/// time_domain's bound, eta_rest <= eta_rest_max (objective motion, default 3 mm) or eta_motion
/// <= eta_motion_max (objective rest). `auto` returns a law that breaks it only when no usable
/// candidate meets it, and then as infeasible: a plan that breaks the limit is never optimal.
struct BoundVerdict {
  double value{0.0};                                      ///< the bounded nonlinear figure [m]
  double bound{std::numeric_limits<double>::infinity()};  ///< the bound [m]
  bool on_rest{true};  ///< the figure is eta_rest (objective motion), else eta_motion
  /// The candidate meets every constraint but the bound (machine limits, ramps, its method's
  /// own): it may be returned as the least infeasible when no usable candidate meets the bound.
  bool others_met{false};
  /// Relative round-off of the verification.
  [[nodiscard]] bool meets() const { return value <= bound * (1.0 + 1e-6); }
};

/// kAuto's pick among its verified candidates (SPEC §5).
struct AutoChoice {
  /// The chosen candidate; 0 (the first, the uniform law) when none is eligible.
  std::size_t index{0};
  /// Some candidate was usable (optimal, acceptable or time-limited) and competed.
  bool eligible{false};
  /// Some usable candidate is not worse than the uniform law (then the worse ones do not compete).
  bool any_not_worse{false};
  /// Per candidate, index for index: why it lost (kNone for `index`) and the figures that decided
  /// it, e.g. "eta_rest 1.2 mm vs 0.8 mm of the chosen multi_notch". A rest loss is against the
  /// candidate the rule kept at that point, which a later one may have replaced (the 1e-6 tie is
  /// not transitive); the sentence then names both.
  std::vector<CandidateLoss> lost;
  std::vector<std::string> lost_detail;
  /// Bounds were given and no usable candidate meets them: `index` is the least infeasible
  /// candidate (lowest bounded figure among those whose only fault is the bound), `eligible` is
  /// false and the plan is infeasible; `bound_sentence` says so with the figures.
  bool bound_missed{false};
  std::string bound_sentence;
  /// The candidates were ranked on their linear figures: a rectangular tank's nonlinear model
  /// holds for some of their laws and not for others, so their nonlinear figures do not come
  /// from one model (set by the planners, not by choose_auto).
  bool ranked_on_linear{false};
};

/// SPEC §5's rule, pure: among the usable candidates (not worse than the uniform law while one
/// that is not remains; `worse_than_baseline[k]` flags candidate k), those whose nonlinear
/// eta_motion is within 5 % of the best compete; the lowest eta_rest wins (relative ties of 1e-6:
/// the lower peak acceleration, then the earlier candidate).
/// With `bounds` (index for index; empty: none), only the usable candidates that meet their bound
/// compete; when none does, the least infeasible one is returned (AutoChoice::bound_missed).
[[nodiscard]] AutoChoice choose_auto(const std::vector<PlanCandidate>& candidates,
                                     const std::vector<bool>& worse_than_baseline,
                                     const std::vector<BoundVerdict>& bounds = {});

/// Everything plan() returns. The durations are always admissible (SPEC §3).
struct PlanResult {
  Strategy strategy{};  ///< the requested strategy
  SolveStatus status{SolveStatus::kFailed};
  /// The status the strategy's solve or design ended with, before the warnings' caveats made an
  /// optimal plan `acceptable` (SPEC §5 "Honest status"), and its account, whose first clause (up
  /// to "; ") says why when that status is acceptable. A plan along a path starts from them and
  /// judges its own warnings.
  SolveStatus solved_status{SolveStatus::kFailed};
  std::string solved_detail;
  /// Set when plan() refused its inputs (validate_plan_input, or a model or uniform law that is
  /// not finite for them): status kFailed, the message is "invalid input: <its message>; nothing
  /// was planned", and nothing was planned: zero predictions; the model and the uniform law (as
  /// durations and law) only when they can be built finite from the valid inputs.
  std::optional<InvalidInput> invalid_input;
  /// One or two sentences a line engineer can act on.
  std::string message;
  /// The seven durations when the planned law is a 7-segment law (every optimising strategy, and
  /// fir_chain when conditions (14) hold) [s]; empty for the general laws of shaper, iir and
  /// fir_chain otherwise.
  std::optional<Durations> durations;
  /// The planned law, whatever its kind.
  MotionLaw law;
  /// How the filtering strategies built the law; empty for the optimising ones.
  std::optional<FilterDesign> design;
  double A{};  ///< positive plateau (general laws: peak acceleration) [m/s^2]
  double B{};  ///< negative plateau magnitude (general laws: peak deceleration) [m/s^2]
  SloshingModel model;
  /// A rectangular tank's model (both directions; SPEC §15), nullopt for the cylinder. `model` is
  /// then its most excited direction driven by the motion, and the predictions are the tank's
  /// highest wall or corner.
  std::optional<RectangularModel> rectangular;
  LawPrediction prediction;  ///< of the returned law
  LawPrediction baseline;    ///< of the uniform law
  /// The band of min_jerk_band (also reported for the other strategies as w1 +- band) [rad/s].
  std::array<double, 2> band_omega{};
  SolverReport solver;
  /// Each with its kind (warning_kinds()); the kinds decide the honest status.
  std::vector<Warning> warnings;
  std::vector<PlanCandidate> candidates;  ///< filled by kAuto only
  /// With PlanOptions::drive_profile kMoveAbsolute, the MC_MoveAbsolute numbers of the law (set
  /// whenever the returned law is a one-jerk 7-segment law).
  std::optional<MoveAbsoluteProfile> move_absolute;
  /// With PlanOptions::uncertainty active: the omega_1 and zeta range it implies.
  std::optional<UncertaintyRange> uncertainty;
  /// With PlanOptions::robustness: the returned law swept over the frequency range (the
  /// uncertainty's range at its least damping when active, else +-10 % at the nominal zeta).
  std::optional<RobustnessReport> robustness;
  /// With PlanOptions::uncertainty active: the returned law's largest verified eta over the
  /// sample models (the figure robust designs and auto are judged by).
  std::optional<LawPrediction> worst_case;
  /// A plan along a path (plan_on_path): the returned law's and the uniform law's verified
  /// figures along it, with the wall directions of the peaks (what its predictions were taken
  /// from); nullopt on a straight line.
  std::optional<PathPlanReport> path;

  /// True when the law can be run: optimal, acceptable, or time-limited (best admissible).
  [[nodiscard]] bool usable() const {
    return status == SolveStatus::kOptimal || status == SolveStatus::kAcceptable ||
           status == SolveStatus::kTimeLimit;
  }
};

/// The frequencies the returned law of `r` (planned for `format` with `options`) notches
/// [rad/s], ascending: notch's (one, or one per excited direction of a turned rectangular tank),
/// multi_notch's three around each such mode (also as auto's choice); empty for the other
/// strategies. The spectrum's notch markers.
[[nodiscard]] std::vector<double> notched_frequencies(const Format& format,
                                                      const PlanOptions& options,
                                                      const PlanResult& r);

/// The robustness report (SPEC §10) of a plan's law: swept over the uncertainty range of
/// `options` at its least damping when active, else over +-10 % at the model's zeta; judged by
/// options.eta_rest_max and, when given, options.eta_motion_max. plan() attaches it when
/// options.robustness is set.
[[nodiscard]] RobustnessReport robustness_of(const Format& format, const PlanOptions& options,
                                             const PlanResult& result);

/// Plans a law for `format`. Invalid inputs (validate_plan_input) give an invalid-input result,
/// never a throw or a non-finite number. Status rules (SPEC §5 "Honest status"): kOptimal and
/// kAcceptable only when the returned law meets every constraint of the strategy on the
/// verification (machine limits, the band of min_jerk_band on a fine grid, the eta bound of
/// time_domain on the dense nonlinear response), kInfeasible only when it does not, with the
/// least infeasible law found and a message naming the constraint, its limit and the best value
/// reached. A law more than 5 % and 0.5 mm above the uniform law on any eta carries the warning
/// `worse_than_baseline: ...`.
[[nodiscard]] PlanResult plan(const Format& format, Strategy strategy, const PlanOptions& options);

}  // namespace slosh
