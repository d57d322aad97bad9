#include "slosh/core/strategy/min_time.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include "slosh/core/strategy/path_plan.hpp"
#include "slosh/core/strategy/rectangular_path_plan.hpp"
#include "slosh/core/strategy/robustness.hpp"
#include "status_caveat.hpp"
#include "strategies.hpp"
#include "text.hpp"

namespace slosh {

namespace {

using detail::sig3;
using Clock = std::chrono::steady_clock;

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Relative tolerance of the eta limits, the planner's own (SPEC §5: constraints to 1e-6).
constexpr double kLimitTolerance{1e-6};

/// Time to accelerate from rest to `v` and have zero acceleration again, under |a| <= a and
/// |j| <= j (either may be infinite) [s].
double accel_time(double v, double a, double j) {
  if (std::isinf(a) && std::isinf(j)) return 0.0;
  if (std::isinf(j)) return v / a;
  if (std::isinf(a)) return 2.0 * std::sqrt(v / j);
  return v >= a * a / j ? v / a + a / j : 2.0 * std::sqrt(v / j);
}

/// T rounded up to the 1 ms grid (a value already on it, up to round-off, stays).
/// (Divided, not multiplied, by the grid count: 955 / 1000 is the double nearest 0.955.)
double ceil_to_grid(double t) {
  return std::ceil(t / kMinTimeResolution - 1e-9) / std::round(1.0 / kMinTimeResolution);
}
double round_to_grid(double t) {
  return std::round(t / kMinTimeResolution) / std::round(1.0 / kMinTimeResolution);
}

std::string mm(double metres) {
  return sig3(metres * 1e3) + " mm";
}
/// A time on the 1 ms grid ("0.683 s"); other times with 3 significant digits.
std::string sec(double seconds) {
  const double ms = seconds * 1e3;
  if (std::abs(ms - std::round(ms)) < 1e-6 && seconds < 100.0) {
    return detail::fixed(seconds, 3) + " s";
  }
  return sig3(seconds) + " s";
}

/// "eta_motion <= 63 mm and eta_rest <= 3 mm (nonlinear model)"
std::string limits_text(const MinTimeResult& r, LimitModel model) {
  return "eta_motion <= " + mm(r.eta_motion_max) + " and eta_rest <= " + mm(r.eta_rest_max) + " (" +
         (model == LimitModel::kBoth ? std::string("both models") : to_string(model) + " model") +
         ")";
}

/// The clause saying that a point's nonlinear figures are its linear ones standing in (a
/// rectangular tank's nonlinear model does not hold for its law), when the limits read them.
std::string stood_in(const MinTimePoint& p, LimitModel model) {
  if (!p.linear_stood_in || model == LimitModel::kLinear) return {};
  return "; the nonlinear model does not hold for the plan at T = " + sec(p.motion_time) +
         ", so its linear figures stood in for the nonlinear ones (nonlinear_model_not_valid)";
}

/// Why a point of the curve (finite predictions) is infeasible, for messages.
std::string why_not(const MinTimePoint& p, const MinTimeResult& r) {
  std::string text;
  if (p.eta_motion > r.eta_motion_max * (1.0 + kLimitTolerance)) {
    text = "eta_motion " + mm(p.eta_motion);
  }
  if (p.eta_rest > r.eta_rest_max * (1.0 + kLimitTolerance)) {
    text += (text.empty() ? "" : ", ") + std::string("eta_rest ") + mm(p.eta_rest);
  }
  if (p.plan_status != SolveStatus::kOptimal && p.plan_status != SolveStatus::kAcceptable) {
    text += (text.empty() ? "" : "; ") + std::string("plan ") + to_string(p.plan_status);
  }
  return text;
}

/// The strategies that optimise the 7 durations (and so take a warm start).
bool takes_warm_start(Strategy s) {
  return s == Strategy::kNotch || s == Strategy::kMultiNotch || s == Strategy::kMinJerkBand ||
         s == Strategy::kTimeDomain;
}

class Search {
 public:
  /// `deadline`: the search's budget, time_limit, counted from the request (its validation and
  /// references count too).
  Search(const Format& format, Strategy strategy, const MinTimeOptions& options,
         MinTimeResult& result, const detail::Deadline& deadline)
      : format_(format),
        strategy_(strategy),
        options_(options),
        result_(result),
        deadline_(deadline) {}

  /// Plans T, warm-started from a neighbour (see warm_start_for). A warm-started plan that is
  /// infeasible is planned again from the planner's own starts (what a plan request at T without
  /// a warm start does), and that plan is kept when it is feasible or both are infeasible: a T
  /// is called infeasible only when the planner's own starts cannot meet the limits there
  /// (continuation can follow a branch that misses its own constraints, e.g. time_domain's
  /// eta_rest of 43 mm at a T where a fresh plan holds 3 mm). `trust_far_miss`: below every
  /// feasible T found so far, a plan warm-started from a far miss that misses the limits by more
  /// than refine_excess itself is taken as it is (the scan far from the limits, where the re-plan
  /// would double the cost; warm_start_for plans the T next to a near miss from the planner's own
  /// starts at once). Nullopt when the budget (time or max_plans) ran out before or during a plan.
  std::optional<MinTimePoint> evaluate(double T, bool trust_far_miss) {
    const std::optional<Durations> from = warm_start_for(T);
    std::optional<Planned> point = plan_at(T, from);
    if (!point) return std::nullopt;
    if (from && !point->point.feasible && !(trust_far_miss && far_miss(point->point))) {
      std::optional<Planned> fresh = plan_at(T, std::nullopt);
      if (!fresh) return std::nullopt;
      point = std::move(fresh);
    }
    return record(std::move(*point));
  }

  /// Plans T from a neighbour's warm start (see warm_start_for) and keeps the plan as it is, even
  /// when it misses the limits: the curve above T_min, whose failing points are confirmed
  /// afterwards only as far as feasible_above needs (extend_curve_and_report). Nullopt when the
  /// budget ran out.
  std::optional<MinTimePoint> evaluate_warm(double T) {
    std::optional<Planned> point = plan_at(T, warm_start_for(T));
    if (!point) return std::nullopt;
    return record(std::move(*point));
  }

