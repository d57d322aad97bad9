#include "slosh/core/strategy/planner.hpp"

#include "slosh/core/model/modal_truncation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>

#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "slosh/core/strategy/rectangular_plan.hpp"
#include "solve/one_jerk_chart.hpp"
#include "strategy/fill_range_warning.hpp"
#include "strategy/status_caveat.hpp"
#include "strategy/strategies.hpp"
#include "text.hpp"

namespace slosh {

namespace {

using detail::sig3;

/// Tie tolerance of the `auto` rule on eta_rest (relative) [-].
constexpr double kAutoTieTolerance{1e-6};
/// `auto` keeps candidates whose eta_motion is within this factor of the best one (SPEC §5).
constexpr double kAutoMotionSlack{1.05};

/// The verified prediction of a law: on the cylinder's `model`, or on the rectangular tank's
/// walls and corners when `rectangular` is given.
/// `out_of_range`, when given, receives why the rectangular nonlinear model does not hold for the
/// law (empty when it does).
LawPrediction predict(const SloshingModel& model, const RectangularModel* rectangular,
                      const MotionLaw& law, double rest_time, std::string* out_of_range = nullptr) {
  LawPrediction p;
  p.kinematics = law.summary();
  if (rectangular != nullptr) {
    RectangularPrediction r = rectangular_prediction(*rectangular, law, rest_time);
    p.linear = r.linear;
    p.nonlinear = r.nonlinear;
    p.linear_directions = r.linear_directions;
    if (out_of_range != nullptr) *out_of_range = std::move(r.warning);
    return p;
  }
  p.linear = LinearResponse(model, law, rest_time).peaks();
  p.nonlinear = nonlinear_peaks(model, law, rest_time);
  return p;
}

/// The sweep of SPEC §10 for `options`: over the uncertainty range at its least damping when
/// active, else over +-10 % at `nominal_zeta`; judged by eta_rest_max (and eta_motion_max when
/// given).
RobustnessSweep sweep_for(const Format& format, const PlanOptions& options, double nominal_zeta) {
  RobustnessSweep sweep;
  sweep.zeta = nominal_zeta;
  if (options.uncertainty.active()) {
    const UncertaintyRange range = uncertainty_range(format, options.model, options.uncertainty);
    sweep.delta_lo = range.scale_lo - 1.0;
    sweep.delta_hi = range.scale_hi - 1.0;
    sweep.zeta = range.zeta_lo;
  }
  sweep.rest_time = options.rest_time;
  sweep.eta_rest_max = options.eta_rest_max;
  sweep.eta_motion_max = options.eta_motion_max;
  return sweep;
}

/// The law's figures and their change against the uniform law's, on the nonlinear model unless
/// `one_model` (both laws' nonlinear figures do not come from one model: the linear model's
/// figures, as reduction_pct then compares).
std::string summary_sentence(const LawPrediction& p, const LawPrediction& b, bool one_model) {
  auto change = [](double base, double v) {
    const double r = reduction_percent(base, v);
    if (std::abs(r) < 5e-4) return std::string("0 %");  // below the 3 digits shown
    std::string text(r >= 0.0 ? "-" : "+");
    text.append(sig3(std::abs(r)));
    text.append(" %");
    return text;
  };
  const SloshPeaks& law = one_model ? p.linear : p.nonlinear;
  const SloshPeaks& base = one_model ? b.linear : b.nonlinear;
  return std::string(one_model ? "linear model (both laws on one model)" : "nonlinear model") +
         ": eta_motion " + sig3(law.motion.value * 1e3) + " mm (" +
         change(base.motion.value, law.motion.value) + " vs the uniform law), " + "eta_rest " +
         sig3(law.rest.value * 1e3) + " mm (" + change(base.rest.value, law.rest.value) + ")";
}

/// What the baseline guard compares every law with: the law strategy baseline returns. That is
/// the uniform law when the options admit it; else its nearest admissible law (every segment at
/// its minimum plus an equal share), since a law the options forbid is no alternative to offer.
struct GuardReference {
  LawPrediction prediction;
  bool uniform{true};  ///< the reference is the uniform law itself
  /// Its nonlinear figures are the nonlinear model's (false: a rectangular tank's nonlinear
  /// model does not hold for it, and they are the linear model's).
  bool nonlinear_in_range{true};
};

/// The `worse_than_baseline` warning naming the figures, or empty. `law_in_range`: the law's
/// nonlinear figures are the nonlinear model's; when only one of the two laws' are, the linear
/// figures alone are compared.
std::string worse_than_baseline(const LawPrediction& p, const GuardReference& ref,
                                bool law_in_range) {
  const bool linear_only = law_in_range != ref.nonlinear_in_range;
  std::string figures = detail::worse_figures(detail::peak_figures(p),
                                              detail::peak_figures(ref.prediction), linear_only);
  if (figures.empty()) return {};
  if (linear_only) figures += detail::kWorseOnLinearModel;
  if (!ref.uniform) {
    return "worse_than_baseline: " + figures +
           " for baseline's law (more than 5 % and 0.5 mm above it; the uniform law breaks the "
           "options, so baseline's law is every segment at its minimum plus an equal share); "
           "strategy baseline sloshes less there";
  }
  return "worse_than_baseline: " + figures +
         " for the uniform law (more than 5 % and 0.5 mm above it); the uniform law (strategy "
         "baseline) sloshes less there";
}

bool finite_prediction(const LawPrediction& p) {
  const double values[] = {p.linear.motion.value,       p.linear.rest.value,
                           p.nonlinear.motion.value,    p.nonlinear.rest.value,
                           p.kinematics.v_peak,         p.kinematics.a_peak_positive,
                           p.kinematics.a_peak_negative};
  return std::all_of(std::begin(values), std::end(values),
                     [](double v) { return std::isfinite(v); });
}

/// A rectangular tank's sides and orientation.
std::optional<InvalidInput> validate_rectangular(const Format& f) {
  if (!f.container.rectangular) return std::nullopt;
  const RectangularTank& t = *f.container.rectangular;
  const InputBounds side = closed_range(kMinPlanRadius, kMaxPlanLength);
  if (auto bad = first_out_of_range({
          {PlanInput::kContainerLength, t.length, side},
          {PlanInput::kContainerWidth, t.width, side},
          {PlanInput::kContainerOrientation, t.orientation_deg, closed_range(-180.0, 180.0)},
      })) {
    return bad;
  }
  return std::nullopt;
}

}  // namespace

std::optional<InvalidInput> validate_plan_input(const Format& f, const PlanOptions& options) {
  const InputBounds length = closed_range(kMinPlanLength, kMaxPlanLength);
  if (auto bad = validate_rectangular(f)) return bad;
  if (auto bad = first_out_of_range({
          {PlanInput::kContainerRadius,
           f.container.rectangular ? kMinPlanRadius : f.container.radius,
           closed_range(kMinPlanRadius, kMaxPlanLength)},
          {PlanInput::kContainerHeight, f.container.height.value_or(1.0), positive()},
          {PlanInput::kFillHeight, f.fill_height, length},
          {PlanInput::kFluidDensity, f.fluid.density, closed_range(1.0, 1e5)},
          {PlanInput::kFluidViscosity, f.fluid.viscosity, closed_range(0.0, 1e6)},
          {PlanInput::kStroke, f.stroke, length},
          {PlanInput::kMotionTime, f.motion_time, closed_range(kMinPlanTime, kMaxPlanTime)},
      })) {
    return bad;
  }
  if (auto model = validate_model_options(options.model)) return model;
  return options.validate(f);
}

double reduction_percent(double baseline, double value) {
  return baseline > 0.0 ? 100.0 * (1.0 - value / baseline) : 0.0;
}

std::optional<InvalidInput> drive_profile_refusal(Strategy strategy, DriveProfile profile) {
  if (profile != DriveProfile::kMoveAbsolute ||
      (strategy != Strategy::kShaper && strategy != Strategy::kIir)) {
    return std::nullopt;
  }
  return refused(PlanInput::kDriveProfile, NAN, InputBounds{},
                 "drive_profile = move_absolute needs a 7-segment law, and " + to_string(strategy) +
                     " builds a general law: plan with baseline, notch, multi_notch, "
                     "min_jerk_band, time_domain, fir_chain or auto");
}

bool is_filter_strategy(Strategy strategy) {
  return strategy == Strategy::kFirChain || strategy == Strategy::kShaper ||
         strategy == Strategy::kIir;
}

namespace {

/// The relation 4 min_ramp + plateau minimums <= T, or nullopt when it holds (NaN floors pass:
/// their own checks refuse them).
std::optional<InvalidInput> ramps_and_plateaus(const PlanOptions& o, double T) {
  const double floor_sum = 4.0 * o.min_ramp + o.plateau_min[0] + o.plateau_min[1];
  if (!(floor_sum > T)) return std::nullopt;
  const InputBounds bounds{-INFINITY, T, false, false};
  return refused(PlanInput::kRampsAndPlateaus, floor_sum, bounds,
                 "min_ramp = " + sig3(o.min_ramp) + " s and plateau_min = [" +
                     sig3(o.plateau_min[0]) + ", " + sig3(o.plateau_min[1]) +
                     "] s need 4 ramps + 2 plateaus = " + sig3(floor_sum) +
                     " s, more than the motion_time " + sig3(T) +
                     " s: allowed min_ramp <= (motion_time - plateau minimums) / 4 = " +
                     sig3((T - o.plateau_min[0] - o.plateau_min[1]) / 4.0) + " s");
}

/// With drive_profile kMoveAbsolute: some one-jerk law meets the ramp and plateau minimums.
std::optional<InvalidInput> one_jerk_family(const PlanOptions& o, double T) {
  if (o.drive_profile != DriveProfile::kMoveAbsolute) return std::nullopt;
  const detail::OneJerkChart chart(T, o.min_ramp, o.fix_constant_velocity_zero ? 0.0 : T,
                                   o.plateau_min);
  if (chart.anchor) return std::nullopt;
  return refused(PlanInput::kDriveProfile, T, InputBounds{},
                 "drive_profile = move_absolute: no one-jerk law of " + sig3(T) +
                     " s has ramps >= min_ramp = " + sig3(o.min_ramp) +
                     " s and plateaus >= plateau_min = [" + sig3(o.plateau_min[0]) + ", " +
                     sig3(o.plateau_min[1]) + "] s; lower the plateau minimums");
}

/// The arrays: plateau_min[i] >= 0, weights[i] >= 0 and their sum > 0.
std::optional<InvalidInput> validate_arrays(const PlanOptions& o) {
  for (int i = 0; i < 2; ++i) {
    if (!non_negative().contains(o.plateau_min[i])) {
      return out_of_range(PlanInput::kPlateauMin, i, o.plateau_min[i], non_negative());
    }
    // A duration below kZeroDuration is 0 (SPEC §11): such a minimum could not be held.
    if (o.plateau_min[i] > 0.0 && o.plateau_min[i] < kZeroDuration) {
      InvalidInput e =
          refused(PlanInput::kPlateauMin, o.plateau_min[i], InputBounds{kZeroDuration, INFINITY},
                  "plateau_min[" + std::to_string(i) + "] = " + sig3(o.plateau_min[i]) +
                      " s must be 0 or >= 1e-09 s: durations below 1 ns are exactly 0");
      e.index = i;
      return e;
    }
  }
  double weight_sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (!non_negative().contains(o.weights[i])) {
      return out_of_range(PlanInput::kWeights, i, o.weights[i], non_negative());
    }
    weight_sum += o.weights[i];
  }
  if (weight_sum <= 0.0) {
    return refused(PlanInput::kWeights, weight_sum, positive(),
                   "weights = [0, 0, 0]: at least one weight must be > 0");
  }
  if (!o.warm_start) return std::nullopt;
  double warm_sum = 0.0;
  for (int i = 0; i < static_cast<int>(kSegments); ++i) {
    const double d = (*o.warm_start)[static_cast<std::size_t>(i)];
    if (!non_negative().contains(d))
      return out_of_range(PlanInput::kWarmStart, i, d, non_negative());
    warm_sum += d;
  }
  if (!(warm_sum > 0.0) || !std::isfinite(warm_sum)) {
    return refused(PlanInput::kWarmStart, warm_sum, positive(),
                   "warm_start sums to " + sig3(warm_sum) + " s: it must be finite and > 0");
  }
  return std::nullopt;
}

}  // namespace