  /// Removes T's point from the curve (a plan kept out of it; it still counts in `plans`).
  void drop(double T) {
    std::erase_if(result_.curve, [&](const MinTimePoint& p) { return p.motion_time == T; });
  }

  /// Plans T again from the planner's own starts when its point on the curve is infeasible and
  /// was warm-started (a far miss taken as it was during the scan), and puts that plan in its
  /// place. False when the budget ran out; true when there was nothing to do or it was done.
  bool confirm(double T) {
    auto it = std::find_if(result_.curve.begin(), result_.curve.end(),
                           [&](const MinTimePoint& p) { return p.motion_time == T; });
    if (it == result_.curve.end() || it->feasible || !it->warm_start) return true;
    std::optional<Planned> fresh = plan_at(T, std::nullopt);
    if (!fresh) return false;
    result_.curve.erase(it);
    record(std::move(*fresh));
    return true;
  }

 private:
  struct Planned {
    MinTimePoint point;
    PlanResult plan;
  };
  /// A plan that misses the limits by more than refine_excess, below every feasible T found so
  /// far.
  [[nodiscard]] bool far_miss(const MinTimePoint& p) const {
    return p.excess > options_.refine_excess && (!result_.t_min || p.motion_time < *result_.t_min);
  }

  /// One plan() of T; nullopt when the budget ran out before or during it.
  std::optional<Planned> plan_at(double T, const std::optional<Durations>& warm_start) {
    // The search's own budget: the plans share time_limit, and a stop request ends it at once.
    const double remaining = deadline_.remaining();
    if (remaining <= 0.0 || result_.plans >= options_.max_plans) return std::nullopt;
    Format f = format_;
    f.motion_time = T;
    PlanOptions o = options_.plan;
    o.eta_rest_max = result_.eta_rest_max;
    o.eta_motion_max = result_.eta_motion_max;
    o.time_limit = remaining;
    o.warm_start = warm_start;
    o.robustness = false;  // the report is made once, for the returned plan (min_time())
    Planned out{MinTimePoint{}, options_.path ? plan_on_path(f, *options_.path, strategy_, o)
                                              : plan(f, strategy_, o)};
    ++result_.plans;
    if (out.plan.status == SolveStatus::kTimeLimit) return std::nullopt;
    MinTimePoint& p = out.point;
    const PlanResult& plan_result = out.plan;
    p.motion_time = T;
    p.warm_start = warm_start;
    p.durations = plan_result.durations;
    p.plan_status = plan_result.status;
    p.linear_stood_in = has_warning(plan_result.warnings, WarningKind::kNonlinearModelNotValid);
    p.prediction = plan_result.prediction;
    // A robust plan is judged by its worst case over the uncertainty range.
    const LawPrediction& judged = plan_result.worst_case.value_or(plan_result.prediction);
    const SloshPeaks& nl = judged.nonlinear;
    const SloshPeaks& lin = judged.linear;
    switch (options_.model) {
      case LimitModel::kNonlinear:
        p.eta_motion = nl.motion.value;
        p.eta_rest = nl.rest.value;
        break;
      case LimitModel::kLinear:
        p.eta_motion = lin.motion.value;
        p.eta_rest = lin.rest.value;
        break;
      case LimitModel::kBoth:
        p.eta_motion = std::max(nl.motion.value, lin.motion.value);
        p.eta_rest = std::max(nl.rest.value, lin.rest.value);
        break;
    }
    const bool refused = plan_result.invalid_input.has_value() ||
                         plan_result.status == SolveStatus::kFailed ||
                         !std::isfinite(p.eta_motion) || !std::isfinite(p.eta_rest);
    p.excess = refused ? kInf
                       : std::max(p.eta_motion / result_.eta_motion_max,
                                  p.eta_rest / result_.eta_rest_max);
    const bool usable = plan_result.status == SolveStatus::kOptimal ||
                        plan_result.status == SolveStatus::kAcceptable;
    p.feasible = !refused && usable && p.excess <= 1.0 + kLimitTolerance;
    const std::optional<double>& a_max = options_.plan.limits.a_max;
    if (options_.path && a_max && !plan_result.invalid_input && plan_result.law.duration() > 0.0) {
      p.a_max_ratio = path_acceleration(*options_.path, plan_result.law).total / *a_max;
    }
    return out;
  }

  /// Adds a planned point to the curve, T_min and the best point.
  MinTimePoint record(Planned planned) {
    const MinTimePoint& p = planned.point;
    // A plan without finite predictions (refused inputs, a diverging model) has nothing to plot.
    if (!std::isinf(p.excess)) result_.curve.push_back(p);
    if (p.feasible) {
      if (!result_.t_min || p.motion_time < *result_.t_min) {
        result_.t_min = p.motion_time;
        result_.plan = std::move(planned.plan);
      }
    } else if (!result_.t_min && std::isfinite(p.excess) &&
               (!result_.best || p.excess < result_.best->excess)) {
      result_.best = p;
      result_.plan = std::move(planned.plan);
    }
    return p;
  }