std::optional<InvalidInput> PlanOptions::validate(const Format& format) const {
  const double T = format.motion_time;
  if (!positive().contains(min_ramp)) {
    return out_of_range(PlanInput::kMinRamp, -1, min_ramp, positive());
  }
  if (auto relation = ramps_and_plateaus(*this, T)) return relation;
  if (auto arrays = validate_arrays(*this)) return arrays;
  if (auto family = one_jerk_family(*this, T)) return family;
  if (auto bad = first_out_of_range({
          {PlanInput::kPNotch, p_notch, open_range(0.0, 1.0)},
          {PlanInput::kBand, band, open_range(0.0, 1.0)},
          {PlanInput::kNBand, static_cast<double>(n_band), closed_range(1.0, kMaxBandPoints)},
          {PlanInput::kTolRel, tol_rel, positive()},
          {PlanInput::kEtaRestMax, eta_rest_max, positive()},
          {PlanInput::kEtaMotionMax, eta_motion_max.value_or(1.0), positive()},
          {PlanInput::kRestTime, rest_time, {0.0, kMaxPlanTime, true, false}},
          {PlanInput::kAMax, limits.a_max.value_or(1.0), positive()},
          {PlanInput::kVMax, limits.v_max.value_or(1.0), positive()},
          {PlanInput::kJMax, limits.j_max.value_or(1.0), positive()},
      })) {
    return bad;
  }
  // An infinite budget is no budget.
  if (!(time_limit > 0.0) || std::isnan(time_limit)) {
    return refused(PlanInput::kTimeLimit, time_limit, positive(),
                   "time_limit = " + sig3(time_limit) + " s must be > 0");
  }
  if (auto bad = first_out_of_range({
          {PlanInput::kResidual, residual, {0.0, 1.0, false, true}},
          {PlanInput::kIirTau, iir_tau, positive()},
          {PlanInput::kIirSamplePeriod, iir_sample_period, {0.0, T / kIirMinSamples, true, false}},
      })) {
    return bad;
  }
  if (auto bad = validate_uncertainty(format, model, uncertainty)) return bad;
  return std::nullopt;
}

bool uses_band(Strategy strategy) {
  return strategy == Strategy::kMinJerkBand || strategy == Strategy::kAuto;
}

std::optional<InvalidInput> band_refusal(Strategy strategy, const Format& format,
                                         const PlanOptions& options) {
  if (!uses_band(strategy) || !options.uncertainty.active()) return std::nullopt;
  const double widened = detail::widened_band(
      options.band, uncertainty_range(format, options.model, options.uncertainty));
  if (widened < 1.0) return std::nullopt;
  return refused(PlanInput::kBand, options.band, open_range(0.0, 1.0),
                 "band = " + sig3(options.band) + " widened to cover the uncertainty range is " +
                     sig3(widened) + ": its lower edge reaches 0 Hz (min_jerk_band" +
                     (strategy == Strategy::kAuto ? ", a candidate of auto," : "") +
                     " holds the band); narrow the band or the range");
}

bool PlanOptions::is_valid(const Format& format, InvalidInput* error) const {
  std::optional<InvalidInput> invalid = validate(format);
  if (invalid && error != nullptr) *error = std::move(*invalid);
  return !invalid;
}

namespace detail {

double widened_band(double band, const UncertaintyRange& r) {
  return (0.5 * (r.scale_hi - r.scale_lo) + band * r.scale_hi) / r.scale_mid();
}

MultiStartResult least_limit_scale(const StrategyContext& c, int first, int rows) {
  // min z s.t. quantity_r / limit_r <= z for the rows [first, first + rows) of limit_constraints
  // (g = quantity / limit - 1); z <= 1: those limits are reachable together.
  const int total = c.space.limit_count();
  const DurationSpace* space = &c.space;
  NlpProblem p = c.space.problem(1);
  p.inequality_count = rows;
  p.inequalities = [space, total, first, rows](const double* x, double* g, double* jac) {
    std::vector<double> all(static_cast<std::size_t>(total));
    std::vector<double> all_jac(static_cast<std::size_t>(total) * (kSegments + 1), 0.0);
    space->limit_constraints(x, all.data(), jac ? all_jac.data() : nullptr, kSegments + 1);
    for (int r = 0; r < rows; ++r) {
      g[r] = all[static_cast<std::size_t>(first + r)] + 1.0 - x[kSegments];
      if (jac != nullptr) {
        for (std::size_t i = 0; i < kSegments; ++i) {
          jac[r * (kSegments + 1) + i] = all_jac[(first + r) * (kSegments + 1) + i];
        }
        jac[r * (kSegments + 1) + kSegments] = -1.0;
      }
    }
  };
  auto starts = as_vectors(c.space.starts(4));
  for (auto& x : starts) {
    std::vector<double> g(static_cast<std::size_t>(total));
    space->limit_constraints(x.data(), g.data(), nullptr, kSegments + 1);
    double z = 0.0;
    for (int r = 0; r < rows; ++r) z = std::max(z, g[static_cast<std::size_t>(first + r)] + 1.0);
    x.push_back(z);
  }
  return multi_start(p, starts, c, NlpOptions{});
}

std::string explain_limits(const StrategyContext& c) {
  const MachineLimits& lim = c.space.limits;
  const double s = c.format.stroke, T = c.format.motion_time;
  struct Quantity {
    const char* name;
    const char* unit;
    std::optional<double> limit;
    int rows;
    int first;  // first row in limit_constraints
  };
  const int a_rows = lim.a_max ? 2 : 0;
  const int v_rows = lim.v_max ? 1 : 0;
  const Quantity quantities[] = {{"a_max", "m/s^2", lim.a_max, a_rows, 0},
                                 {"v_max", "m/s", lim.v_max, v_rows, a_rows},
                                 {"j_max", "m/s^3", lim.j_max, lim.j_max ? 4 : 0, a_rows + v_rows}};
  int limited = 0;
  for (const Quantity& q : quantities) {
    if (!q.limit) continue;
    ++limited;
    const MultiStartResult m = least_limit_scale(c, q.first, q.rows);
    if (m.feasible && m.best.objective > 1.0 + 1e-6) {
      return std::string(q.name) + " = " + sig3(*q.limit) + " " + q.unit +
             " is not reachable: " + sig3(s * 1e3) + " mm in " + sig3(T) +
             " s with ramps >= " + sig3(c.options.min_ramp) + " s needs at least " +
             sig3(m.best.objective * *q.limit) + " " + q.unit + "; lengthen the motion or raise " +
             q.name;
    }
  }
  // Each limit alone is reachable: together, by the same scale over every row (a zero objective
  // let the solver stop at its infeasible start).
  if (limited > 1) {
    const MultiStartResult m = least_limit_scale(c, 0, c.space.limit_count());
    if (m.feasible && m.best.objective > 1.0 + 1e-6) {
      return "the machine limits are each reachable but not together for " + sig3(s * 1e3) +
             " mm in " + sig3(T) + " s (together they are exceeded by " +
             sig3(100.0 * (m.best.objective - 1.0)) +
             " % at best); raise one of them or lengthen the motion";
    }
  }
  return {};
}

namespace {

/// The uncertainty range's design model, sample models, check models, band and p_notch.
void set_range(StrategyContext& c) {
  const PlanOptions& o = c.options;
  c.range = uncertainty_range(c.format, o.model, o.uncertainty);
  const UncertaintyRange& r = *c.range;
  const double mid = r.scale_mid();
  c.design_model = scaled_model(c.model, mid, r.zeta_mid());
  c.sample_models = sample_models(c.model, r, o.uncertainty.sample_points);
  // The robustness report's grid: the models a robust plan is verified at are its points.
  c.sweep = sweep_for(c.format, o, c.model.zeta);
  c.check_models.clear();
  for (double delta : robustness_deltas(c.sweep)) {
    c.check_models.push_back(scaled_model(c.model, 1.0 + delta, c.sweep.zeta));
  }
  // The band around the middle reaches (1 + band) scale_hi (and beyond (1 - band) scale_lo).
  c.band = widened_band(o.band, r);
  // Side notches at the ends of the range when it is wider than +-p_notch.
  c.p_notch = std::max(o.p_notch, (r.scale_hi - r.scale_lo) / (r.scale_hi + r.scale_lo));
}

}  // namespace

void set_design(StrategyContext& c) {
  const PlanOptions& o = c.options;
  c.band = o.band;
  c.p_notch = o.p_notch;
  c.design_model = c.model;
  c.sample_models = {c.model};
  c.check_models = {c.model};
  c.over_directions = false;
  if (o.uncertainty.active()) set_range(c);
  set_directions(c);
  c.band_grid = band_check_grid(c.design_model.omega1(), c.band, o.n_band);
}

void set_references(StrategyContext& c, double eta_ref) {
  const Durations uniform = uniform_durations(c.format.motion_time);
  // X_ref is the nominal band's (SPEC §5): a band widened for an uncertainty range keeps the
  // nominal level as its limit instead of loosening with the wider band's larger maximum.
  // Without a range the nominal band is the design band: its grid is built already.
  c.x_ref =
      band_peak(uniform, c.format.stroke,
                c.robust() ? band_check_grid(c.model.omega1(), c.options.band, c.options.n_band)
                           : c.band_grid)
          .value;
  c.jerk_ref = SevenSegmentLaw(uniform, c.format.stroke).jerk_integral();
  c.eta_ref = eta_ref;
  c.eta_motion_max = c.options.eta_motion_max.value_or(eta_ref);
}

std::string violated_constraint(const StrategyContext& c, Strategy strategy, const Durations& d,
                                const SloshPeaks& verified) {
  constexpr double kSlack = 1e-6;          // relative round-off of the verification
  constexpr double kDurationSlack = 1e-9;  // s
  // The admissibility rules of the options (the optimisers hold them by their bounds; the uniform
  // law does not).
  for (int i : {0, 2, 4, 6}) {
    if (d[i] < c.options.min_ramp - kDurationSlack) {
      return "the law's ramp " + std::to_string(i + 1) + " lasts " + sig3(d[i]) +
             " s, less than min_ramp_s = " + sig3(c.options.min_ramp) + " s";
    }
  }
  for (int k = 0; k < 2; ++k) {
    const int i = k == 0 ? 1 : 5;
    if (d[i] < c.options.plateau_min[k] - kDurationSlack) {
      return "the law's plateau " + std::to_string(i + 1) + " lasts " + sig3(d[i]) +
             " s, less than plateau_min_s[" + std::to_string(k) +
             "] = " + sig3(c.options.plateau_min[k]) + " s";
    }
  }
  if (c.options.fix_constant_velocity_zero && d[3] > kDurationSlack) {
    return "the law cruises for " + sig3(d[3]) +
           " s although fix_constant_velocity_zero asks for no constant-velocity segment";
  }
  const SevenSegmentLaw law(d, c.format.stroke);
  double jerk = 0.0;
  for (double j : law.jerks()) jerk = std::max(jerk, std::abs(j));
  if (std::string limit =
          limit_violation(c.options.limits, std::max(law.A(), law.B()), law.v_peak(), jerk, kSlack);
      !limit.empty()) {
    return limit;
  }
  if (strategy == Strategy::kMinJerkBand) {
    const double ratio = band_peak(d, c.format.stroke, band_check_grid(c)).value / c.x_ref;
    if (ratio > c.options.tol_rel * (1.0 + kBandTolerance)) return band_limit_sentence(c, ratio);
  }
  if (strategy == Strategy::kTimeDomain) {
    const bool motion = c.options.objective == TimeDomainObjective::kMotion;
    const double value = motion ? verified.rest.value : verified.motion.value;
    const double bound = motion ? c.options.eta_rest_max : c.eta_motion_max;
    if (value <= bound * (1.0 + kSlack)) return {};
    const std::string head = std::string(motion ? "eta_rest" : "eta_motion") +
                             " <= " + sig3(bound * 1e3) + " mm is not ";
    const std::string in_time = " in " + sig3(c.format.motion_time) + " s: ";
    const std::string act = "lengthen the motion or relax the limit";
    if (c.rectangular != nullptr) {
      // time_domain bounds each direction's oscillator model, its bound corrected by the gap to
      // the tank's model (second mode, corners) at each round's point; a local search whose
      // correction has not settled, or a robust plan (whose range is not corrected), can end
      // above the bound where a law of another strategy meets it.
      return head + "met" + in_time +
             "time_domain's law, bounded on each direction's oscillator model corrected by its "
             "gap to the tank's model, verifies at " +
             sig3(value * 1e3) +
             " mm on the tank's model (second mode included); try notch or "
             "multi_notch, " +
             act;
    }
    return head + "reachable" + in_time + "the best is " + sig3(value * 1e3) + " mm; " + act;
  }
  return {};
}

}  // namespace detail

namespace {

/// The invalid-input result: nothing planned, but what can be built from the valid parts (the
/// model, the uniform law) is filled in when finite, so a renderer that expects them does not
/// meet empty or non-finite fields; predictions stay zero.
PlanResult refusal(const Format& f, Strategy strategy, const PlanOptions& options,
                   InvalidInput why) {
  PlanResult invalid;
  invalid.strategy = strategy;
  invalid.status = SolveStatus::kFailed;
  invalid.message = "invalid input: " + why.message + "; nothing was planned";
  invalid.invalid_input = std::move(why);
  invalid.solver.name = "none";
  const ModelOptions& m = options.model;
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (positive(f.container.radius) && positive(f.fill_height) && positive(f.fluid.density) &&
      std::isfinite(f.fluid.viscosity) && f.fluid.viscosity >= 0.0 && m.modes >= 1 &&
      m.modes <= static_cast<int>(kMaxModes) && std::isfinite(m.alpha) &&
      std::isfinite(m.explicit_zeta) && m.explicit_zeta >= 0.0) {
    const SloshingModel model = make_sloshing_model(f, m);
    const bool finite = std::isfinite(model.zeta) && std::isfinite(model.C) &&
                        std::isfinite(model.K) &&
                        std::all_of(model.omega.begin(), model.omega.end(), positive);
    if (finite) invalid.model = model;
  }
  if (positive(f.motion_time) && f.motion_time <= kMaxPlanTime && positive(f.stroke) &&
      f.stroke <= kMaxPlanLength) {
    const Durations uniform = uniform_durations(f.motion_time);
    const SevenSegmentLaw law(uniform, f.stroke);
    if (std::isfinite(law.A()) && std::isfinite(law.B())) {
      invalid.durations = uniform;
      invalid.law = law.law();
      invalid.A = law.A();
      invalid.B = law.B();
    }
  }
  return invalid;
}

/// The refusal of a model that is not finite for valid inputs, or nullopt.
std::optional<InvalidInput> model_refusal(const SloshingModel& model) {
  const double w1 = model.omega1();
  if (std::isfinite(w1) && w1 > 0.0 && std::isfinite(model.zeta) && model.zeta >= 0.0 &&
      std::isfinite(model.K)) {
    return std::nullopt;
  }
  return refused(PlanInput::kSloshingModel, w1, positive(),
                 "the sloshing model of this format is not finite (omega1 = " + sig3(w1) +
                     " rad/s, zeta = " + sig3(model.zeta) + ")");
}

/// With an uncertainty range, a law swept over it: the robustness report (the plan's, when it is
/// the returned law) and the worst case it gives, which the law is verified and judged by.
struct RangeJudgement {
  RobustnessReport report;
  LawPrediction worst;
};

/// A law's verification: its prediction at the nominal model, its sweep over the uncertainty
/// range when robust, and why the rectangular nonlinear model does not hold for it (or empty).
struct Verification {
  LawPrediction prediction;
  std::optional<RangeJudgement> range;
  std::string out_of_range;
};

/// One strategy's outcome in one shape (the optimisers' durations become their law), carrying
/// the strategy that produced it.
struct Outcome {
  Strategy strategy{};
  SolveStatus status{SolveStatus::kFailed};
  std::optional<Durations> durations;
  MotionLaw law;
  std::optional<FilterDesign> design;
  std::string detail;
  detail::StrategyOutcome solver;  // evaluations, starts, objective, solver name
  /// Set when the law was verified (and its status judged) while it was chosen among designs.
  std::optional<Verification> verification;