  /// The durations of the nearest planned T below and above T, the one of lower excess (ties:
  /// below): above the least feasible T so far when it is feasible or a far miss, below it when
  /// it is a far miss and the scan's excess, extrapolated to T, stays above refine_excess. Nullopt
  /// otherwise, for the first T, and for the strategies that do not optimise durations.
  [[nodiscard]] std::optional<Durations> warm_start_for(double T) const {
    if (!takes_warm_start(strategy_)) return std::nullopt;
    const MinTimePoint* below = nullptr;
    const MinTimePoint* above = nullptr;
    for (const MinTimePoint& q : result_.curve) {
      if (!q.durations) continue;  // the curve holds finite predictions only
      if (q.motion_time < T && (below == nullptr || q.motion_time > below->motion_time)) below = &q;
      if (q.motion_time > T && (above == nullptr || q.motion_time < above->motion_time)) above = &q;
    }
    const MinTimePoint* from = below;
    if (from == nullptr || (above != nullptr && above->excess < from->excess)) from = above;
    if (from == nullptr) return std::nullopt;
    // An infeasible warm-started plan is planned again from the planner's own starts, so where
    // it is likely infeasible the search plans from those at once (one plan instead of two):
    // below every feasible T found so far (the bracketing) unless the neighbour is a far miss
    // (the scan far from the limits, whose far misses are kept), and next to a near miss.
    const bool below_feasible = !result_.t_min || T < *result_.t_min;
    if (below_feasible && from->feasible) return std::nullopt;
    if (!from->feasible && from->excess <= options_.refine_excess) return std::nullopt;
    if (below_feasible && from == below && from->excess > options_.refine_excess) {
      // The scan approaching the limits: the excess extrapolated from the last two planned T
      // below reaches refine_excess at T, so T is likely a near miss.
      const MinTimePoint* before = nullptr;
      for (const MinTimePoint& q : result_.curve) {
        if (q.motion_time < from->motion_time && std::isfinite(q.excess) &&
            (before == nullptr || q.motion_time > before->motion_time)) {
          before = &q;
        }
      }
      if (before != nullptr) {
        const double slope =
            (from->excess - before->excess) / (from->motion_time - before->motion_time);
        if (from->excess + slope * (T - from->motion_time) <= options_.refine_excess) {
          return std::nullopt;
        }
      }
    }
    return *from->durations;
  }

  const Format& format_;
  Strategy strategy_;
  const MinTimeOptions& options_;
  MinTimeResult& result_;
  const detail::Deadline& deadline_;
};

}  // namespace

double plan_validation_time(double motion_time_max, const PlanOptions& plan) {
  return std::max(motion_time_max, 4.0 * plan.min_ramp + plan.plateau_min[0] + plan.plateau_min[1]);
}

double kinematic_lower_bound(const PlanarPath& path, const MachineLimits& limits) {
  MachineLimits along = limits;
  const std::vector<PathElement>& elements = path.elements();
  const bool arcs_only = std::all_of(elements.begin(), elements.end(), [](const PathElement& e) {
    return e.kind == PathElement::Kind::kArc;
  });
  if (arcs_only && limits.a_max) {
    double rho = std::numeric_limits<double>::infinity();
    for (const PathElement& e : elements) rho = std::min(rho, e.radius);
    const double v_normal = std::sqrt(*limits.a_max * rho);
    along.v_max = limits.v_max ? std::min(*limits.v_max, v_normal) : v_normal;
  }
  return kinematic_lower_bound(path.length(), along);
}

double kinematic_lower_bound(double stroke, const MachineLimits& limits) {
  const double a = limits.a_max.value_or(kInf);
  const double v = limits.v_max.value_or(kInf);
  const double j = limits.j_max.value_or(kInf);
  if (std::isinf(a) && std::isinf(v) && std::isinf(j)) return 0.0;
  if (std::isfinite(v)) {
    // Cruise at v when accelerating to v and back fits in the stroke.
    const double ta = accel_time(v, a, j);
    if (v * ta <= stroke) return ta + stroke / v;
  }
  // No cruise: the peak velocity vp solves vp * accel_time(vp) = stroke.
  if (std::isinf(j)) return 2.0 * std::sqrt(stroke / a);
  const double jerk_only = 4.0 * std::cbrt(stroke / (2.0 * j));
  if (std::isinf(a)) return jerk_only;
  if (stroke < 2.0 * a * a * a / (j * j)) return jerk_only;  // a_max not reached
  const double vp = 0.5 * (-a * a / j + std::sqrt(a * a * a * a / (j * j) + 4.0 * stroke * a));
  return 2.0 * (vp / a + a / j);
}

std::optional<double> MinTimeOptions::eta_motion_limit(const Format& format) const {
  if (eta_motion_max) return eta_motion_max;
  if (format.container.height) {
    return *format.container.height - format.fill_height - free_board_margin;
  }
  return std::nullopt;
}

std::optional<InvalidInput> MinTimeOptions::validate(const Format& format) const {
  if (auto e = first_out_of_range({
          {PlanInput::kMotionTimeMax, motion_time_max, {0.0, kMaxPlanTime, true, false}},
          {PlanInput::kFreeBoardMargin, free_board_margin, closed_range(0.0, 10.0)},
          {PlanInput::kEtaRestMax, eta_rest_max, {0.0, 10.0, true, false}},
          {PlanInput::kScanStep, scan_step, closed_range(kMinTimeResolution, 1.0)},
          {PlanInput::kMaxPlans, static_cast<double>(max_plans), closed_range(3.0, 10000.0)},
          {PlanInput::kCurveFactor, curve_factor, closed_range(1.0, 10.0)},
          {PlanInput::kRefineExcess, refine_excess, closed_range(1.0, 1000.0)},
      })) {
    return e;
  }
  const std::optional<double> eta_motion = eta_motion_limit(format);
  if (!eta_motion) {
    return refused(PlanInput::kEtaMotionMax, std::numeric_limits<double>::quiet_NaN(),
                   {0.0, 10.0, true, false},
                   "eta_motion_max is required when the container height is not given (its "
                   "default is the free board, container height - fill height - margin)");
  }
  if (!InputBounds{0.0, 10.0, true, false}.contains(*eta_motion)) {
    if (eta_motion_max) {
      return out_of_range(PlanInput::kEtaMotionMax, -1, *eta_motion, {0.0, 10.0, true, false});
    }
    return refused(PlanInput::kFreeBoardMargin, free_board_margin,
                   {0.0, *format.container.height - format.fill_height, false, true},
                   "the free board " + mm(*format.container.height - format.fill_height) +
                       " minus free_board_margin " + mm(free_board_margin) +
                       " leaves no eta_motion_max > 0");
  }
  Format at_max = format;
  at_max.motion_time = plan_validation_time(motion_time_max, plan);
  return validate_plan_input(at_max, plan);
}

namespace {

// One strategy's search in progress: the options, the limits' sentence, the planner and the
// points of the coarse scan.
struct SearchRun {
  const Format& format;
  Strategy strategy;
  const MinTimeOptions& options;
  MinTimeResult& r;
  std::string limits;
  Search search;
  double last_infeasible{-1.0};
  double first_feasible{-1.0};
  std::vector<MinTimePoint> scanned;