  /// `law` is the 7-segment law of `durations`: the optimisers' laws are, the filters' are not.
  [[nodiscard]] bool law_of_durations() const { return !is_filter_strategy(strategy); }
};

Outcome from_solver(const detail::StrategyContext& c, Strategy s, detail::StrategyOutcome o) {
  Outcome out;
  out.strategy = s;
  out.status = o.status;
  if (o.status == SolveStatus::kFailed) o.durations = uniform_durations(c.format.motion_time);
  out.durations = o.durations;
  out.law = SevenSegmentLaw(o.durations, c.format.stroke).law();
  out.detail = o.detail;
  out.solver = std::move(o);
  return out;
}

Outcome from_filter(Strategy s, detail::FilterOutcome o) {
  Outcome out;
  out.strategy = s;
  out.status = o.status;
  out.durations = o.durations;
  out.law = std::move(o.law);
  out.design = std::move(o.design);
  out.detail = std::move(o.detail);
  out.solver.solver = "none";
  return out;
}

/// baseline: the uniform law, or, when the options' bounds exclude it (min_ramp above T/7,
/// plateau minimums, no cruise), every segment at its lower bound plus an equal share of the
/// remaining time (SPEC §5: never durations that break the admissibility rules).
detail::StrategyOutcome uniform_or_admissible(const detail::StrategyContext& c) {
  detail::StrategyOutcome o;
  o.status = SolveStatus::kOptimal;
  o.solver = "none";
  o.durations = uniform_durations(c.format.motion_time);
  if (c.space.uniform_inside()) return o;
  const std::string broken =
      detail::violated_constraint(c, Strategy::kBaseline, o.durations, SloshPeaks{});
  o.durations = c.space.nearest_uniform();
  o.detail = "the uniform law breaks the options (" + broken +
             "), so baseline returns every segment at its minimum plus an equal share of the "
             "remaining time";
  return o;
}

/// The prediction of an outcome's law: the plan's uniform-law prediction when the law is the
/// uniform 7-segment law (the same durations give the same law and the same responses, so it is
/// not simulated twice; `out_of_range` is then the context's reason of it), else simulated here.
/// `out_of_range`, when given, receives why the rectangular nonlinear model does not hold for the
/// law (empty when it does).
LawPrediction predict_outcome(const detail::StrategyContext& c, const Outcome& o,
                              std::string* out_of_range = nullptr) {
  if (c.uniform_prediction != nullptr && o.law_of_durations() && o.durations &&
      *o.durations == uniform_durations(c.format.motion_time)) {
    if (out_of_range != nullptr) *out_of_range = c.uniform_out_of_range;
    return *c.uniform_prediction;
  }
  return predict(c.model, c.rectangular, o.law, c.options.rest_time, out_of_range);
}

/// One strategy's design in the context `c` (not kAuto); `seeds` are time_domain's extra starts.
Outcome run_design(const detail::StrategyContext& c, Strategy s,
                   const std::vector<Durations>& seeds) {
  switch (s) {
    case Strategy::kNotch:
      return from_solver(c, s, detail::solve_notch(c));
    case Strategy::kMultiNotch:
      return from_solver(c, s, detail::solve_multi_notch(c));
    case Strategy::kMinJerkBand:
      return from_solver(c, s, detail::solve_min_jerk_band(c));
    case Strategy::kTimeDomain:
      return from_solver(c, s, detail::solve_time_domain(c, seeds));
    case Strategy::kFirChain:
      return from_filter(s, detail::design_fir_chain(c));
    case Strategy::kShaper:
      return from_filter(s, detail::design_shaper(c));
    case Strategy::kIir:
      return from_filter(s, detail::design_iir(c));
    default:
      return from_solver(c, s, uniform_or_admissible(c));
  }
}

/// SPEC §5 "Honest status": the status follows the verification of the returned law. An
/// optimiser's law that meets every constraint is never infeasible; one that violates a
/// constraint is never optimal or acceptable (filter designs are only ever downgraded: their
/// "infeasible" also means "this method has no law here").
void verify(const detail::StrategyContext& c, Outcome& o, const LawPrediction& p) {
  const bool usable_before =
      o.status == SolveStatus::kOptimal || o.status == SolveStatus::kAcceptable;
  if (c.options.drive_profile == DriveProfile::kMoveAbsolute && usable_before &&
      (!o.durations || !move_absolute_profile(*o.durations, c.format.stroke))) {
    o.status = SolveStatus::kInfeasible;
    o.detail = (o.detail.empty() ? "" : o.detail + "; ") +
               std::string(
                   "the law is not a one-jerk 7-segment law, so a MC_MoveAbsolute block "
                   "cannot run it (drive_profile move_absolute)");
    return;
  }
  if (!o.durations) return;
  const Strategy s = o.strategy;
  const std::string violation = detail::violated_constraint(c, s, *o.durations, p.nonlinear);
  const bool usable = o.status == SolveStatus::kOptimal || o.status == SolveStatus::kAcceptable;
  if (!violation.empty() && usable) {
    o.status = SolveStatus::kInfeasible;
    if (s == Strategy::kBaseline) {
      o.detail = "the uniform law does not meet the options: " + violation;
    } else if (o.detail.empty() || is_filter_strategy(s)) {
      o.detail = (o.detail.empty() ? "" : o.detail + "; ") + violation;
    } else {
      o.detail = violation;
    }
  } else if (violation.empty() && o.status == SolveStatus::kInfeasible && !is_filter_strategy(s)) {
    o.status = SolveStatus::kAcceptable;
    o.detail =
        "the law meets every constraint on the verification, though its objective was "
        "not minimised";
  }
}

std::optional<RangeJudgement> judge_over_range(const detail::StrategyContext& c,
                                               const MotionLaw& law, const LawPrediction& nominal) {
  if (!c.robust()) return std::nullopt;
  // A turned tank is judged on its walls and corners with both directions' frequencies swept.
  // A rectangular tank is judged on its own walls and corners by its own nonlinear model (the
  // second mode and the range checks included), as simulate() of the scaled tank answers.
  const std::pair at_zero{nominal.linear, nominal.nonlinear};
  RangeJudgement j{c.rectangular != nullptr
                       ? *rectangular_robustness_report(*c.rectangular, law, c.sweep, at_zero)
                       : robustness_report(c.model, law, c.sweep, at_zero),
                   {}};
  j.worst.kinematics = nominal.kinematics;
  j.worst.linear = j.report.worst_linear;
  j.worst.nonlinear = j.report.worst_nonlinear;
  return j;
}

/// The prediction a law is verified and judged by: its worst case over the range, or its own.
const LawPrediction& judged(const std::optional<RangeJudgement>& range,
                            const LawPrediction& nominal) {
  return range ? range->worst : nominal;
}

bool usable_status(SolveStatus status) {
  return status == SolveStatus::kOptimal || status == SolveStatus::kAcceptable ||
         status == SolveStatus::kTimeLimit;
}

bool finite_verification(const Verification& v) {
  return finite_prediction(v.prediction) && (!v.range || finite_prediction(v.range->worst));
}

/// The outcome's verification in the context `c` (the one made while choosing its design, when
/// made), its status judged by it (SPEC §5 "Honest status"; a law the models cannot follow is
/// left to its caller's refusal).
Verification verification_of(const detail::StrategyContext& c, Outcome& o) {
  if (o.verification) return *std::exchange(o.verification, std::nullopt);
  Verification v;
  v.prediction = predict_outcome(c, o, &v.out_of_range);
  v.range = judge_over_range(c, o.law, v.prediction);
  if (finite_verification(v)) verify(c, o, judged(v.range, v.prediction));
  return v;
}

/// The strategies whose design takes a turned tank's second direction in (set_directions).
bool designs_over_directions(Strategy s) {
  switch (s) {
    case Strategy::kNotch:
    case Strategy::kMultiNotch:
    case Strategy::kMinJerkBand:
    case Strategy::kFirChain:
    case Strategy::kShaper:
    case Strategy::kIir:
      return true;
    default:
      return false;
  }
}

/// One design of a strategy on a turned tank: its outcome and verification, the direction it was
/// designed for alone (null: over both) and its rank, lower better: 0 usable and not worse than
/// the uniform law, 1 usable but worse, 2 not usable (a design the budget cut included).
struct Design {
  Outcome outcome;
  Verification verification;
  const char* alone{nullptr};
  int rank{2};
  [[nodiscard]] double rest() const {
    return judged(verification.range, verification.prediction).nonlinear.rest.value;
  }
};

Design ranked(Outcome o, Verification v, const char* alone, const GuardReference& guard) {
  Design d{std::move(o), std::move(v), alone, 2};
  // A design the budget cut is not a design of this strategy to prefer.
  const SolveStatus st = d.outcome.status;
  if (finite_verification(d.verification) &&
      (st == SolveStatus::kOptimal || st == SolveStatus::kAcceptable)) {
    const bool worse =
        !worse_than_baseline(d.verification.prediction, guard, d.verification.out_of_range.empty())
             .empty();
    d.rank = worse ? 1 : 0;
  }
  return d;
}

bool ranks_before(const Design& a, const Design& b) {
  if (a.rank != b.rank) return a.rank < b.rank;
  return a.rest() < b.rest() || (std::isfinite(a.rest()) && !std::isfinite(b.rest()));
}

/// The lower eta_rest of a verified verification (nominal, or the worst over the range), on the
/// linear model where the tank's nonlinear model holds for only one of the two.
bool rests_lower(const Verification& a, const Verification& b) {
  const LawPrediction& pa = judged(a.range, a.prediction);
  const LawPrediction& pb = judged(b.range, b.prediction);
  const bool linear = a.out_of_range.empty() != b.out_of_range.empty();
  return linear ? pa.linear.rest.value < pb.linear.rest.value
                : pa.nonlinear.rest.value < pb.nonlinear.rest.value;
}

/// A spectral law and its mirror (its durations reversed) reach the same objective: |X| and the
/// jerk do not see the direction of time, so which of the two a solve returns turns on the last
/// digits of its inputs. On a turned tank the two directions' waves add at the corners with
/// phases the mirror changes (multi_notch on the README's cup flipped between the two across
/// 1e-12 degree, eta_rest 0.857 and 0.936 mm): both are verified on the tank and the one that
/// rests lower is kept, the one whose durations compare lower on a tie. `v` is `o`'s
/// verification.
void keep_better_mirror(const detail::StrategyContext& c, Outcome& o, Verification& v) {
  const Strategy s = o.strategy;
  const bool mirror_blind =
      s == Strategy::kNotch || s == Strategy::kMultiNotch || s == Strategy::kMinJerkBand;
  if (!mirror_blind || !o.durations || !finite_verification(v) || c.deadline.expired()) return;
  Durations mirrored;
  std::reverse_copy(o.durations->begin(), o.durations->end(), mirrored.begin());
  if (mirrored == *o.durations) return;
  Outcome m = o;
  m.durations = mirrored;
  m.law = SevenSegmentLaw(mirrored, c.format.stroke).law();
  m.verification.reset();
  Verification mv = verification_of(c, m);
  if (!finite_verification(mv)) return;
  const bool better = rests_lower(mv, v) ||
                      (!rests_lower(v, mv) &&
                       std::lexicographical_compare(mirrored.begin(), mirrored.end(),
                                                    o.durations->begin(), o.durations->end()));
  if (!better) return;
  o = std::move(m);
  v = std::move(mv);
}

/// The design for `direction` alone: the law the strategy gives on that direction's axis (the
/// context of `c` with that direction's model and set_directions left out), verified on the tank.
Design own_design(const detail::StrategyContext& c, Strategy s, const DrivenDirection& direction,
                  const GuardReference& guard) {
  detail::StrategyContext own{c.format, c.options, direction.model, c.space, c.deadline};
  own.rectangular = c.rectangular;
  own.uniform_prediction = c.uniform_prediction;
  own.uniform_out_of_range = c.uniform_out_of_range;
  own.one_direction = true;
  detail::set_design(own);
  detail::set_references(own, c.eta_ref);
  Outcome o = run_design(own, s, {});
  Verification v = verification_of(own, o);
  keep_better_mirror(own, o, v);
  return ranked(std::move(o), std::move(v),
                direction.axis == TankAxis::kLength ? "length" : "width", guard);
}

/// Whether `d` rests above the reference law of `guard` (the uniform law) on the tank: its
/// nominal eta_rest on the nonlinear model, on the linear one where the tank's nonlinear model
/// holds for only one of the two laws (as worse_than_baseline compares them).
/// The nominal eta_rest of `d` and of the reference law of `guard` [m] as they are compared: on
/// the nonlinear model, on the linear one (`linear`) where the tank's nonlinear model holds for
/// only one of the two laws (as worse_than_baseline compares them).
struct RestComparison {
  double own{}, reference{};
  bool linear{false};
};
RestComparison rest_comparison(const Design& d, const GuardReference& guard) {
  const bool linear = d.verification.out_of_range.empty() != guard.nonlinear_in_range;
  const LawPrediction& p = d.verification.prediction;
  const LawPrediction& ref = guard.prediction;
  return linear ? RestComparison{p.linear.rest.value, ref.linear.rest.value, true}
                : RestComparison{p.nonlinear.rest.value, ref.nonlinear.rest.value, false};
}

bool rests_above_reference(const Design& d, const GuardReference& guard) {
  const RestComparison c = rest_comparison(d, guard);
  return c.own > c.reference;
}

/// Why `own`, designed for one direction alone, is the plan's law rather than `both`.
std::string why_alone(const Design& own, const Design& both, const GuardReference& guard) {
  const std::string other = std::string(own.alone) == "length" ? "width" : "length";
  const std::string head = std::string("designed for the ") + own.alone +
                           "'s first mode alone (the law this strategy gives along the " +
                           own.alone + ", which does not act on the " + other + "'s first mode): ";
  if (both.rank == 2 && own.rank == 2) {
    return head + "neither it nor the design over both directions is usable on the tank, and it " +
           "rests lower: on the tank at " + sig3(own.rest() * 1e3) +
           " mm, the design over both directions (" + to_string(both.outcome.status) + ") at " +
           sig3(both.rest() * 1e3) + " mm";
  }
  if (both.rank == 2 && own.rank < 2) {
    // Why: an optimiser's detail is its violation; a filter's ends with it.
    const std::string& d = both.outcome.detail;
    const std::size_t last = d.rfind("; ");
    const std::string why = is_filter_strategy(both.outcome.strategy)
                                ? (last == std::string::npos ? d : d.substr(last + 2))
                                : d.substr(0, d.find("; "));
    return head + "the design over both directions is " + to_string(both.outcome.status) +
           " on the tank" + (why.empty() ? "" : " (" + why + ")");
  }
  // The designs are ranked on the figures they are judged by: the worst over the uncertainty
  // range when one is given.
  const std::string rests =
      "on the tank it rests at " + sig3(own.rest() * 1e3) +
      " mm, the design over both directions at " + sig3(both.rest() * 1e3) + " mm" +
      (both.verification.range ? " (each its worst over the uncertainty range)" : "");
  if (both.rank == 1 && own.rank == 0) {
    return head +
           "the design over both directions sloshes more than the uniform law on the tank (its "
           "worse_than_baseline warning); " +
           rests;
  }
  if (both.rank == 0 && rests_above_reference(both, guard)) {
    // The nominal figures, as the uniform law has no others here.
    const std::string reference = guard.uniform ? "the uniform law" : "baseline's law";
    const RestComparison c = rest_comparison(both, guard);
    return head + "the design over both directions rests above " + reference +
           " on the tank (nominal eta_rest " + sig3(c.own * 1e3) + " mm against " +
           sig3(c.reference * 1e3) + " mm" + (c.linear ? ", on the linear model" : "") + "); " +
           rests;
  }
  return head + rests;
}

/// A design over both of a turned tank's directions that is not usable on the tank (its own
/// criterion missed: min_jerk_band's band over both modes out of reach where each mode's own is
/// not), sloshes more than the uniform law there (worse_than_baseline) or rests above it, against
/// each direction's own design (the law the strategy gives on that axis), all verified on the
/// tank: the best by rank, then the lower eta_rest as judged (nominal, or the worst over the
/// range). A usable design over both that rests no higher than the uniform law stands: it is the
/// strategy's design for the turned tank (SPEC §15: its notches and band cover both directions),
/// and it moves continuously with the orientation. Resting above the uniform law, not only the
/// guard's 5 % and 0.5 mm, makes way for the own designs: an iir over both 24 % above the uniform
/// law at 89 degrees stood while the width's own design rested 80 % below it. Both
/// directions' own designs are weighed, not only the most excited one's: which direction that is
/// changes at an orientation (atan(L / W) for the static wall heights), and the choice would
/// jump there.
Outcome best_of_designs(const detail::StrategyContext& c, Outcome both,
                        const GuardReference& guard) {
  const Strategy s = both.strategy;
  Verification v = verification_of(c, both);
  keep_better_mirror(c, both, v);
  std::vector<Design> designs;
  designs.push_back(ranked(std::move(both), std::move(v), nullptr, guard));
  if (designs.front().rank == 0 && !rests_above_reference(designs.front(), guard)) {
    designs.front().outcome.verification = std::move(designs.front().verification);
    return std::move(designs.front().outcome);
  }
  const std::vector<DrivenDirection> directions = driven_directions(*c.rectangular);
  for (const DrivenDirection& d : directions) {
    if (c.deadline.expired()) break;
    designs.push_back(own_design(c, s, d, guard));
  }
  // Only a proper plan replaces the design over both: a direction's own design that is usable
  // and no worse than the uniform law (where none is, the design over both stays, and with it
  // the plan's continuity with the orientation).
  // An unusable design over both also gives way to an unusable own design that rests lower
  // (infeasible either way): min_jerk_band over both directions of a 200 x 60 mm tray at 15
  // degrees rested at 15.1 mm, its length's own law (its band out of reach too) at 2.9 mm.
  const bool both_unusable = designs.front().rank == 2;
  std::size_t best = 0;
  for (std::size_t k = 1; k < designs.size(); ++k) {
    const bool qualifies = designs[k].rank == 0 || (both_unusable && designs[k].rank == 2);
    if (qualifies && ranks_before(designs[k], designs[best])) best = k;
  }
  Design& kept = designs[best];
  for (std::size_t k = 0; k < designs.size(); ++k) {
    if (k == best) continue;
    kept.outcome.solver.evaluations += designs[k].outcome.solver.evaluations;
    kept.outcome.solver.starts += designs[k].outcome.solver.starts;
  }
  if (kept.alone != nullptr) {
    // The choice leads: the design's own account (a shaper's "no residual at f1") is that of
    // the one direction.
    const std::string& d = kept.outcome.detail;
    kept.outcome.detail = why_alone(kept, designs.front(), guard) + (d.empty() ? "" : "; " + d);
  }
  kept.outcome.verification = std::move(kept.verification);
  return std::move(kept.outcome);
}

/// `o`, designed in the plan's context, against each direction's own design where the tank is
/// turned (not once the budget is spent).
Outcome with_own_designs(const detail::StrategyContext& c, Outcome o, const GuardReference& guard) {
  if (!c.over_directions || !designs_over_directions(o.strategy) || c.deadline.expired()) return o;
  return best_of_designs(c, std::move(o), guard);
}

/// Runs one strategy (not kAuto) on the plan's tank; `seeds` are time_domain's extra starts.
Outcome run_strategy(const detail::StrategyContext& c, Strategy s,
                     const std::vector<Durations>& seeds, const GuardReference& guard) {
  return with_own_designs(c, run_design(c, s, seeds), guard);
}

/// The spectral optima, which seed the time-domain starts (SPEC §5): the designs in the plan's
/// context (on a turned tank, over both directions: time_domain bounds both); their outcomes,
/// each weighed against the axis's design, are appended to `outcomes` when not null.
std::vector<Durations> spectral_seeds(const detail::StrategyContext& c,
                                      std::vector<Outcome>* outcomes, const GuardReference& guard) {
  std::vector<Durations> seeds;
  for (Strategy s : {Strategy::kNotch, Strategy::kMultiNotch, Strategy::kMinJerkBand}) {
    Outcome o = run_design(c, s, {});
    if (o.status == SolveStatus::kOptimal || o.status == SolveStatus::kAcceptable) {
      seeds.push_back(*o.durations);
    }
    if (outcomes != nullptr) outcomes->push_back(with_own_designs(c, std::move(o), guard));
  }
  return seeds;
}

/// The strategy's own outcome, before the budget's verdicts on its report and its verification
/// (PlanResult::solved_status and solved_detail).
struct Solved {
  SolveStatus status;
  std::string detail;
};

/// The law plan() returns: its outcome (solver figures summed over the candidates for kAuto), its
/// verified prediction, the sentence about how it was obtained, and its worse_than_baseline
/// warning (or empty).
struct Selection {
  Outcome outcome;
  LawPrediction prediction;
  /// Why the rectangular nonlinear model does not hold for the law (predict_outcome's), so that
  /// the plan's warnings do not simulate the law again.
  std::string out_of_range;
  std::optional<RangeJudgement> range;  ///< over the uncertainty range, when robust
  std::string detail;
  std::string worse;
};

Selection run_single(const detail::StrategyContext& c, Strategy strategy,
                     const GuardReference& baseline) {
  std::vector<Durations> seeds;
  // A warm start replaces the multi-start, the spectral seeds included (continuation).
  if (strategy == Strategy::kTimeDomain && !c.options.warm_start) {
    seeds = spectral_seeds(c, nullptr, baseline);
  }
  Selection s;
  s.outcome = run_strategy(c, strategy, seeds, baseline);
  Verification v = verification_of(c, s.outcome);
  s.prediction = std::move(v.prediction);
  s.range = std::move(v.range);
  s.out_of_range = std::move(v.out_of_range);
  s.detail = s.outcome.detail;
  // baseline is the reference itself (when the options exclude the uniform law, its nearest
  // admissible law): it is never "worse than the baseline".
  if (strategy != Strategy::kBaseline) {
    s.worse = worse_than_baseline(s.prediction, baseline, s.out_of_range.empty());
  }
  return s;
}

/// As the strategy's own plan says (SPEC §5): a candidate that sloshes more than the uniform law
/// (its worse_than_baseline warning) is not optimal.
void not_optimal_when_worse(PlanCandidate& k) {
  if (!k.worse_than_baseline.empty() && k.status == SolveStatus::kOptimal) {
    k.status = SolveStatus::kAcceptable;
  }
}

/// Whether a candidate competes in choose_auto: usable, and not worse than the uniform law while
/// a usable candidate that is not remains.
bool competes(const PlanCandidate& k, bool worse_than_baseline, bool any_not_worse) {
  return usable_status(k.status) && (!any_not_worse || !worse_than_baseline);
}

/// The prediction choose_auto judges a candidate by: with an uncertainty range, its worst case
/// over it.
const LawPrediction& judged_prediction(const PlanCandidate& k) {
  return k.worst_case ? *k.worst_case : k.prediction;
}

/// A candidate's peak acceleration, the tie-breaker on eta_rest [m/s^2].
double peak_acceleration(const PlanCandidate& k) {
  return std::max(k.prediction.kinematics.a_peak_positive, k.prediction.kinematics.a_peak_negative);
}

/// The rule's pass over the candidates in order: sets choice.index, choice.eligible and every
/// loser's reason, and beaten_by[k] to the candidate k lost to on eta_rest, recorded when the pass
/// rejects or replaces it (the tie rule is not transitive, so a loser judged again against the
/// final choice could get a reason the pass never applied).
void rank_candidates(const std::vector<PlanCandidate>& candidates,
                     const std::vector<bool>& worse_than_baseline, double best_motion,
                     AutoChoice& choice, std::vector<std::size_t>& beaten_by) {
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const auto& cand = candidates[k];
    if (!usable_status(cand.status)) {
      choice.lost[k] = CandidateLoss::kNotUsable;
      continue;
    }
    if (!competes(cand, worse_than_baseline[k], choice.any_not_worse)) {
      choice.lost[k] = CandidateLoss::kWorseThanBaseline;
      continue;
    }
    if (judged_prediction(cand).nonlinear.motion.value > kAutoMotionSlack * best_motion) {
      choice.lost[k] = CandidateLoss::kMotionAboveBest;
      continue;
    }
    if (!choice.eligible) {
      choice.index = k;
      choice.eligible = true;
      continue;
    }
    const auto& cur = candidates[choice.index];
    const double a = judged_prediction(cand).nonlinear.rest.value;
    const double b = judged_prediction(cur).nonlinear.rest.value;
    const bool tie = std::abs(a - b) <= kAutoTieTolerance * b;
    if (a < b * (1.0 - kAutoTieTolerance) ||
        (tie && peak_acceleration(cand) < peak_acceleration(cur))) {
      choice.lost[choice.index] = tie ? CandidateLoss::kTieOnRest : CandidateLoss::kHigherRest;
      beaten_by[choice.index] = k;
      choice.index = k;
    } else {
      choice.lost[k] = tie ? CandidateLoss::kTieOnRest : CandidateLoss::kHigherRest;
      beaten_by[k] = choice.index;
    }
  }
}

/// choice.lost_detail: the sentence of every loss with the figures that decided it (a client can
/// check the choice against the candidates' predictions).
void explain_losses(const std::vector<PlanCandidate>& candidates, double best_motion,
                    const std::vector<std::size_t>& beaten_by, AutoChoice& choice) {
  const PlanCandidate& chosen = candidates[choice.index];
  const std::string by_worst = chosen.worst_case ? " (worst case over the uncertainty range)" : "";
  auto mm = [](double metres) { return sig3(metres * 1e3) + " mm"; };
  // The candidate a loser lost to, named as the chosen one or as the one that then replaced it.
  auto winner = [&](std::size_t w) {
    if (w == choice.index) return "the chosen " + to_string(chosen.strategy);
    return to_string(candidates[w].strategy) + " (kept then, later replaced; auto chose " +
           to_string(chosen.strategy) + ")";
  };
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const PlanCandidate& cand = candidates[k];
    const LawPrediction& p = judged_prediction(cand);
    const PlanCandidate& won = candidates[beaten_by[k]];
    std::string& detail = choice.lost_detail[k];
    switch (choice.lost[k]) {
      case CandidateLoss::kNone:
      case CandidateLoss::kAboveBound:  // choose_auto writes its sentence
        break;
      case CandidateLoss::kNotUsable:
        detail = "status " + to_string(cand.status) +
                 ": only optimal, acceptable and time_limit candidates compete";
        break;
      case CandidateLoss::kWorseThanBaseline:
        detail =
            "worse than the uniform law (its worse_than_baseline warning) while a candidate that "
            "is not competes";
        break;
      case CandidateLoss::kMotionAboveBest:
        detail = "eta_motion " + mm(p.nonlinear.motion.value) + by_worst +
                 " is more than 5 % above the best " + mm(best_motion);
        break;
      case CandidateLoss::kTieOnRest:
        detail = "eta_rest " + mm(p.nonlinear.rest.value) + by_worst + " ties with " +
                 winner(beaten_by[k]) + " and its peak acceleration " +
                 sig3(peak_acceleration(cand)) + " m/s^2 is not below " +
                 sig3(peak_acceleration(won)) + " m/s^2";
        break;
      case CandidateLoss::kHigherRest: {
        // Against the chosen one when its eta_rest is below this one's (a client compares the
        // two); else (a chain of ties raised it) against the one this candidate lost to.
        const std::size_t shown =
            judged_prediction(chosen).nonlinear.rest.value < p.nonlinear.rest.value ? choice.index
                                                                                    : beaten_by[k];
        detail = "eta_rest " + mm(p.nonlinear.rest.value) + by_worst + " vs " +
                 mm(judged_prediction(candidates[shown]).nonlinear.rest.value) + " of " +
                 winner(shown);
        break;
      }
    }
  }
}

}  // namespace

namespace {

/// "eta_rest" or "eta_motion", and its option.
std::string bound_figure(const BoundVerdict& b) {
  return b.on_rest ? "eta_rest" : "eta_motion";
}
std::string bound_option(const BoundVerdict& b) {
  return b.on_rest ? "eta_rest_max_mm" : "eta_motion_max_mm";
}

/// No usable candidate meets its bound: the least infeasible one (lowest bounded figure among
/// those whose only fault is the bound, and among those not worse than the uniform law while one
/// is; ties: the earlier) is returned, and every other one says why it was not.
AutoChoice least_infeasible(const std::vector<PlanCandidate>& candidates,
                            const std::vector<bool>& worse_than_baseline,
                            const std::vector<BoundVerdict>& bounds) {
  AutoChoice choice;
  choice.bound_missed = true;
  choice.lost.assign(candidates.size(), CandidateLoss::kNotUsable);
  choice.lost_detail.assign(candidates.size(), std::string());
  auto fault_is_bound = [&](std::size_t k) {
    return usable_status(candidates[k].status) || bounds[k].others_met;
  };
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    choice.any_not_worse = choice.any_not_worse || (fault_is_bound(k) && !worse_than_baseline[k]);
  }
  auto considered = [&](std::size_t k) {
    return fault_is_bound(k) && (!choice.any_not_worse || !worse_than_baseline[k]);
  };
  bool found = false;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (considered(k) && (!found || bounds[k].value < bounds[choice.index].value)) {
      choice.index = k;
      found = true;
    }
  }
  const BoundVerdict& best = bounds[choice.index];
  auto mm = [](double metres) { return sig3(metres * 1e3) + " mm"; };
  const std::string chosen = to_string(candidates[choice.index].strategy);
  choice.bound_sentence = "no candidate meets " + bound_figure(best) + " <= " + mm(best.bound) +
                          " (" + bound_option(best) + "): the lowest is " + mm(best.value) + " (" +
                          chosen + "), which auto returns; lengthen the motion or relax the limit";
  choice.lost[choice.index] = CandidateLoss::kNone;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (k == choice.index) continue;
    if (fault_is_bound(k) && !considered(k)) {
      choice.lost[k] = CandidateLoss::kWorseThanBaseline;
      choice.lost_detail[k] = bound_figure(bounds[k]) + " " + mm(bounds[k].value) +
                              " but worse than the uniform law (its worse_than_baseline warning) "
                              "while a candidate that is not remains; no candidate meets " +
                              bound_figure(best) + " <= " + mm(best.bound);
    } else if (considered(k)) {
      choice.lost[k] = CandidateLoss::kAboveBound;
      choice.lost_detail[k] = bound_figure(bounds[k]) + " " + mm(bounds[k].value) + " vs " +
                              mm(best.value) + " of the chosen " + chosen +
                              "; no candidate meets " + bound_figure(best) +
                              " <= " + mm(best.bound);
    } else {
      choice.lost_detail[k] = "status " + to_string(candidates[k].status) +
                              ": only optimal, acceptable and time_limit candidates compete";
    }
  }
  return choice;
}