  SearchRun(const Format& f, Strategy s, const MinTimeOptions& o, MinTimeResult& result,
            const detail::Deadline& deadline)
      : format(f),
        strategy(s),
        options(o),
        r(result),
        limits(limits_text(result, o.model)),
        search(f, s, o, result, deadline) {}

  /// Which budget ran out, so the client raises the one that matters.
  [[nodiscard]] std::string budget_text() const {
    return r.plans >= options.max_plans
               ? "the search's plan budget (max_plans " + std::to_string(options.max_plans) +
                     ", all planned; raise max_plans)"
               : "the search's time budget (time_limit_s " + sec(options.plan.time_limit) + ")";
  }

  void out_of_budget(const std::string& where) {
    r.status = SolveStatus::kTimeLimit;
    r.message = budget_text() + " ran out " + where;
    r.best.reset();  // the least excess is the infeasible searches' answer
    if (r.t_min) {
      r.message += "; the best bound so far is T_min <= " + sec(*r.t_min);
      for (const MinTimePoint& p : r.curve) {
        if (p.motion_time == *r.t_min) r.message += stood_in(p, options.model);
      }
    } else {
      r.message += " before a motion time met " + limits;
    }
  }

  void found(const MinTimePoint& p) {
    first_feasible = p.motion_time;
    last_infeasible = -1.0;
    for (const MinTimePoint& q : r.curve) {
      if (q.motion_time < p.motion_time) last_infeasible = std::max(last_infeasible, q.motion_time);
    }
  }
};

// The refusals and the bounds before any plan; false when the result is final.
bool prepare_search(const Format& format, Strategy strategy, const MinTimeOptions& options,
                    MinTimeResult& r) {
  if (strategy == Strategy::kAuto) {
    r.invalid_input = refused(PlanInput::kMotionTime, std::numeric_limits<double>::quiet_NaN(), {},
                              "auto is not searched: name the strategies to compare");
    r.message = "invalid input: " + r.invalid_input->message + "; nothing was planned";
    return false;
  }
  if (auto e = options.validate(format);
      e || (e = drive_profile_refusal(strategy, options.plan.drive_profile)) ||
      (e = band_refusal(strategy, format, options.plan))) {
    r.invalid_input = std::move(e);
    r.message = "invalid input: " + r.invalid_input->message + "; nothing was planned";
    return false;
  }
  r.eta_motion_max = *options.eta_motion_limit(format);
  r.eta_rest_max = options.eta_rest_max;
  r.kinematic_bound = options.path ? kinematic_lower_bound(*options.path, options.plan.limits)
                                   : kinematic_lower_bound(format.stroke, options.plan.limits);
  const double admissible =
      4.0 * options.plan.min_ramp + options.plan.plateau_min[0] + options.plan.plateau_min[1];
  r.scan_start = ceil_to_grid(std::max({r.kinematic_bound, admissible, kMinPlanTime}));
  const double t_max = options.motion_time_max;
  if (r.scan_start > t_max + 1e-12) {
    r.status = SolveStatus::kInfeasible;
    r.message = "no motion time up to motion_time_max " + sec(t_max) +
                " is possible: " + (options.path ? "the path length " : "the stroke ") +
                mm(format.stroke) + " needs at least " + sec(r.scan_start) +
                " (machine limits and ramps >= min_ramp); raise " +
                "motion_time_max_s or the machine limits" +
                // Where the ramps and plateaus alone need the time, lowering them is the remedy
                // (motion_time_max_s has a most of its own).
                (admissible >= r.scan_start ? std::string(", or lower min_ramp_s and plateau_min_s")
                                            : std::string());
    return false;
  }
  return true;
}

// The plan's law breaks limits.a_max along the path (beyond the planner's own slack).
bool breaks_a_max(const MinTimePoint& p) {
  return p.a_max_ratio > 1.0 + 1e-6;
}

// Golden-section search for the least excess between the last three scanned points; false when
// the budget ran out. `hit` is set to the first feasible T found.
bool refine_near_miss(SearchRun& run, std::optional<MinTimePoint>& hit) {
  const std::vector<MinTimePoint>& scanned = run.scanned;
  const std::size_t n = scanned.size();
  constexpr double kGolden = 0.6180339887498949;
  double a = scanned[n - 3].motion_time, b = scanned[n - 1].motion_time;
  std::optional<MinTimePoint> c_point = scanned[n - 2];
  double c = c_point->motion_time;
  while (b - a > 2.5 * kMinTimeResolution && !hit) {
    // Probe inside the larger of [a, c] and [c, b].
    const bool left = c - a > b - c;
    double d = round_to_grid(left ? c - (1.0 - kGolden) * (c - a) : c + (1.0 - kGolden) * (b - c));
    if (d <= a || d >= b || d == c) break;
    const std::optional<MinTimePoint> q = run.search.evaluate(d, true);
    if (!q) {
      run.out_of_budget("while refining the scan near T = " + sec(c));
      return false;
    }
    if (q->feasible) {
      hit = q;
      break;
    }
    if (q->excess < c_point->excess) {
      (left ? b : a) = c;
      c = d;
      c_point = q;
    } else {
      (left ? a : b) = d;
    }
  }
  return true;
}

// Along a path, the step from the last scanned point (infeasible, within a_max) to the next: the
// scan starts with scan_step and grows it geometrically, doubling it where the excess lingers
// and tripling it where it falls, but never beyond 35 % of the way to where the excess,
// extrapolated from the last two points as exp(c T), reaches 1. Without machine limits nothing
// bounds T from below but the ramps (0.2 s), and on an arc the normal acceleration s'^2/rho keeps
// the excess far above 1 up to several times that (a 90 degree index of a 300 mm table: 80 at
// 0.2 s, 10 at 0.8 s, T_min 0.8-1.7 s), a range the line's fixed step took 25-40 plans to cross;
// far from the limits the grown steps cross it in a few, near them (a steep fall of the excess)
// the step is scan_step again. A feasible window narrower than the step between two points with
// no near miss is passed, as between the line's scan points.
double path_scan_step(const SearchRun& run, double step) {
  const double base = run.options.scan_step;
  const std::vector<MinTimePoint>& s = run.scanned;
  const std::size_t n = s.size();
  if (n < 2 || breaks_a_max(s[n - 2])) return base;  // no slope yet (first point, after a jump)
  const MinTimePoint& p = s[n - 1];
  const MinTimePoint& q = s[n - 2];
  // Growth per point where the excess lingers, where it falls, and the fraction of the way to the
  // extrapolated crossing a falling excess allows (chosen on the table index above: every
  // strategy's T_min as with the fixed step, in <= 27 plans).
  constexpr double kGrowLingering = 2.0, kGrowFalling = 3.0, kWayToCrossing = 0.35;
  double next = kGrowLingering * step;
  if (std::isfinite(p.excess) && std::isfinite(q.excess) && p.excess < q.excess) {
    const double rate = std::log(p.excess / q.excess) / (p.motion_time - q.motion_time);
    next = std::min(kGrowFalling * step, kWayToCrossing * std::log(p.excess) / -rate);
  }
  return std::max(base, next);
}

// Whether a scanned near miss is worth refining on a rectangular tank: the refinement looks for
// the residual wave's narrow zeros, so it is spent only where eta_motion already meets its limit
// and eta_rest alone misses. eta_motion falls smoothly with T and has no such zeros: on the README
// cup (120 x 80 mm, 50 mm of water, 200 mm) multi_notch's scan has local minima of the excess at
// 0.64 and 0.72 s where eta_motion is 1.6 and 1.3 times its limit, and refining them spent 17 of
// the 40 plans of the default budget before the scan reached T_min = 1.041 s. A cylinder's search
// keeps refining every near miss (its pinned results).
bool rest_bound_near_miss(const SearchRun& run, const MinTimePoint& p) {
  if (!run.format.container.rectangular) return true;
  return p.eta_motion <= run.r.eta_motion_max * (1.0 + kLimitTolerance);
}

// 1. Coarse scan up from the lower bound until the first feasible T. A scanned local minimum of
// the excess within refine_excess of the limits is refined by golden-section search on the 1 ms
// grid (the residual wave has zeros narrower than the scan step). On a line the step is
// scan_step; along a path it adapts (path_scan_step). False when the budget ran out.
bool coarse_scan(SearchRun& run) {
  double step = run.options.scan_step;
  const double t_max = run.options.motion_time_max;
  double next = run.r.scan_start;
  for (int k = 0;; ++k) {
    double T = round_to_grid(next);
    if (T > t_max) T = t_max;
    if (k > 0 && T <= run.scanned.back().motion_time) break;  // t_max reached
    const std::optional<MinTimePoint> p = run.search.evaluate(T, true);
    if (!p) {
      run.out_of_budget("during the scan at T = " + sec(T));
      return false;
    }
    if (p->feasible) {
      run.found(*p);
      break;
    }
    run.scanned.push_back(*p);
    if (run.options.path && !breaks_a_max(*p)) step = path_scan_step(run, step);
    next = T + step;
    if (breaks_a_max(*p)) {
      // Along an arc the normal acceleration s'^2/rho alone can break a_max. The law's total
      // acceleration scales as 1/T^2 when its shape is stretched, so no T below
      // T sqrt(a_total/a_max) lets this shape meet a_max: scan on from there (a plan that breaks
      // the machine limit is not refined, whatever its slosh figures).
      next = std::max(next, ceil_to_grid(T * std::sqrt(p->a_max_ratio)));
      run.last_infeasible = T;
      if (T >= t_max) break;
      continue;
    }
    const std::size_t n = run.scanned.size();
    if (n >= 3 && run.scanned[n - 2].excess < run.scanned[n - 3].excess &&
        run.scanned[n - 2].excess < run.scanned[n - 1].excess &&
        run.scanned[n - 2].excess <= run.options.refine_excess &&
        rest_bound_near_miss(run, run.scanned[n - 2]) && !breaks_a_max(run.scanned[n - 2]) &&
        !breaks_a_max(run.scanned[n - 3])) {
      std::optional<MinTimePoint> hit;
      if (!refine_near_miss(run, hit)) return false;
      if (hit) {
        run.found(*hit);
        break;
      }
    }
    run.last_infeasible = T;
    if (T >= t_max) break;
  }
  return true;
}

// Along a path: every scanned law broke limits.a_max on the total horizontal acceleration, as a
// sentence naming it (the η limits are then not what no T meets); empty otherwise.
std::string a_max_unreachable(const SearchRun& run) {
  const MinTimeResult& r = run.r;
  const std::optional<double>& a_max = run.options.plan.limits.a_max;
  if (!run.options.path || !a_max || run.scanned.empty()) return {};
  for (const MinTimePoint& p : run.scanned) {
    if (!breaks_a_max(p)) return {};
  }
  const MinTimePoint& last = run.scanned.back();
  double rho = std::numeric_limits<double>::infinity();
  for (const PathElement& e : run.options.path->elements()) {
    if (e.kind == PathElement::Kind::kArc) rho = std::min(rho, e.radius);
  }
  std::string out = "no motion time from " + sec(r.scan_start) + " to " +
                    sec(run.options.motion_time_max) + " (scanned every " +
                    sec(run.options.scan_step) + ") keeps limits.a_max = " + sig3(*a_max) +
                    " m/s^2 on the total horizontal acceleration sqrt(s''^2 + (s'^2/rho)^2) along "
                    "the path with " +
                    to_string(run.strategy) + ": at T = " + sec(last.motion_time) +
                    " its law reaches " + sig3(last.a_max_ratio * *a_max) + " m/s^2";
  if (std::isfinite(rho)) {
    out += " (on the tightest arc, radius " + mm(rho) +
           ", the speed must stay below sqrt(a_max rho) = " + sig3(std::sqrt(*a_max * rho) * 1e3) +
           " mm/s)";
  }
  return out +
         "; a longer motion does not help a law that must cross that arc at speed: raise "
         "limits.a_max or widen the arc";
}

void report_infeasible(SearchRun& run) {
  MinTimeResult& r = run.r;
  r.status = SolveStatus::kInfeasible;
  if (std::string a_max = a_max_unreachable(run); !a_max.empty()) {
    r.message = std::move(a_max);
    return;
  }
  std::string message = "no motion time from " + sec(r.scan_start) + " to " +
                        sec(run.options.motion_time_max) + " (scanned every " +
                        sec(run.options.scan_step) + ") meets " + run.limits + " with " +
                        to_string(run.strategy);
  if (r.best) {
    message += ": the best reached is eta_motion " + mm(r.best->eta_motion) + ", eta_rest " +
               mm(r.best->eta_rest) + " at T = " + sec(r.best->motion_time) +
               stood_in(*r.best, run.options.model);
  }
  r.message = message + "; relax the limits, raise motion_time_max_s or try another strategy";
}

// The planned point at T (nullptr when T was not planned).
const MinTimePoint* point_at(const MinTimeResult& r, double T) {
  for (const MinTimePoint& p : r.curve) {
    if (p.motion_time == T) return &p;
  }
  return nullptr;
}

// The next T to plan strictly inside (lo, hi) on the 1 ms grid. Regula falsi (Illinois): where
// the line through the ratio to its limit of one quantity (eta_motion or eta_rest), at lo (> 1)
// and at hi (< 1), crosses 1, the ratios' distances to 1 scaled by `scale_lo` and `scale_hi`
// (halved while the other end keeps moving). Those ratios are smooth near a crossing, while the
// excess saturates at 1 where time_domain holds eta_rest on its limit. The quantity is the one lo
// violates most among those that hi meets with a margin (a quantity held on its limit at hi, as
// time_domain's eta_rest, carries no slope: its line would put every step next to hi). The
// midpoint when `bisect` is set or no quantity brackets 1.
double next_bracket_point(const MinTimeResult& r, double lo, double hi, double scale_lo,
                          double scale_hi, bool bisect) {
  double t = 0.5 * (lo + hi);
  const MinTimePoint* a = point_at(r, lo);
  const MinTimePoint* b = point_at(r, hi);
  if (!bisect && a != nullptr && b != nullptr && std::isfinite(a->excess) &&
      std::isfinite(b->excess)) {
    // hi's ratio must be below 1 by more than this to give the line a slope [-].
    constexpr double kMargin = 1e-3;
    const std::array<std::array<double, 2>, 2> ratios{{
        {a->eta_motion / r.eta_motion_max, b->eta_motion / r.eta_motion_max},
        {a->eta_rest / r.eta_rest_max, b->eta_rest / r.eta_rest_max},
    }};
    const std::array<double, 2>* chosen = nullptr;
    for (const std::array<double, 2>& q : ratios) {
      if (q[0] > 1.0 && q[1] < 1.0 - kMargin && (chosen == nullptr || q[0] > (*chosen)[0])) {
        chosen = &q;
      }
    }
    if (chosen != nullptr) {
      const double f_lo = scale_lo * ((*chosen)[0] - 1.0);
      const double f_hi = scale_hi * ((*chosen)[1] - 1.0);
      t = lo + (hi - lo) * f_lo / (f_lo - f_hi);
    }
  }
  t = round_to_grid(t);
  return std::clamp(t, round_to_grid(lo + kMinTimeResolution),
                    round_to_grid(hi - kMinTimeResolution));
}

// 2. Bracketing to 1 ms between the last infeasible and the first feasible scanned T: regula
// falsi (Illinois), with a bisection step after two steps in a row that did not halve the
// bracket. The infeasible end, T_min - 1 ms, is infeasible from the planner's own starts too (a
// far miss the scan took from a warm start is planned again); when that plan is feasible, T_min
// moves down to it and the bracketing goes on below. False when the budget ran out.
bool bisect(SearchRun& run) {
  for (;;) {
    if (run.last_infeasible < 0.0) return true;  // T_min is the scan start: nothing below
    double lo = run.last_infeasible, hi = run.first_feasible;
    double scale_lo = 1.0, scale_hi = 1.0;
    int moved = 0;  // +1: hi moved last, -1: lo moved last
    int slow = 0;   // steps in a row that did not halve the bracket
    while (hi - lo > 1.5 * kMinTimeResolution) {
      const double width = hi - lo;
      const double t = next_bracket_point(run.r, lo, hi, scale_lo, scale_hi, slow >= 2);
      const std::optional<MinTimePoint> p = run.search.evaluate(t, false);
      if (!p) {
        run.out_of_budget("during the bisection between " + sec(lo) + " and " + sec(hi));
        run.r.infeasible_below = lo;
        return false;
      }
      if (p->feasible) {
        hi = t;
        scale_hi = 1.0;
        if (moved == 1) scale_lo *= 0.5;
        moved = 1;
      } else {
        lo = t;
        scale_lo = 1.0;
        if (moved == -1) scale_hi *= 0.5;
        moved = -1;
      }
      slow = hi - lo <= 0.5 * width + 1e-12 ? 0 : slow + 1;
    }
    run.r.infeasible_below = lo;
    if (!run.search.confirm(lo)) {
      run.out_of_budget("while planning T = " + sec(lo) + " again from the planner's own starts");
      return false;
    }
    const MinTimePoint* below = point_at(run.r, lo);
    if (below == nullptr || !below->feasible) return true;
    run.r.infeasible_below.reset();
    run.found(*below);
  }
}

// The judgement of the T above T_min that failed: the lowest one that fails from the planner's own
// starts, and the lowest warm-started failure left off the curve.
struct FailuresAbove {
  std::optional<double> confirmed_bad;
  double lowest_dropped = kInf;
};

// An infeasible T above T_min calls feasibility non-monotone: it must be infeasible from the
// planner's own starts too (a warm start may follow a branch they do not). One such T decides
// feasible_above, so the warm-started failures are planned again from the planner's own starts
// in ascending order only until one fails from them too; the warm-started failures above it are
// left off the curve (no point on it is called infeasible unless the planner's own starts
// miss there), which saves their second plan.
FailuresAbove confirm_failures_above(SearchRun& run, double t_min, std::optional<double>& cut) {
  MinTimeResult& r = run.r;
  std::vector<double> unconfirmed;
  for (const MinTimePoint& p : r.curve) {
    if (p.motion_time > t_min && !p.feasible && p.warm_start) unconfirmed.push_back(p.motion_time);
  }
  std::sort(unconfirmed.begin(), unconfirmed.end());
  FailuresAbove out;
  for (const MinTimePoint& p : r.curve) {
    if (p.motion_time > t_min && !p.feasible && !p.warm_start &&
        (!out.confirmed_bad || p.motion_time < *out.confirmed_bad)) {
      out.confirmed_bad = p.motion_time;
    }
  }
  for (double T : unconfirmed) {
    if (!cut && !(out.confirmed_bad && T > *out.confirmed_bad)) {
      if (run.search.confirm(T)) {
        const MinTimePoint* again = point_at(r, T);
        if (again != nullptr && !again->feasible) out.confirmed_bad = T;
        continue;
      }
      cut = T;
    }
    run.search.drop(T);
    out.lowest_dropped = std::min(out.lowest_dropped, T);
  }
  return out;
}

// Whether the plan at T_min was judged by the nonlinear model's limits on the linear figures
// standing in for it (a rectangular tank's nonlinear model out of its range there).
bool stood_in_at_t_min(const SearchRun& run) {
  return run.options.model != LimitModel::kLinear && run.r.plan &&
         has_warning(run.r.plan->warnings, WarningKind::kNonlinearModelNotValid);
}

// Why the plan at T_min is not optimal, or empty: its own warnings (SPEC §5 "Honest status"),
// or the limits met on a tank's linear figures standing in, which under-predict the steep waves
// that put the nonlinear model out of its range: a T a little longer, where it holds again, can
// miss them (a 120 x 80 mm cup, 200 mm, eta_motion <= 11.3 mm: T_min 1.204 s on the linear
// 11.297 mm; 1.222-1.226 s reach 11.33-11.45 mm on the nonlinear model).
std::string t_min_caveat(const SearchRun& run) {
  const MinTimeResult& r = run.r;
  std::string caveat = r.plan ? detail::optimal_caveat(r.plan->warnings, run.strategy) : "";
  if (caveat.empty() && stood_in_at_t_min(run)) {
    caveat =
        "its nonlinear figures are the linear model's standing in (nonlinear_model_not_valid), "
        "which under-predict the steep waves that put the nonlinear model out of its range: the "
        "limits were met on them, not on the nonlinear model";
  }
  return caveat;
}

// A search its budget cut after a T met the limits: its bound's plan is judged as a T_min's
// (t_min_caveat), so that a bound met on a tank's linear figures standing in does not win the
// headline as the one honest T over the T_min plans with that caveat (the README's cup on its
// axis: min_jerk_band's bound 1.08 s won against time_domain's 0.618 s, -41.9 % against the
// uniform law).
void judge_bound(SearchRun& run) {
  MinTimeResult& r = run.r;
  if (r.t_min && r.not_optimal.empty()) r.not_optimal = t_min_caveat(run);
}

// 3. The curve above T_min, up to curve_factor T_min, on the scan grid continued (3 points when
// the budget allows): feasible_above is judged on the T planned above T_min, the least failing
// one confirmed from the planner's own starts. When the budget runs out here, T_min stands
// (bracketed) but the curve is partial: kTimeLimit, and feasible_above is unknown unless a failing
// T was found.
void extend_curve_and_report(SearchRun& run) {
  MinTimeResult& r = run.r;
  const double t_min = *r.t_min;
  const double t_max = run.options.motion_time_max;
  const double curve_end = std::min(t_max, run.options.curve_factor * t_min);
  const int curve_points =
      std::max(1, std::min(3, static_cast<int>(std::floor((curve_end - run.first_feasible) /
                                                          run.options.scan_step))));
  std::optional<double> cut;  // the T the budget ran out at
  for (int k = 1; k <= curve_points && !cut; ++k) {
    const double T =
        round_to_grid(run.first_feasible + (curve_end - run.first_feasible) * k / curve_points);
    if (T <= run.first_feasible || T > t_max) break;
    if (!run.search.evaluate_warm(T)) cut = T;
  }
  const FailuresAbove failures = confirm_failures_above(run, t_min, cut);
  const std::optional<double>& confirmed_bad = failures.confirmed_bad;
  const double lowest_dropped = failures.lowest_dropped;
  const MinTimePoint* first_bad = confirmed_bad ? point_at(r, *confirmed_bad) : nullptr;
  // With the budget cut: the T above T_min known to be feasible, up to the first one left
  // unjudged.
  double last_planned = t_min;
  for (const MinTimePoint& p : r.curve) {
    if (p.motion_time < lowest_dropped) last_planned = std::max(last_planned, p.motion_time);
  }
  r.feasible_above = first_bad != nullptr ? std::optional<bool>(false)
                     : cut                ? std::nullopt
                                          : std::optional<bool>(true);
  r.t_min_final = true;
  r.status = cut ? SolveStatus::kTimeLimit : SolveStatus::kOptimal;
  r.best.reset();  // the least excess is the infeasible searches' answer
  r.message = "T_min = " + sec(t_min) + ": the shortest motion time on the 1 ms grid whose " +
              "verified " + to_string(run.strategy) + " plan meets " + run.limits;
  if (r.infeasible_below) {
    for (const MinTimePoint& p : r.curve) {
      if (p.motion_time == *r.infeasible_below) {
        r.message += "; " + sec(p.motion_time) + " does not (" + why_not(p, r) + ")";
      }
    }
  } else {
    r.message += "; it is the lower bound of the machine limits and ramps";
  }
  // A rectangular tank's nonlinear model may not hold at T_min: its plan's nonlinear figures are
  // then the linear ones standing in (SPEC §15), and the limits were judged on those.
  if (stood_in_at_t_min(run)) {
    r.message +=
        "; the nonlinear model does not hold for the plan at T_min, so its linear "
        "figures stood in for the nonlinear ones there (nonlinear_model_not_valid)";
    // Where the nonlinear model's range begins above T_min its figures can miss the limits the
    // linear ones met, between the few T the curve plans: no claim about the T above.
    if (r.feasible_above == true) {
      r.feasible_above.reset();
      r.message +=
          "; feasibility above T_min is not established: where the nonlinear model's range "
          "begins, its figures can miss the limits the linear ones met";
    }
  }
  if (first_bad != nullptr) {
    r.message += "; feasibility is not monotone: T = " + sec(first_bad->motion_time) +
                 " above it fails (" + why_not(*first_bad, r) + ")";
  }
  // SPEC §5 "Honest status" carried into the search: T_min meets the limits asked, but when its
  // plan's own warnings say it is not optimal (the liquid spills by the larger model, the wave
  // uncovers the bottom, ...), the answer is acceptable and says why first.
  r.not_optimal = t_min_caveat(run);
  if (!r.not_optimal.empty()) {
    if (!cut) r.status = SolveStatus::kAcceptable;
    r.message = "not optimal: the plan at T_min is not (" + r.not_optimal + "); " + r.message;
  }
  if (cut) {
    r.message = run.budget_text() + " ran out at T = " + sec(*cut) + ", after T_min was " +
                "bracketed, while the curve above it was planned (to " + sec(curve_end) +
                "): the curve is partial, " +
                (first_bad != nullptr ? std::string("and ")
                                      : "every T planned above T_min (up to " + sec(last_planned) +
                                            ") is feasible but beyond that it is unknown; ") +
                r.message;
  }
}

}  // namespace

MinTimeResult min_time(const Format& format, Strategy strategy, const MinTimeOptions& options) {
  const auto started = Clock::now();
  // One budget for the whole search: its plans and the returned plan's robustness report.
  const detail::Deadline budget(options.plan.time_limit, options.plan.stop);
  MinTimeResult r;
  r.strategy = strategy;
  // The returned plan's robustness report, judged by the search's limits, within the budget.
  auto take_report = [&](MinTimeResult& result, const detail::Deadline& deadline) {
    PlanResult& plan = *result.plan;
    std::optional<RobustnessReport> report;
    if (options.path) {
      // Along a path: the returned law swept over +-10 % of the mode frequencies on the planar
      // models (as plan_on_path's report), each point verifying it along the whole path again.
      RobustnessSweep sweep;
      sweep.zeta = plan.model.zeta;
      sweep.rest_time = options.plan.rest_time;
      sweep.eta_rest_max = result.eta_rest_max;
      sweep.eta_motion_max = result.eta_motion_max;
      const auto out_of_time = [&deadline] { return deadline.expired(); };
      report =
          plan.rectangular
              ? rectangular_robustness_report_on_path(*plan.rectangular, *options.path, plan.law,
                                                      sweep, out_of_time)
              : robustness_report_on_path(plan.model, *options.path, plan.law, sweep, out_of_time);
    } else if (!deadline.expired()) {
      Format at = format;
      at.motion_time = plan.law.duration();
      PlanOptions judged = options.plan;
      judged.eta_rest_max = result.eta_rest_max;
      judged.eta_motion_max = result.eta_motion_max;
      report = robustness_of(at, judged, plan);
    }
    if (report) {
      plan.robustness = std::move(*report);
    } else {
      // Not the budget's whole answer: time_limit, which is not cached.
      result.status = SolveStatus::kTimeLimit;
      plan.message += " The robustness report was left out: the search's budget ran out.";
      result.message +=
          "; the returned plan's robustness report was left out: the search's budget ran out "
          "(raise time_limit_s)";
    }
  };
  auto finish = [&]() -> MinTimeResult {
    std::sort(r.curve.begin(), r.curve.end(), [](const MinTimePoint& a, const MinTimePoint& b) {
      return a.motion_time < b.motion_time;
    });
    if (r.plan && options.plan.robustness && !r.plan->invalid_input) take_report(r, budget);
    r.search_ms = std::chrono::duration<double, std::milli>(Clock::now() - started).count();
    return std::move(r);
  };
  if (!prepare_search(format, strategy, options, r)) return finish();
  SearchRun run(format, strategy, options, r, budget);
  if (!coarse_scan(run)) {
    judge_bound(run);
    return finish();
  }
  if (run.first_feasible < 0.0) {
    report_infeasible(run);
    return finish();
  }
  if (!bisect(run)) {
    judge_bound(run);
    return finish();
  }
  extend_curve_and_report(run);
  return finish();
}

MinTimeSummary summarize_min_time(const std::vector<MinTimeResult>& results) {
  MinTimeSummary s;
  // A search its budget cut before T_min was final still verified a plan at its bound: the line
  // can run at that T (the true minimum is at or below it), so it competes, as a bound.
  auto bound = [](const MinTimeResult& r) {
    return r.t_min && r.status == SolveStatus::kTimeLimit && !r.t_min_final && r.plan &&
           r.plan->usable();
  };
  // Its plan's own status stands for the caveats the search had no time to judge.
  auto honest_at = [&bound](const MinTimeResult& r) {
    return r.not_optimal.empty() && (!bound(r) || r.plan->status == SolveStatus::kOptimal);
  };
  for (std::size_t i = 0; i < results.size(); ++i) {
    const MinTimeResult& r = results[i];
    const bool found = r.t_min && (r.status == SolveStatus::kOptimal || r.t_min_final);
    if (!found && !bound(r)) continue;
    if (found && r.strategy == Strategy::kBaseline && !s.baseline) s.baseline = i;
    // A T_min whose plan is not optimal wins only when no strategy's T_min plan is optimal.
    const bool honest = honest_at(r);
    const bool winner_honest = s.winner && honest_at(results[*s.winner]);
    if (!s.winner || (honest && !winner_honest) ||
        (honest == winner_honest && *r.t_min < *results[*s.winner].t_min)) {
      s.winner = i;
    }
  }
  if (s.winner && !results[*s.winner].not_optimal.empty()) {
    s.winner_not_optimal = results[*s.winner].not_optimal;
  }
  if (s.winner) s.winner_bound = bound(results[*s.winner]);
  if (s.winner_bound && s.winner_not_optimal.empty() && !honest_at(results[*s.winner])) {
    s.winner_not_optimal =
        "the plan at its bound is " + std::string(to_string(results[*s.winner].plan->status));
  }
  if (s.winner && s.baseline) {
    const double tw = *results[*s.winner].t_min;
    const double tb = *results[*s.baseline].t_min;
    s.gain_pct = 100.0 * (tb - tw) / tb;
    s.gain_cycles_per_min = 60.0 / tw - 60.0 / tb;
  }
  return s;
}

}  // namespace slosh