AutoChoice choose_unbounded(const std::vector<PlanCandidate>& candidates,
                            const std::vector<bool>& worse_than_baseline) {
  // SPEC §5: the lowest eta_rest among those whose eta_motion is within 5 % of the best (ties:
  // lower peak acceleration); infeasible or failed candidates do not compete, nor do those worse
  // than the uniform law while one that is not remains (the baseline never is).
  AutoChoice choice;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    choice.any_not_worse =
        choice.any_not_worse || (usable_status(candidates[k].status) && !worse_than_baseline[k]);
  }
  // With an uncertainty range the candidates are judged by their worst case over it.
  double best_motion = INFINITY;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (competes(candidates[k], worse_than_baseline[k], choice.any_not_worse)) {
      best_motion = std::min(best_motion, judged_prediction(candidates[k]).nonlinear.motion.value);
    }
  }
  choice.lost.assign(candidates.size(), CandidateLoss::kNone);
  choice.lost_detail.assign(candidates.size(), std::string());
  std::vector<std::size_t> beaten_by(candidates.size(), 0);
  rank_candidates(candidates, worse_than_baseline, best_motion, choice, beaten_by);
  // With no eligible candidate the first one is returned, whatever excluded it.
  choice.lost[choice.index] = CandidateLoss::kNone;
  explain_losses(candidates, best_motion, beaten_by, choice);
  return choice;
}

}  // namespace

AutoChoice choose_auto(const std::vector<PlanCandidate>& candidates,
                       const std::vector<bool>& worse_than_baseline,
                       const std::vector<BoundVerdict>& bounds) {
  if (bounds.empty()) return choose_unbounded(candidates, worse_than_baseline);
  // A usable candidate that breaks the eta bound competes only against the others that break
  // it: when one meets it, they lose to it; when none does, the least infeasible is returned.
  bool any_within = false;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    any_within = any_within || (usable_status(candidates[k].status) && bounds[k].meets());
  }
  bool any_considered = false;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    any_considered = any_considered || usable_status(candidates[k].status) || bounds[k].others_met;
  }
  if (!any_within) {
    return any_considered ? least_infeasible(candidates, worse_than_baseline, bounds)
                          : choose_unbounded(candidates, worse_than_baseline);
  }
  // The rule among the candidates within the bound: the others are judged as not usable, then
  // named for the bound they break.
  std::vector<PlanCandidate> within = candidates;
  std::vector<std::size_t> above;
  for (std::size_t k = 0; k < within.size(); ++k) {
    if (usable_status(within[k].status) && !bounds[k].meets()) {
      within[k].status = SolveStatus::kInfeasible;
      above.push_back(k);
    }
  }
  AutoChoice choice = choose_unbounded(within, worse_than_baseline);
  for (std::size_t k : above) {
    const BoundVerdict& b = bounds[k];
    choice.lost[k] = CandidateLoss::kAboveBound;
    choice.lost_detail[k] = bound_figure(b) + " " + sig3(b.value * 1e3) + " mm is above " +
                            bound_option(b) + " = " + sig3(b.bound * 1e3) +
                            " mm, which another candidate meets";
  }
  return choice;
}

namespace {

/// Marks the chosen candidate and every loser's reason; returns the sentence of the choice. The
/// guard's reference is named as it is (baseline's law when the options exclude the uniform law).
std::string record_choice(const detail::StrategyContext& c, const AutoChoice& choice,
                          const GuardReference& baseline, std::vector<PlanCandidate>& candidates) {
  const std::string reference =
      baseline.uniform ? "the uniform law" : "baseline's law (the uniform law breaks the options)";
  candidates[choice.index].chosen = true;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    candidates[k].lost = choice.lost[k];
    candidates[k].lost_detail = choice.lost_detail[k];
    if (choice.lost[k] == CandidateLoss::kWorseThanBaseline && !baseline.uniform) {
      candidates[k].lost_detail = "worse than " + reference +
                                  " (its worse_than_baseline warning) while a candidate that is "
                                  "not competes";
    }
  }
  if (choice.bound_missed) return choice.bound_sentence;
  if (!choice.eligible) {
    return std::string("no candidate meets every constraint; auto returns ") +
           (baseline.uniform ? "the uniform law" : "baseline's law");
  }
  return "auto chose " + to_string(candidates[choice.index].strategy) +
         (c.robust() ? " (judged by the worst case over the uncertainty range: " : " (") +
         "lowest eta_rest among the candidates within 5 % of the best eta_motion, " +
         (choice.any_not_worse
              ? "none worse than " + reference + ")"
              : "all worse than " + reference + ", which does not meet the options)") +
         (choice.ranked_on_linear ? detail::kRankedOnLinearModel : "");
}

/// A verified candidate against time_domain's eta bound (BoundVerdict). Its other constraints
/// are met when it is usable, or when it is a 7-segment law that meets the options' ramps and
/// machine limits (time_domain's least infeasible law, whose one fault is the bound).
BoundVerdict bound_verdict(const detail::StrategyContext& c, const Outcome& o,
                           const LawPrediction& p) {
  BoundVerdict b;
  b.on_rest = c.options.objective == TimeDomainObjective::kMotion;
  b.value = b.on_rest ? p.nonlinear.rest.value : p.nonlinear.motion.value;
  b.bound = b.on_rest ? c.options.eta_rest_max : c.eta_motion_max;
  b.others_met =
      usable_status(o.status) ||
      (o.strategy == Strategy::kTimeDomain && o.durations &&
       detail::violated_constraint(c, Strategy::kBaseline, *o.durations, p.nonlinear).empty());
  return b;
}

/// The models diverge for every candidate of auto (over the uncertainty range, say): the uniform
/// law `first` goes back to plan(), whose finiteness check refuses it with the reason.
Selection all_diverged(const detail::StrategyContext& c, Outcome first,
                       const std::string& diverged) {
  Selection none;
  none.outcome = std::move(first);
  none.prediction = predict_outcome(c, none.outcome, &none.out_of_range);
  none.range = judge_over_range(c, none.outcome.law, none.prediction);
  none.detail = "left out, the sloshing models diverge for their laws: " + diverged;
  return none;
}

/// Per candidate, whether the rectangular nonlinear model holds for its law (no reason why not).
std::vector<bool> in_range_of(const std::vector<std::string>& out_of_range) {
  std::vector<bool> in_range;
  for (const std::string& why : out_of_range) in_range.push_back(why.empty());
  return in_range;
}

/// kAuto: every strategy but iir, verified, into `candidates`; the one choose_auto picks.
/// auto's candidates solved: every strategy but iir (the shaper's general law not for a
/// MC_MoveAbsolute block), baseline first.
std::vector<Outcome> auto_outcomes(const detail::StrategyContext& c, const GuardReference& guard) {
  std::vector<Outcome> outcomes;
  outcomes.push_back(run_strategy(c, Strategy::kBaseline, {}, guard));
  const std::vector<Durations> seeds = spectral_seeds(c, &outcomes, guard);
  outcomes.push_back(run_strategy(c, Strategy::kTimeDomain, seeds, guard));
  outcomes.push_back(run_strategy(c, Strategy::kFirChain, {}, guard));
  if (c.options.drive_profile != DriveProfile::kMoveAbsolute) {
    outcomes.push_back(run_strategy(c, Strategy::kShaper, {}, guard));
  }
  return outcomes;
}

Selection run_auto(const detail::StrategyContext& c, const GuardReference& baseline,
                   std::vector<PlanCandidate>& candidates) {
  std::vector<Outcome> outcomes = auto_outcomes(c, baseline);
  int evaluations = 0, starts = 0;
  std::vector<bool> worse;           // candidate k carries a worse_than_baseline warning
  std::vector<BoundVerdict> bounds;  // and how it stands against the eta bound
  std::vector<Outcome> kept;         // the outcomes of `candidates`, index for index
  std::vector<std::optional<RangeJudgement>> ranges;  // and their sweeps over the range
  std::vector<std::string> out_of_range;  // and why the rectangular nonlinear model does not hold
  std::string diverged;                   // the candidates the models cannot follow, left out
  std::string unverified;                 // the candidates the budget left no time to verify
  for (Outcome& o : outcomes) {
    evaluations += o.solver.evaluations;
    starts += o.solver.starts;
    if (!candidates.empty() && c.deadline.expired()) {
      // Each verification simulates the whole motion on the models (a second or more for a tank
      // whose period is tiny against a long motion): once the budget is spent, auto chooses
      // among the laws it verified in time.
      unverified += (unverified.empty() ? "" : ", ") + to_string(o.strategy);
      continue;
    }
    PlanCandidate cand;
    cand.strategy = o.strategy;
    cand.law = o.law;
    Verification v = verification_of(c, o);
    if (!finite_verification(v)) {
      diverged += (diverged.empty() ? "" : ", ") + to_string(o.strategy);
      continue;
    }
    std::string why_linear = std::move(v.out_of_range);
    cand.prediction = std::move(v.prediction);
    std::optional<RangeJudgement> range = std::move(v.range);
    if (range) cand.worst_case = range->worst;
    bounds.push_back(bound_verdict(c, o, judged(range, cand.prediction)));
    cand.status = o.status;
    cand.durations = o.durations;
    if (o.strategy != Strategy::kBaseline) {
      cand.worse_than_baseline = worse_than_baseline(cand.prediction, baseline, why_linear.empty());
    }
    not_optimal_when_worse(cand);
    worse.push_back(!cand.worse_than_baseline.empty());
    candidates.push_back(std::move(cand));
    kept.push_back(std::move(o));
    ranges.push_back(std::move(range));
    out_of_range.push_back(std::move(why_linear));
  }
  if (candidates.empty()) return all_diverged(c, std::move(outcomes.front()), diverged);
  const AutoChoice choice =
      detail::choose_on_one_model(candidates, in_range_of(out_of_range), worse, bounds);
  Selection s;
  s.outcome = std::move(kept[choice.index]);
  // The least infeasible law when no candidate meets the eta bound: never optimal.
  if (choice.bound_missed) {
    s.outcome.status = SolveStatus::kInfeasible;
    s.outcome.detail.clear();
  }
  s.outcome.solver.evaluations = evaluations;
  s.outcome.solver.starts = starts;
  std::string chose = record_choice(c, choice, baseline, candidates);
  if (!diverged.empty()) {
    chose += "; left out, the sloshing models diverge for their laws: " + diverged;
  }
  if (!unverified.empty()) {
    chose += "; left out, the budget ran out before their laws were verified: " + unverified;
  }
  const std::string& own = s.outcome.detail;
  if (s.outcome.status == SolveStatus::kAcceptable && !own.empty()) {
    // Why the chosen law is only acceptable (its own account's first clause) leads.
    const std::size_t why = own.find("; ");
    s.detail = own.substr(0, why) + "; " + chose +
               (why == std::string::npos ? std::string() : own.substr(why));
  } else {
    s.detail = chose + (own.empty() ? "" : "; " + own);
  }
  s.worse = candidates[choice.index].worse_than_baseline;
  s.prediction = candidates[choice.index].prediction;
  s.range = std::move(ranges[choice.index]);
  s.out_of_range = std::move(out_of_range[choice.index]);
  return s;
}

/// The guard's reference: the uniform law's prediction `uniform` when the options admit it, else
/// that of baseline's admissible law (simulated here; the uniform law's when it is not finite).
/// `uniform_in_range`: the rectangular nonlinear model holds for the uniform law.
GuardReference guard_reference(const detail::StrategyContext& c, const LawPrediction& uniform,
                               bool uniform_in_range) {
  if (c.space.uniform_inside()) return {uniform, true, uniform_in_range};
  const Durations d = c.space.nearest_uniform();
  std::string why_linear;
  LawPrediction p = predict(c.model, c.rectangular, SevenSegmentLaw(d, c.format.stroke).law(),
                            c.options.rest_time, &why_linear);
  if (!finite_prediction(p)) return {uniform, true, uniform_in_range};
  return {std::move(p), false, why_linear.empty()};
}

/// The sentence of an infeasible optimised law: the machine limits first when they alone cannot
/// hold; otherwise the strategy's own sentence (constraint, limit, best value reached).
std::string infeasible_sentence(const detail::StrategyContext& c, const PlanResult& r,
                                Strategy result_strategy, const std::string& detail_text) {
  std::string limits;
  // (The uniform law is not searched: its own sentence says which option it breaks.)
  if (result_strategy != Strategy::kBaseline && c.space.limit_count() > 0 && r.durations &&
      !detail::violated_constraint(c, Strategy::kBaseline, *r.durations, r.prediction.nonlinear)
           .empty()) {
    limits = detail::explain_limits(c);
  }
  std::string message = !limits.empty() ? limits : detail_text;
  if (message.empty() && r.durations) {
    message = detail::violated_constraint(c, result_strategy, *r.durations, r.prediction.nonlinear);
  } else if (limits.empty() && r.durations && result_strategy != Strategy::kBaseline) {
    // The strategy's own constraint is named; a machine limit the returned law breaks too
    // (although the limits are reachable) must not go unsaid.
    const std::string also =
        detail::violated_constraint(c, Strategy::kBaseline, *r.durations, r.prediction.nonlinear);
    if (!also.empty()) message += "; moreover " + also;
  }
  message += result_strategy == Strategy::kBaseline
                 ? "; the durations returned are the uniform law, not a solution: plan with "
                   "a strategy that holds the options"
                 : "; the durations returned are the least infeasible found, not a solution";
  return message;
}

/// The message (Ceres' BriefReport): what happened, then what the law does.
std::string brief_report(const detail::StrategyContext& c, const PlanResult& r,
                         Strategy result_strategy, std::string detail_text) {
  std::string message;
  switch (r.status) {
    case SolveStatus::kOptimal:
    case SolveStatus::kAcceptable:
      message = to_string(r.strategy) + " " + to_string(r.status);
      break;
    case SolveStatus::kTimeLimit:
      message = "the time budget of " + sig3(c.options.time_limit) +
                " s ran out; returning the best admissible point found";
      break;
    case SolveStatus::kInfeasible:
      // A filter design says what it built and which constraint it misses.
      message = is_filter_strategy(result_strategy)
                    ? detail_text
                    : infeasible_sentence(c, r, result_strategy, detail_text);
      detail_text.clear();
      break;
    case SolveStatus::kFailed:
      message = "the solver failed; the durations returned are the uniform law";
      break;
  }
  if (!detail_text.empty()) message += ": " + detail_text;
  return message + ". " +
         summary_sentence(r.prediction, r.baseline, compares_on_linear_model(r.warnings));
}

/// Fills the result from the selected law.
void take_selection(PlanResult& r, Selection& s, const Format& format) {
  Outcome& o = s.outcome;
  r.status = o.status;
  r.durations = o.durations;
  r.law = std::move(o.law);
  r.design = std::move(o.design);
  r.solver.name = o.solver.solver;
  r.solver.iterations = o.solver.evaluations;
  r.solver.starts = o.solver.starts;
  r.solver.objective = o.solver.objective;
  r.prediction = s.prediction;
  if (r.durations) {
    const SevenSegmentLaw law(*r.durations, format.stroke);
    r.A = law.A();
    r.B = law.B();
  } else {
    r.A = r.prediction.kinematics.a_peak_positive;
    r.B = r.prediction.kinematics.a_peak_negative;
  }
  if (!std::isfinite(r.solver.objective)) r.solver.objective = 0.0;
}

/// The refusal of a law the sloshing models cannot follow, at the nominal model or somewhere in
/// the uncertainty range.
InvalidInput diverging_law(const KinematicSummary& k, Strategy strategy, bool at_nominal) {
  const double a_peak = std::max(k.a_peak_positive, k.a_peak_negative);
  return refused(PlanInput::kLawResponse, a_peak, non_negative(),
                 "the sloshing models diverge for the planned " + to_string(strategy) + " law " +
                     (at_nominal ? "on this format" : "somewhere in the uncertainty range") +
                     " (peak |a| = " + sig3(a_peak) +
                     " m/s^2): the motion is outside what they describe; lengthen the motion "
                     "time" +
                     (at_nominal ? "" : " or narrow the range"));
}

/// The uniform law's prediction as the strategies see it: on the axis's tank when a rectangular
/// tank is planned as on its axis (`axis_tank`), else the plan's own `r.baseline`;
/// `out_of_range` receives why the rectangular nonlinear model does not hold for it, or empty
/// (`baseline_out_of_range` is that of r.baseline).
LawPrediction strategies_reference(const PlanResult& r,
                                   const std::optional<RectangularModel>& axis_tank,
                                   const Format& format, double rest_time,
                                   const std::string& baseline_out_of_range,
                                   std::string& out_of_range) {
  if (!axis_tank) {
    out_of_range = baseline_out_of_range;
    return r.baseline;
  }
  return predict(r.model, &*axis_tank,
                 SevenSegmentLaw(uniform_durations(format.motion_time), format.stroke).law(),
                 rest_time, &out_of_range);
}

/// A rectangular tank's figures of the selected law on the tank itself, and why its nonlinear
/// model does not hold for the law into `s.out_of_range`: simulated again only when the
/// strategies saw the tank on its axis (`on_axis`; the figures differ in the last digits), and
/// the uniform law's reason (`baseline_out_of_range`) when the law is the uniform law
/// (`uniform`), whose prediction the selection did not simulate again.
void take_own_figures(PlanResult& r, Selection& s, bool on_axis, const Durations& uniform,
                      const std::string& baseline_out_of_range, double rest_time) {
  if (!r.rectangular) return;
  if (on_axis) {
    r.prediction = predict(r.model, &*r.rectangular, r.law, rest_time, &s.out_of_range);
  } else if (s.outcome.law_of_durations() && r.durations && *r.durations == uniform) {
    s.out_of_range = baseline_out_of_range;
  }
}

/// The plan's warnings: SPEC §2's validity warnings, the baseline guard's `worse`, and a
/// rectangular tank's (its nonlinear model out of range for the law, `out_of_range`, or for the
/// uniform law of reference, a motion too short to act on a mode), each once.
std::vector<Warning> plan_warnings(const Format& format, const PlanOptions& options,
                                   const PlanResult& r, const std::string& worse,
                                   std::string out_of_range,
                                   const std::string& baseline_out_of_range) {
  const double rest_time = options.rest_time;
  const bool law_in_range = out_of_range.empty();
  std::vector<Warning> w = validity_warnings(
      format,
      std::max(r.prediction.kinematics.a_peak_positive, r.prediction.kinematics.a_peak_negative),
      r.prediction.linear.motion.value, r.prediction.nonlinear.motion.value, law_in_range,
      r.prediction.linear.rest.value,
      r.prediction.linear_directions ? &*r.prediction.linear_directions : nullptr);
  if (!worse.empty()) w.push_back({WarningKind::kWorseThanBaseline, worse});
  if (!law_in_range) w.push_back({WarningKind::kNonlinearModelNotValid, std::move(out_of_range)});
  if (format.container.rectangular && r.rectangular) {
    for (Warning& t : modal_truncation_warnings(*format.container.rectangular, format.fill_height,
                                                *r.rectangular, r.law, rest_time)) {
      w.push_back(std::move(t));
    }
  }
  for (Warning& reference : detail::reference_model_warnings(law_in_range, baseline_out_of_range,
                                                             detail::peak_figures(r.prediction),
                                                             detail::peak_figures(r.baseline))) {
    w.push_back(std::move(reference));
  }
  if (r.rectangular) {
    // Against the uniform law's own linear eta_rest: the figure the floor bounds.
    std::string too_short = motion_too_short_for_mode(
        *r.rectangular, format.stroke, r.law.duration(), rest_time, r.baseline.linear.rest.value);
    if (!too_short.empty()) w.push_back({WarningKind::kMotionTooShort, std::move(too_short)});
  }
  if (auto range = detail::fill_range_beyond_models(format, options.uncertainty)) {
    w.push_back({WarningKind::kFillRangeBeyondModels, std::move(*range)});
  }
  return w;
}

/// The status and message of a plan whose warnings are set: the solve's status and account kept
/// (solved_status, solved_detail), then the warnings' caveats (SPEC §5 "Honest status").
/// The first rule the inputs break (the plan's inputs, the drive profile, the band), or nullopt.
std::optional<InvalidInput> input_refusal(const Format& format, Strategy strategy,
                                          const PlanOptions& options) {
  if (std::optional<InvalidInput> why = validate_plan_input(format, options)) return why;
  if (std::optional<InvalidInput> why = drive_profile_refusal(strategy, options.drive_profile)) {
    return why;
  }
  return band_refusal(strategy, format, options);
}

/// The budget covers the verification of the laws on the models, which for a tank whose period
/// is tiny against a long motion costs more than the solves: a plan that ran past it says so, as
/// a solve that ran out does, and is not cached as the budget's answer.
void take_budget_overrun(PlanResult& r, Selection& s, const Format& format,
                         const detail::Deadline& deadline) {
  if (!deadline.expired() ||
      !(r.status == SolveStatus::kOptimal || r.status == SolveStatus::kAcceptable)) {
    return;
  }
  r.status = SolveStatus::kTimeLimit;
  s.detail = "the budget ran out while the laws were verified on the models (" +
             sig3(format.motion_time * r.model.omega1() / (2.0 * std::numbers::pi)) +
             " first-mode periods each); the law is returned with its verified figures" +
             (s.detail.empty() ? std::string() : "; " + s.detail);
}

void finish_status(const detail::StrategyContext& c, PlanResult& r, Selection& s,
                   Strategy result_strategy, const Solved& solved) {
  r.solved_status = solved.status;
  r.solved_detail = solved.detail;
  detail::apply_optimal_caveat(r.status, s.detail, r.warnings, result_strategy);
  r.message = brief_report(c, r, result_strategy, std::move(s.detail));
}

/// PlanResult::move_absolute of a one-jerk law under drive_profile kMoveAbsolute.
void take_move_absolute(PlanResult& r, const PlanOptions& options, const Format& format) {
  if (options.drive_profile != DriveProfile::kMoveAbsolute || !r.durations) return;
  r.move_absolute = move_absolute_profile(*r.durations, format.stroke);
}

}  // namespace

std::vector<double> notched_frequencies(const Format& format, const PlanOptions& options,
                                        const PlanResult& r) {
  if (r.invalid_input) return {};
  Strategy strategy = r.strategy;
  for (const PlanCandidate& k : r.candidates) {
    if (k.chosen) strategy = k.strategy;
  }
  // The design plan() gave the strategies (set_design), rebuilt: the same format, options and
  // tank (turned onto its axis where plan() turned it).
  const detail::Deadline deadline(0.0);
  detail::StrategyContext c{format, options, r.model, detail::DurationSpace(format, options),
                            deadline};
  const std::optional<RectangularModel> axis_tank =
      r.rectangular ? rectangular_axis_tank(*r.rectangular) : std::nullopt;
  c.rectangular = axis_tank ? &*axis_tank : (r.rectangular ? &*r.rectangular : nullptr);
  detail::set_design(c);
  return detail::notched_frequencies(c, strategy);
}

RobustnessReport robustness_of(const Format& format, const PlanOptions& options,
                               const PlanResult& r) {
  if (r.rectangular) {
    return *rectangular_robustness_report(*r.rectangular, r.law,
                                          sweep_for(format, options, r.model.zeta),
                                          std::pair{r.prediction.linear, r.prediction.nonlinear});
  }
  return robustness_report(r.model, r.law, sweep_for(format, options, r.model.zeta),
                           std::pair{r.prediction.linear, r.prediction.nonlinear});
}

namespace {

/// robustness_of within the plan's budget, which covers the report: nullopt when the budget ran
/// out before it was complete. A rectangular tank is asked before each point (a tank whose period
/// is tiny against a long motion makes each point's simulation cost a second or more); a
/// cylinder's sweep, at most a few hundred periods per point, only before it starts.
std::optional<RobustnessReport> robustness_within(const Format& format, const PlanOptions& options,
                                                  const PlanResult& r,
                                                  const detail::Deadline& deadline) {
  if (deadline.expired()) return std::nullopt;
  if (!r.rectangular) return robustness_of(format, options, r);
  return rectangular_robustness_report(*r.rectangular, r.law,
                                       sweep_for(format, options, r.model.zeta),
                                       std::pair{r.prediction.linear, r.prediction.nonlinear},
                                       [&deadline] { return deadline.expired(); });
}

// The plan's robustness report (with options.robustness): a robust plan's own sweep, else a
// sweep within what is left of the budget.
void take_robustness(PlanResult& r, Selection& s, const Format& format, const PlanOptions& options,
                     const detail::Deadline& deadline) {
  if (!options.robustness) return;
  // A robust plan's law was swept over the range already: that sweep is its report.
  if (s.range) {
    r.robustness = std::move(s.range->report);
  } else if (std::optional<RobustnessReport> report =
                 robustness_within(format, options, r, deadline)) {
    r.robustness = std::move(*report);
  } else if (r.status == SolveStatus::kTimeLimit) {
    // The solve itself ran out: its point is what the budget allowed, not a law that was found.
    s.detail =
        "the solve ran out of the budget first: its law is the best admissible point it "
        "reached, which need not meet the options' bounds (verified at the nominal model: "
        "the figures below)" +
        (s.detail.empty() ? std::string() : " (" + s.detail + ")") +
        "; the robustness report was left out too: raise time_limit_s";
  } else {
    // The law is found and verified at the nominal model; the budget, which covers the
    // report, is spent: the plan says so instead of overrunning it.
    r.status = SolveStatus::kTimeLimit;
    s.detail =
        "the robustness report was left unfinished (each of its points simulates "
        "the whole motion, " +
        sig3(format.motion_time * r.model.omega1() / (2.0 * std::numbers::pi)) +
        " first-mode periods here); the law is returned without it, verified at the nominal "
        "model: raise time_limit_s or set robustness to false" +
        (s.detail.empty() ? std::string() : "; " + s.detail);
  }
}

}  // namespace

PlanResult plan(const Format& format, Strategy strategy, const PlanOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  if (std::optional<InvalidInput> why = input_refusal(format, strategy, options)) {
    return refusal(format, strategy, options, std::move(*why));
  }
  const detail::Deadline deadline(options.time_limit, options.stop);
  PlanResult r;
  r.strategy = strategy;
  r.model = make_sloshing_model(format, options.model);
  if (format.container.rectangular) r.rectangular = rectangular_model_of(format, options.model);
  const RectangularModel* rectangular = r.rectangular ? &*r.rectangular : nullptr;
  if (std::optional<InvalidInput> why = model_refusal(r.model)) {
    return refusal(format, strategy, options, std::move(*why));
  }
  const Durations uniform = uniform_durations(format.motion_time);
  std::string baseline_out_of_range;
  r.baseline = predict(r.model, rectangular, SevenSegmentLaw(uniform, format.stroke).law(),
                       options.rest_time, &baseline_out_of_range);
  if (!finite_prediction(r.baseline)) {
    return refusal(
        format, strategy, options,
        refused(PlanInput::kUniformResponse, r.baseline.nonlinear.motion.value, non_negative(),
                "the uniform law's predicted sloshing is not finite for this format"));
  }
  // A tank turned a hair off an axis is planned as on it (rectangular_axis_tank): the strategies
  // and their references see the axis's tank, the plan's figures are the tank's own.
  const std::optional<RectangularModel> axis_tank =
      rectangular ? rectangular_axis_tank(*rectangular) : std::nullopt;
  std::string reference_out_of_range;
  const LawPrediction reference = strategies_reference(
      r, axis_tank, format, options.rest_time, baseline_out_of_range, reference_out_of_range);
  detail::StrategyContext c{format, options, r.model, detail::DurationSpace(format, options),
                            deadline};
  c.rectangular = axis_tank ? &*axis_tank : rectangular;
  detail::set_design(c);
  const double w_design = c.design_model.omega1();
  // (A strategy without a band may widen it past 0 Hz: the marker stops there.)
  r.band_omega = {std::max(0.0, (1.0 - c.band) * w_design), (1.0 + c.band) * w_design};
  r.uncertainty = c.range;
  detail::set_references(c, reference.nonlinear.motion.value);
  c.uniform_prediction = &reference;
  c.uniform_out_of_range = reference_out_of_range;
  if (!(std::isfinite(c.x_ref) && c.x_ref > 0.0 && std::isfinite(c.jerk_ref) && c.jerk_ref > 0.0)) {
    return refusal(
        format, strategy, options,
        refused(PlanInput::kReferenceLevels, c.x_ref, positive(),
                "the uniform law's reference levels are not finite and positive (X_ref = " +
                    sig3(c.x_ref) + " m/s)"));
  }

  const GuardReference guard = guard_reference(c, reference, reference_out_of_range.empty());
  Selection s = strategy == Strategy::kAuto ? run_auto(c, guard, r.candidates)
                                            : run_single(c, strategy, guard);
  const Strategy result_strategy = s.outcome.strategy;
  take_selection(r, s, format);
  take_own_figures(r, s, axis_tank.has_value(), uniform, baseline_out_of_range, options.rest_time);
  take_move_absolute(r, options, format);
  // A law the models cannot follow (hundreds of g on a short move), at the nominal model or
  // somewhere in the uncertainty range: no numbers to promise.
  const bool nominal_diverges = !finite_prediction(r.prediction);
  if (nominal_diverges || (s.range && !finite_prediction(s.range->worst))) {
    return refusal(format, strategy, options,
                   diverging_law(r.prediction.kinematics, result_strategy, nominal_diverges));
  }
  if (s.range) r.worst_case = s.range->worst;
  const Solved solved{r.status, s.detail};
  take_robustness(r, s, format, options, deadline);
  take_budget_overrun(r, s, format, deadline);
  r.solver.solve_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  r.warnings =
      plan_warnings(format, options, r, s.worse, std::move(s.out_of_range), baseline_out_of_range);
  finish_status(c, r, s, result_strategy, solved);
  return r;
}

namespace detail {

std::string worse_figures(const PeakFigures& law, const PeakFigures& reference, bool linear_only) {
  // Above the reference by more than this fraction and by more than kWorseAbsolute [m].
  constexpr double kWorseRelative{0.05};
  constexpr double kWorseAbsolute{0.5e-3};
  std::string figures;
  auto check = [&](double value, double base, const char* what) {
    if (value > base * (1.0 + kWorseRelative) && value > base + kWorseAbsolute) {
      if (!figures.empty()) figures += ", ";
      figures += std::string(what) + " " + sig3(value * 1e3) + " mm vs " + sig3(base * 1e3) + " mm";
    }
  };
  if (!linear_only) {
    check(law.nonlinear_motion, reference.nonlinear_motion, "eta_motion (nonlinear)");
    check(law.nonlinear_rest, reference.nonlinear_rest, "eta_rest (nonlinear)");
  }
  check(law.linear_motion, reference.linear_motion, "eta_motion (linear)");
  check(law.linear_rest, reference.linear_rest, "eta_rest (linear)");
  return figures;
}

AutoChoice choose_on_one_model(const std::vector<PlanCandidate>& candidates,
                               const std::vector<bool>& in_range,
                               const std::vector<bool>& worse_than_baseline,
                               const std::vector<BoundVerdict>& bounds) {
  const bool mixed =
      std::adjacent_find(in_range.begin(), in_range.end(), std::not_equal_to<>()) != in_range.end();
  if (!mixed) return choose_auto(candidates, worse_than_baseline, bounds);
  std::vector<PlanCandidate> linear = candidates;
  std::vector<BoundVerdict> linear_bounds = bounds;
  for (std::size_t k = 0; k < linear.size(); ++k) {
    PlanCandidate& cand = linear[k];
    cand.prediction.nonlinear = cand.prediction.linear;
    if (cand.worst_case) cand.worst_case->nonlinear = cand.worst_case->linear;
    const SloshPeaks& judged = cand.worst_case ? cand.worst_case->linear : cand.prediction.linear;
    linear_bounds[k].value = linear_bounds[k].on_rest ? judged.rest.value : judged.motion.value;
  }
  AutoChoice choice = choose_auto(linear, worse_than_baseline, linear_bounds);
  choice.ranked_on_linear = true;
  for (std::size_t k = 0; k < choice.lost.size(); ++k) {
    const CandidateLoss l = choice.lost[k];
    if (l == CandidateLoss::kMotionAboveBest || l == CandidateLoss::kTieOnRest ||
        l == CandidateLoss::kHigherRest || l == CandidateLoss::kAboveBound ||
        (l == CandidateLoss::kWorseThanBaseline && choice.bound_missed)) {
      choice.lost_detail[k] += " (linear model)";
    }
  }
  if (choice.bound_missed) choice.bound_sentence += detail::kRankedOnLinearModel;
  return choice;
}

std::vector<Warning> reference_model_warnings(bool law_in_range,
                                              const std::string& reference_reason,
                                              const PeakFigures& law,
                                              const PeakFigures& reference) {
  std::vector<Warning> out;
  const bool reference_in_range = reference_reason.empty();
  if (!reference_in_range) {
    out.push_back({WarningKind::kReferenceLinear,
                   "the uniform law's nonlinear figures (the reference of the reductions) are the "
                   "linear model's: " +
                       reference_reason});
  }
  if (law_in_range == reference_in_range) return out;
  const std::string which = law_in_range
                                ? "the uniform law is outside the rectangular nonlinear model's "
                                  "range (its nonlinear figures are the linear model's) and the "
                                  "plan's law within it"
                                : "the plan's law is outside the rectangular nonlinear model's "
                                  "range (its nonlinear figures are the linear model's) and the "
                                  "uniform law within it";
  out.push_back({WarningKind::kReductionsOnLinearModel,
                 "reductions on the linear model: " + which +
                     ", so both laws' nonlinear figures do not come from one model; the "
                     "reductions compare their linear figures: eta_motion " +
                     sig3(law.linear_motion * 1e3) + " mm vs " +
                     sig3(reference.linear_motion * 1e3) + " mm, eta_rest " +
                     sig3(law.linear_rest * 1e3) + " mm vs " + sig3(reference.linear_rest * 1e3) +
                     " mm (the uniform law's)"});
  return out;
}

}  // namespace detail

}  // namespace slosh
