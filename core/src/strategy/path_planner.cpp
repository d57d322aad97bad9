// plan_on_path (path_plan.hpp): each strategy's law of s(t) along the path, verified on the
// planar models; auto chooses among them on those verified figures (SPEC §5's rule).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include "response/tank_planar_sensitivity.hpp"
#include "slosh/core/model/modal_truncation.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/response/rectangular_planar.hpp"
#include "slosh/core/response/rectangular_yaw.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/strategy/path_plan.hpp"
#include "slosh/core/strategy/rectangular_path_plan.hpp"
#include "slosh/core/strategy/robustness.hpp"
#include "strategy/path_time_domain.hpp"
#include "strategy/status_caveat.hpp"
#include "strategy/strategies.hpp"
#include "text.hpp"

namespace slosh {

namespace {

using detail::sig3;
using detail::sig_above;

constexpr double kLimitSlack{1e-9};
constexpr double kBoundTolerance{1e-7};
/// Relative difference of two residual waves below which a law and its mirror tie.
constexpr double kMirrorTie{1e-9};

SloshPeaks as_peaks(const PlanarPeaks& p) {
  SloshPeaks out;
  out.motion.value = p.motion.value;
  out.motion.time = p.motion.time;
  out.rest.value = p.rest.value;
  out.rest.time = p.rest.time;
  return out;
}

LawPrediction as_prediction(const PathPrediction& p, const KinematicSummary& kinematics) {
  return {as_peaks(p.linear), as_peaks(p.nonlinear), kinematics, p.linear_directions};
}

bool finite(const PathPrediction& p) {
  for (double v : {p.linear.motion.value, p.linear.rest.value, p.nonlinear.motion.value,
                   p.nonlinear.rest.value, p.a_total_peak}) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

/// The figures of `law` along the path: the tank's models for a rectangular tank, else the
/// planar models of `model`.
PathPrediction verified_on_path(const SloshingModel& model,
                                const std::optional<RectangularModel>& tank, const PlanarPath& path,
                                const MotionLaw& law, double rest_time,
                                std::string* warning = nullptr) {
  if (tank) return predict_tank_on_path(*tank, path, law, rest_time, warning);
  return predict_on_path(model, path, law, rest_time);
}

/// What every strategy's plan along the path shares.
struct PathContext {
  const Format& format;  ///< stroke = the path length
  const PlanarPath& path;
  const PlanOptions& options;  ///< robustness and uncertainty off
  SloshingModel model;
  PathPrediction uniform;
  LawPrediction uniform_line;  ///< the uniform law's kinematics (and the line figures)
  const detail::Deadline& deadline;
  /// A rectangular tank's models (SPEC §15): the laws are then verified on them along the path
  /// (rectangular_path_plan.hpp) instead of on the cylinder's planar models.
  std::optional<RectangularModel> tank{};
  /// Why a rectangular tank's nonlinear model does not hold for the uniform law along the path
  /// (its nonlinear figures are then the linear model's), or empty.
  std::string uniform_warning{};
  /// The returned law gets a robustness report (the plan's options.robustness).
  bool report{false};

  /// The verified figures of `law` along the path; the tank's nonlinear model's out-of-range
  /// reason in `*warning` when given.
  [[nodiscard]] PathPrediction predict(const MotionLaw& law, std::string* warning = nullptr) const {
    return verified_on_path(model, tank, path, law, options.rest_time, warning);
  }
  /// What the figures are, for the messages.
  [[nodiscard]] const char* models() const {
    return tank ? "the tank's models" : "the planar models";
  }
};

/// `first` and `then` as one list of clauses ("a; b"), either of which may be empty.
std::string clauses(const std::string& first, const std::string& then) {
  if (first.empty()) return then;
  if (then.empty()) return first;
  return first + "; " + then;
}

/// `text` for a search its budget ended: the budget, not the motion or the limit, is what to
/// change.
std::string budget_advice(std::string text) {
  constexpr std::string_view kAdvice = "lengthen the motion or relax the limit";
  for (std::size_t at = text.find(kAdvice); at != std::string::npos; at = text.find(kAdvice, at)) {
    text.replace(at, kAdvice.size(), "raise time_limit_s");
  }
  return text;
}

/// The first path limit the prediction breaks, as a sentence; empty when all hold.
std::string path_limit_violation(const MachineLimits& lim, const PathPrediction& p) {
  if (lim.v_max && p.v_peak > *lim.v_max * (1.0 + kLimitSlack)) {
    return "the law's peak speed s' " + sig_above(p.v_peak, *lim.v_max) +
           " m/s exceeds limits.v_max = " + detail::precise(*lim.v_max) + " m/s";
  }
  if (lim.a_max && p.a_total_peak > *lim.a_max * (1.0 + kLimitSlack)) {
    return "the law's peak horizontal acceleration sqrt(s''^2 + (s'^2/rho)^2) " +
           sig_above(p.a_total_peak, *lim.a_max) +
           " m/s^2 exceeds limits.a_max = " + detail::precise(*lim.a_max) +
           " m/s^2 (normal acceleration up to " + sig3(p.a_normal_peak) + " m/s^2 on the arcs)";
  }
  if (lim.j_max && p.j_peak > *lim.j_max * (1.0 + kLimitSlack)) {
    return "the law's peak tangential jerk " + sig_above(p.j_peak, *lim.j_max) +
           " m/s^3 exceeds limits.j_max = " + detail::precise(*lim.j_max) + " m/s^3";
  }
  return {};
}

/// time_domain's bound on the verified planar nonlinear prediction, as a sentence when broken.
std::string bound_violation(const PathContext& c, const PathPrediction& p) {
  const bool motion = c.options.objective == TimeDomainObjective::kMotion;
  const double bound = motion ? c.options.eta_rest_max
                              : c.options.eta_motion_max.value_or(c.uniform.nonlinear.motion.value);
  const double value = motion ? p.nonlinear.rest.value : p.nonlinear.motion.value;
  if (value <= bound * (1.0 + kBoundTolerance)) return {};
  return std::string(motion ? "eta_rest" : "eta_motion") + " " + sig3(value * 1e3) + " mm of " +
         (c.tank ? "the tank's model" : "the planar nonlinear model") + " exceeds its bound " +
         sig3(bound * 1e3) + " mm";
}

/// `law_in_range`: the law's nonlinear figures are a rectangular tank's nonlinear model's (the
/// context's `uniform_warning` says the same of the uniform law's); when only one of the two laws'
/// are, the linear figures alone are compared.
std::string worse_than_uniform(const PathContext& c, const PathPrediction& p, bool law_in_range) {
  const bool linear_only = law_in_range != c.uniform_warning.empty();
  std::string figures =
      detail::worse_figures(detail::peak_figures(p), detail::peak_figures(c.uniform), linear_only);
  if (figures.empty()) return {};
  if (linear_only) figures += detail::kWorseOnLinearModel;
  return "worse_than_baseline: " + figures +
         " for the uniform law along the path (more than 5 % and 0.5 mm above it); the uniform "
         "law (strategy baseline) sloshes less there";
}

/// One strategy's law along the path with its verified figures.
struct PathOutcome {
  PlanResult plan;  ///< the law's plan; its status follows the verification along the path
  PathPrediction prediction;
  std::string detail;  ///< how the law was made, and why it is not a solution when it is not
  std::string worse;   ///< its worse_than_baseline warning along the path, or empty
  /// A rectangular tank's nonlinear model out of its range along the path (why the linear
  /// model answers), or empty.
  std::string model_warning;
};

/// The status follows the verification along the path: a usable law that breaks a path limit
/// (or time_domain's bound) is infeasible; a time_domain law that meets them all is usable.
void verify_on_path(const PathContext& c, PathOutcome& o, bool time_domain) {
  const std::string limit = path_limit_violation(c.options.limits, o.prediction);
  std::string violation = limit;
  if (violation.empty() && time_domain) violation = bound_violation(c, o.prediction);
  SolveStatus& status = o.plan.status;
  const bool usable = status == SolveStatus::kOptimal || status == SolveStatus::kAcceptable;
  if (!violation.empty() && usable) {
    status = SolveStatus::kInfeasible;
    o.detail = clauses(violation, o.detail);
  } else if (!limit.empty()) {
    // (time_domain's own sentence already names its bound and the least value found.)
    o.detail = clauses(limit, o.detail);
  } else if (violation.empty() && time_domain && status == SolveStatus::kInfeasible) {
    status = SolveStatus::kAcceptable;
    o.detail = clauses(
        "the law meets every constraint on the verification, though its objective was not "
        "minimised",
        o.detail);
  }
  if (o.plan.strategy != Strategy::kBaseline) {
    o.worse = worse_than_uniform(c, o.prediction, o.model_warning.empty());
  }
}

/// A verified candidate against time_domain's eta bound (BoundVerdict): its other constraints
/// are met when it is usable, or when it is time_domain's law within the path limits.
BoundVerdict bound_verdict(const PathContext& c, const PathOutcome& o) {
  BoundVerdict b;
  b.on_rest = c.options.objective == TimeDomainObjective::kMotion;
  b.bound = b.on_rest ? c.options.eta_rest_max
                      : c.options.eta_motion_max.value_or(c.uniform.nonlinear.motion.value);
  b.value = b.on_rest ? o.prediction.nonlinear.rest.value : o.prediction.nonlinear.motion.value;
  const SolveStatus st = o.plan.status;
  b.others_met = st == SolveStatus::kOptimal || st == SolveStatus::kAcceptable ||
                 st == SolveStatus::kTimeLimit ||
                 (o.plan.strategy == Strategy::kTimeDomain &&
                  path_limit_violation(c.options.limits, o.prediction).empty());
  return b;
}

/// Whether `s`'s tangential objective is blind to the direction of time: the spectral strategies
/// judge |X(w)| (and the jerk), which a law run backwards (its durations reversed, the
/// acceleration a(T - t) negated) leaves unchanged, and their limits are symmetric too.
bool mirror_blind(Strategy s) {
  return s == Strategy::kNotch || s == Strategy::kMultiNotch || s == Strategy::kMinJerkBand;
}

/// Whether the figures `a` along the path are better than `b`: within the path limits first,
/// then the lower residual wave (what the spectral strategies aim at); on a tie (relative 1e-9)
/// the law that starts with the shorter ramp, so the order the two are given in never decides.
bool better_mirror(const PathContext& c, const PathPrediction& a, const Durations& da,
                   const PathPrediction& b, const Durations& db) {
  if (!finite(a)) return false;
  if (!finite(b)) return true;
  const bool a_keeps = path_limit_violation(c.options.limits, a).empty();
  const bool b_keeps = path_limit_violation(c.options.limits, b).empty();
  if (a_keeps != b_keeps) return a_keeps;
  const double ra = a.nonlinear.rest.value, rb = b.nonlinear.rest.value;
  if (std::abs(ra - rb) > kMirrorTie * std::max(ra, rb)) return ra < rb;
  return std::lexicographical_compare(da.begin(), da.end(), db.begin(), db.end());
}

/// A spectral law and its mirror reach the same tangential objective, so which of the two a solve
/// returns turned on the last digits of the motion time (a 90 degree index of a 300 mm table:
/// 1.202 s gave one, 1.2020000000000002 s the other, eta_rest 3.03 and 2.93 mm along the arc).
/// Along a path, where the normal acceleration tells them apart, both are verified and the better
/// is kept: neighbouring times give the same law.
void keep_better_mirror(const PathContext& c, PathOutcome& o) {
  // Each verification integrates the whole motion: none is begun once the budget is spent.
  if (!mirror_blind(o.plan.strategy) || !o.plan.durations || c.deadline.expired()) return;
  const Durations& own = *o.plan.durations;
  Durations mirrored;
  std::reverse_copy(own.begin(), own.end(), mirrored.begin());
  if (mirrored == own) return;
  const SevenSegmentLaw law(mirrored, c.format.stroke);
  std::string warning;
  PathPrediction p = c.predict(law.law(), &warning);
  if (!better_mirror(c, p, mirrored, o.prediction, own)) return;
  PlanResult& r = o.plan;
  r.durations = mirrored;
  r.law = law.law();
  r.A = law.A();
  r.B = law.B();
  r.prediction.kinematics = r.law.summary();
  if (r.move_absolute) r.move_absolute = move_absolute_profile(mirrored, c.format.stroke);
  o.prediction = p;
  o.model_warning = std::move(warning);
}

/// The options of a strategy's plan on the line: the path plan's remaining budget (plan() takes
/// a fresh budget of time_limit), at least kLeastBudget (a positive time_limit is an input rule).
PlanOptions remaining_budget(const PathContext& c) {
  constexpr double kLeastBudget{1e-6};
  PlanOptions o = c.options;
  o.time_limit = std::max(c.deadline.remaining(), kLeastBudget);
  return o;
}

/// Whether the path has an arc (then its normal acceleration drives a tank across the motion).
bool has_arcs(const PlanarPath& path) {
  return std::any_of(path.elements().begin(), path.elements().end(),
                     [](const PathElement& e) { return e.kind == PathElement::Kind::kArc; });
}

/// Whether `law` keeps limits.a_max on the total horizontal acceleration along the path.
bool keeps_total_acceleration(const PathContext& c, const MotionLaw& law) {
  return path_acceleration(c.path, law).total <= *c.options.limits.a_max * (1.0 + kLimitSlack);
}

/// The largest curvature of the path's arcs [1/m] (0 for lines only).
double largest_curvature(const PlanarPath& path) {
  double kappa = 0.0;
  for (std::size_t e = 0; e < path.elements().size(); ++e) {
    kappa = std::max(kappa, std::abs(path.curvature(e)));
  }
  return kappa;
}

/// A strategy's plan on the line, held so that the total horizontal acceleration
/// sqrt(s''^2 + (s'^2/rho)^2) along the path keeps limits.a_max. The line's plan bounds s'' alone
/// by a_max; on an arc the normal part adds to it, so a law the line admits can break the limit
/// that a law of the same strategy keeps (multi_notch on a 90 degree index of a 300 mm table at
/// 1.2 s: 2.21 m/s^2 against a_max = 2, where notch keeps it). Where the normal part alone breaks
/// it, the speed is what must come down, and lower accelerations over the same time and stroke
/// only raise it: the line is planned again with v_max at sqrt(a_max / kappa_max), at which the
/// normal part keeps the limit on every arc (a 100 mm arc at 1.6 s with v_max 0.6 m/s: notch
/// infeasible at 3.6 m/s^2 against 2.5, optimal with that speed). Where the total still breaks
/// it, the line is planned again with a_max scaled by a factor: first by a_max / total, shrunk
/// the same way while the total breaks the limit, then the largest factor that keeps it
/// (bisection), so the strategy's own objective loses as little as it must. `note` says what the
/// limits became.
PlanResult plan_keeping_total_acceleration(const PathContext& c, Strategy s, std::string& note) {
  PlanResult first = plan(c.format, s, remaining_budget(c));
  const std::optional<double>& a_max = c.options.limits.a_max;
  const bool arcs = has_arcs(c.path);
  if (s == Strategy::kBaseline || !a_max || !arcs || !first.usable() ||
      keeps_total_acceleration(c, first.law)) {
    return first;
  }
  std::optional<double> v_cap;
  std::string speed_note;
  if (path_acceleration(c.path, first.law).normal > *a_max * (1.0 + kLimitSlack)) {
    const double cap = std::sqrt(*a_max / largest_curvature(c.path));
    const std::optional<double>& v_max = c.options.limits.v_max;
    PlanOptions o = remaining_budget(c);
    o.limits.v_max = v_max ? std::min(*v_max, cap) : cap;
    PlanResult r = plan(c.format, s, o);
    if (r.usable() && r.status != SolveStatus::kTimeLimit) {
      v_cap = o.limits.v_max;
      speed_note = "its speed held to " + sig3(*v_cap) +
                   " m/s so that the normal acceleration on the arcs keeps limits.a_max = " +
                   detail::precise(*a_max) + " m/s^2";
      if (keeps_total_acceleration(c, r.law)) {
        note = speed_note;
        return r;
      }
      first = std::move(r);
    }
  }
  constexpr int kShrinks{6}, kBisections{5};
  auto plan_at = [&c, s, &a_max, &v_cap](double factor) {
    PlanOptions o = remaining_budget(c);
    o.limits.a_max = factor * *a_max;
    if (v_cap) o.limits.v_max = v_cap;
    return plan(c.format, s, o);
  };
  std::optional<PlanResult> kept;
  double keeps = 0.0, breaks = 1.0;
  double factor = *a_max / path_acceleration(c.path, first.law).total;
  for (int k = 0; k < kShrinks && !kept && !c.deadline.expired(); ++k) {
    PlanResult r = plan_at(factor);
    if (!r.usable() || r.status == SolveStatus::kTimeLimit) break;
    const double total = path_acceleration(c.path, r.law).total;
    if (total <= *a_max * (1.0 + kLimitSlack)) {
      kept = std::move(r);
      keeps = factor;
    } else {
      breaks = factor;
      factor *= *a_max / total;
    }
  }
  if (!kept) return first;
  for (int k = 0; k < kBisections && !c.deadline.expired(); ++k) {
    const double mid = 0.5 * (keeps + breaks);
    PlanResult r = plan_at(mid);
    if (r.usable() && r.status != SolveStatus::kTimeLimit && keeps_total_acceleration(c, r.law)) {
      kept = std::move(r);
      keeps = mid;
    } else {
      breaks = mid;
    }
  }
  note = (speed_note.empty() ? std::string() : speed_note + ", and ") +
         "its tangential acceleration held to " + sig3(keeps * *a_max) +
         " m/s^2 so that the total keeps limits.a_max = " + detail::precise(*a_max) + " m/s^2";
  return std::move(*kept);
}

/// `s`'s outcome `o` when the budget ran out before its law was verified along the path (a
/// verification integrates the whole motion, 0.4-0.9 s along 10 000 arcs over 60 s): the
/// uniform law, verified already, stands in, time_limit.
PathOutcome uniform_in_its_place(const PathContext& c, Strategy s, PathOutcome o) {
  const SevenSegmentLaw law(uniform_durations(c.format.motion_time), c.format.stroke);
  PlanResult& r = o.plan;
  r.status = SolveStatus::kTimeLimit;
  r.durations = uniform_durations(c.format.motion_time);
  r.law = law.law();
  r.A = law.A();
  r.B = law.B();
  r.design.reset();
  r.move_absolute.reset();
  if (c.options.drive_profile == DriveProfile::kMoveAbsolute) {
    r.move_absolute = move_absolute_profile(*r.durations, c.format.stroke);
  }
  r.prediction.kinematics = r.law.summary();
  o.prediction = c.uniform;
  o.model_warning = c.uniform_warning;
  o.detail = "the budget ran out before " + to_string(s) +
             "'s law was verified along the path (each verification integrates the whole "
             "motion): the uniform law, verified already, stands in";
  verify_on_path(c, o, false);
  return o;
}

PathOutcome run_tangential(const PathContext& c, Strategy s) {
  PathOutcome o;
  std::string held;
  o.plan = plan_keeping_total_acceleration(c, s, held);
  // The uniform law is the reference the context verified already (a cylinder's: a rectangular
  // tank's verification also names its model's range), so a long path is not verified twice.
  const bool uniform = s == Strategy::kBaseline && !c.tank &&
                       o.plan.durations == uniform_durations(c.format.motion_time);
  if (!uniform && c.deadline.expired()) return uniform_in_its_place(c, s, std::move(o));
  o.prediction = uniform ? c.uniform : c.predict(o.plan.law, &o.model_warning);
  keep_better_mirror(c, o);
  if (s != Strategy::kBaseline) {
    o.detail = to_string(s) +
               " shapes the tangential acceleration s'' as on a straight line of the path's "
               "length; the normal acceleration s'^2/rho on the arcs is not shaped, and the "
               "figures are " +
               (c.tank ? std::string(c.models()) : std::string("the planar models'")) +
               " along the path";
    if (!held.empty()) o.detail += " (" + held + ")";
  }
  // A line plan that ran past the budget while its law was verified on the line's models was
  // solved: the path's own verification and budget decide (finish).
  const bool solved = o.plan.solved_status == SolveStatus::kOptimal ||
                      o.plan.solved_status == SolveStatus::kAcceptable;
  if (o.plan.status == SolveStatus::kTimeLimit && solved) o.plan.status = o.plan.solved_status;
  if (o.plan.status == SolveStatus::kTimeLimit && s != Strategy::kBaseline) {
    // The law is not shaped as the sentence above says: the solve stopped where the budget left
    // it (at the uniform law, where it starts, when it had no time at all).
    const bool unsolved = o.plan.durations == uniform_durations(c.format.motion_time);
    o.detail = "the solve on the line ran out of the budget first: its law is " +
               std::string(unsolved ? "the uniform law, where it starts"
                                    : "the best admissible point it reached") +
               ", which need not meet the options' bounds (" + o.detail + ")";
  } else if (o.plan.status == SolveStatus::kInfeasible) {
    // Why the tangential law is not a solution (its own constraint: a band, a filter's limit).
    const std::string& m = o.plan.message;
    o.detail = "on the tangential law: " + m.substr(0, m.find(". ")) +
               (o.detail.empty() ? std::string() : "; " + o.detail);
  } else if (o.plan.status == SolveStatus::kOptimal || o.plan.status == SolveStatus::kAcceptable) {
    // The line's warnings do not hold along the path (its own are judged in finish): the status
    // is the solve's, and when that is acceptable its reason leads, as on a line.
    o.plan.status = o.plan.solved_status;
    const std::string& d = o.plan.solved_detail;
    if (o.plan.status == SolveStatus::kAcceptable && !d.empty()) {
      o.detail = "on the tangential law, " + d.substr(0, d.find("; ")) + "; " + o.detail;
    }
  }
  verify_on_path(c, o, s == Strategy::kTimeDomain);
  return o;
}

/// A rectangular tank's time_domain target: its models along the path, the nonlinear one where
/// the uniform law's verification keeps it (within its range), else the linear one; each law is
/// judged by its own verification (rectangular_planar_nonlinear_peaks), as the plan is.
detail::PathTarget tank_target(const PathContext& c, bool& nonlinear) {
  const RectangularModel& tank = *c.tank;
  const double frame = tank_frame_angle(c.path, tank.orientation_deg);
  const double rest = c.options.rest_time, stroke = c.format.stroke;
  const PlanarPath& path = c.path;
  // The context's verification of the uniform law says why the nonlinear model does not hold
  // for it, or nothing when it does: a long motion is not integrated again to ask.
  nonlinear = c.uniform_warning.empty();
  const RectangularPlanarModel which =
      nonlinear ? RectangularPlanarModel::kNonlinear : RectangularPlanarModel::kLinear;
  detail::PathTarget t;
  t.path = &path;
  t.omega = std::max(tank.along_length.omega1(), tank.along_width.omega1());
  t.sensitivity = [&tank, &path, frame, rest, which](double steps_per_period) {
    return std::make_unique<detail::TankPlanarSensitivity>(tank, path, frame, rest, which,
                                                           steps_per_period);
  };
  t.verified_peak = [&tank, &path, frame, rest, stroke](const Durations& d, bool motion) {
    const PlanarDrive drive(path, SevenSegmentLaw(d, stroke).law());
    const PlanarPeaks p =
        rectangular_planar_nonlinear_peaks(tank, drive, frame, rest).peaks.highest;
    return motion ? p.motion.value : p.rest.value;
  };
  return t;
}

/// What time_domain optimised, for its message.
std::string optimised_models(const PathContext& c, bool nonlinear) {
  if (!c.tank) return "the planar nonlinear model along the path";
  return std::string("the tank's ") + (nonlinear ? "nonlinear" : "linear") +
         " model along the path (its modes in its own frame, the highest corner";
}

PathOutcome run_time_domain(const PathContext& c, const PlanResult& base,
                            const std::vector<Durations>& seeds) {
  detail::StrategyContext sc{c.format, c.options, c.model,
                             detail::DurationSpace(c.format, c.options), c.deadline};
  detail::set_design(sc);
  detail::set_references(sc, c.uniform.nonlinear.motion.value);
  bool nonlinear = true;
  detail::StrategyOutcome out;
  const bool solved = !c.deadline.expired();
  if (!solved) {
    // The budget is gone before the solve: the uniform law stands in (the best of the verified
    // starts then replaces it, keep_best_start), and the plan ends time_limit.
    out.status = SolveStatus::kTimeLimit;
    out.durations = uniform_durations(c.format.motion_time);
    out.detail = "the time budget ran out before time_domain's solve began (the uniform law)";
  } else {
    const detail::PathTarget target =
        c.tank ? tank_target(c, nonlinear) : detail::planar_target(sc, c.path);
    out = detail::solve_path_time_domain(sc, target, seeds);
  }
  if (out.status == SolveStatus::kFailed) out.durations = uniform_durations(c.format.motion_time);
  PathOutcome o;
  o.plan = base;
  PlanResult& r = o.plan;
  r.strategy = Strategy::kTimeDomain;
  r.status = out.status;
  r.durations = out.durations;
  const SevenSegmentLaw law(out.durations, c.format.stroke);
  r.law = law.law();
  r.A = law.A();
  r.B = law.B();
  r.design.reset();
  r.move_absolute.reset();
  if (c.options.drive_profile == DriveProfile::kMoveAbsolute) {
    r.move_absolute = move_absolute_profile(out.durations, c.format.stroke);
  }
  r.solver = {out.solver, out.evaluations, out.starts, out.objective, 0.0};
  r.prediction.kinematics = r.law.summary();
  if (out.durations == uniform_durations(c.format.motion_time)) {
    o.prediction = c.uniform;  // verified already, with its model's range
    o.model_warning = c.uniform_warning;
  } else {
    o.prediction = c.predict(r.law, &o.model_warning);
  }
  const bool motion = c.options.objective == TimeDomainObjective::kMotion;
  // A search the budget cut short did not optimise: it says so.
  o.detail = std::string(out.status == SolveStatus::kTimeLimit
                             ? "the budget cut short time_domain's optimisation of "
                             : "time_domain optimised ") +
             optimised_models(c, nonlinear) + (c.tank ? "; " : " (") +
             (motion ? "min eta_motion s.t. eta_rest <= " + sig3(c.options.eta_rest_max * 1e3)
                     : "min eta_rest s.t. eta_motion <= " + sig3(sc.eta_motion_max * 1e3)) +
             (c.tank ? " mm, exact gradients)" : " mm over the whole wall, exact gradients)");
  if (!solved) {
    o.detail = out.detail;
  } else if (!out.detail.empty()) {
    o.detail = out.detail + "; " + o.detail;
  }
  verify_on_path(c, o, true);
  return o;
}

/// A law's standing against time_domain's problem along the path: whether it meets the bound
/// and the path limits, its bounded figure and its objective (the other window's peak) [m].
struct Standing {
  bool meets{false};
  double bounded{};
  double objective{};
  bool keeps_limits{false};
};

Standing standing(const PathContext& c, const PathOutcome& o) {
  const BoundVerdict b = bound_verdict(c, o);
  Standing st;
  st.keeps_limits = path_limit_violation(c.options.limits, o.prediction).empty();
  st.bounded = b.value;
  st.objective =
      b.on_rest ? o.prediction.nonlinear.motion.value : o.prediction.nonlinear.rest.value;
  st.meets = st.keeps_limits && b.value <= b.bound * (1.0 + kBoundTolerance);
  return st;
}

/// time_domain's law against its own starts verified along the path (the uniform law and the
/// spectral optima): the plan never returns a law worse than one of them. A start that meets the
/// bound and the path limits where the law does not, or with a lower objective, is returned
/// instead (`acceptable`: its objective was not minimised), and the message says so; when none
/// meets them, the least infeasible of the law and the starts that keep the limits is returned.
void keep_best_start(const PathContext& c, PathOutcome& o,
                     const std::vector<const PathOutcome*>& starts) {
  const Standing own = standing(c, o);
  const PathOutcome* best = nullptr;
  Standing best_standing = own;
  for (const PathOutcome* s : starts) {
    if (s == nullptr || !s->plan.durations) continue;
    const Standing st = standing(c, *s);
    const bool better =
        st.meets ? !best_standing.meets || st.objective < best_standing.objective * (1.0 - 1e-6)
                 : !best_standing.meets && st.keeps_limits &&
                       (!best_standing.keeps_limits || st.bounded < best_standing.bounded);
    if (better) {
      best = s;
      best_standing = st;
    }
  }
  if (best == nullptr) return;
  const bool motion = c.options.objective == TimeDomainObjective::kMotion;
  const std::string bounded = motion ? "eta_rest" : "eta_motion";
  const std::string objective = motion ? "eta_motion" : "eta_rest";
  const std::string name = best->plan.strategy == Strategy::kBaseline
                               ? std::string("the uniform law")
                               : to_string(best->plan.strategy) + "'s law";
  const std::string own_figures = "time_domain's own law reached " + bounded + " " +
                                  sig3(own.bounded * 1e3) + " mm, " + objective + " " +
                                  sig3(own.objective * 1e3) + " mm";
  PathOutcome chosen = *best;
  chosen.plan.strategy = Strategy::kTimeDomain;
  chosen.plan.solver = o.plan.solver;
  chosen.worse = worse_than_uniform(c, chosen.prediction, chosen.model_warning.empty());
  if (best_standing.meets) {
    chosen.plan.status = SolveStatus::kAcceptable;
    chosen.detail = name + ", one of time_domain's starts, meets " + bounded +
                    " <= " + sig3(bound_verdict(c, o).bound * 1e3) + " mm along the path (" +
                    sig3(best_standing.bounded * 1e3) + " mm) with " + objective + " " +
                    sig3(best_standing.objective * 1e3) + " mm and is returned (" + own_figures +
                    "; the " + objective + " objective was not minimised from it)";
  } else {
    // A search the budget ended proves nothing: time_limit, and the budget is what to raise.
    const bool cut = c.deadline.expired();
    chosen.plan.status = cut ? SolveStatus::kTimeLimit : SolveStatus::kInfeasible;
    chosen.detail = std::string(cut ? "no law found within the budget" : "no law found") +
                    " that meets " + bounded + " <= " + sig3(bound_verdict(c, o).bound * 1e3) +
                    " mm along the path: the least is " + name + ", one of time_domain's starts (" +
                    sig3(best_standing.bounded * 1e3) + " mm), which is returned (" + own_figures +
                    (cut ? "); raise time_limit_s" : "); lengthen the motion or relax the limit");
  }
  o = std::move(chosen);
}

/// The message: what happened, then what the law does along the path.
/// `violation`: the limit or time_domain bound the law breaks on the verification, or empty.
std::string path_message(const PathContext& c, const PlanResult& r, const PathPrediction& p,
                         std::string detail, const std::string& violation) {
  std::string head;
  switch (r.status) {
    case SolveStatus::kOptimal:
    case SolveStatus::kAcceptable:
      head = to_string(r.strategy) + " " + to_string(r.status);
      break;
    case SolveStatus::kInfeasible:
      head = "not a solution";
      // A filtered law (fir_chain, shaper, iir) has no durations: it is the law that is returned.
      detail += r.durations ? "; the durations returned are the least infeasible found"
                            : "; the law returned is the least infeasible found";
      break;
    case SolveStatus::kTimeLimit:
      // A law that misses a constraint is not admissible, however the budget ended.
      head = "the time budget of " + sig3(c.options.time_limit) + " s ran out; " +
             (violation.empty() ? std::string("returning the best admissible point found")
                                : "no admissible point was found (" + violation +
                                      "); returning the least infeasible found");
      break;
    case SolveStatus::kFailed:
      head = "the solver failed; the durations returned are the uniform law";
      break;
  }
  if (!detail.empty()) head += ": " + detail;
  // Both laws on one model: the linear one when their nonlinear figures are of different models.
  const bool one_model = compares_on_linear_model(r.warnings);
  const auto& law = one_model ? p.linear : p.nonlinear;
  const auto& b = one_model ? c.uniform.linear : c.uniform.nonlinear;
  std::string models = c.tank ? "the tank's models in its own frame, the highest corner"
                              : "planar models, the wave maximised over the wall";
  if (one_model) models += "; linear model (both laws on one model)";
  return head + ". Along the path (" + sig3(c.path.length() * 1e3) + " mm; " + models +
         "): eta_motion " + sig3(law.motion.value * 1e3) + " mm (uniform law " +
         sig3(b.motion.value * 1e3) + " mm), eta_rest " + sig3(law.rest.value * 1e3) +
         " mm (uniform law " + sig3(b.rest.value * 1e3) + " mm); peak horizontal acceleration " +
         sig3(p.a_total_peak) + " m/s^2 (normal " + sig3(p.a_normal_peak) + " m/s^2).";
}

/// The result of the outcome `o` for the requested strategy.
/// A tank turning with the path (a rotary table) whose yaw drives the modes its models leave out:
/// the plan says its figures are a lower bound, as simulate of the same law along the same path.
void add_yaw_warning(const PathContext& c, const PlanResult& r, double horizontal_peak,
                     std::vector<Warning>& warnings) {
  if (!c.tank || !c.path.container_turns() || !c.format.container.rectangular) return;
  std::string yaw = yaw_mode_warning(*c.format.container.rectangular, c.format.fill_height,
                                     PlanarDrive(c.path, r.law), horizontal_peak);
  if (!yaw.empty()) warnings.push_back({WarningKind::kYawModesNotModelled, std::move(yaw)});
}

/// The returned law's robustness report along the path: swept over +-10 % of the mode
/// frequencies on the planar models (SPEC §10), within what is left of the budget (each point
/// verifies the law along the whole path again). A report the budget cuts short is left out and
/// the plan says so, as a plan on the line does.
void take_path_robustness(const PathContext& c, PlanResult& r, std::string& detail) {
  if (!c.report || r.invalid_input || r.law.duration() <= 0.0) return;
  RobustnessSweep sweep;
  sweep.zeta = r.model.zeta;
  sweep.rest_time = c.options.rest_time;
  sweep.eta_rest_max = c.options.eta_rest_max;
  sweep.eta_motion_max = c.options.eta_motion_max;
  const auto out_of_time = [&c] { return c.deadline.expired(); };
  std::optional<RobustnessReport> report =
      c.tank ? rectangular_robustness_report_on_path(*c.tank, c.path, r.law, sweep, out_of_time)
             : robustness_report_on_path(r.model, c.path, r.law, sweep, out_of_time);
  if (report) {
    r.robustness = std::move(*report);
  } else if (r.status == SolveStatus::kTimeLimit) {
    detail += std::string(detail.empty() ? "" : "; ") +
              "the robustness report was left out too: raise time_limit_s";
  } else {
    r.status = SolveStatus::kTimeLimit;
    detail =
        "the robustness report was left unfinished (each of its points verifies the law "
        "along the whole path again); the law is returned without it, with its verified "
        "figures: raise time_limit_s or set robustness to false" +
        (detail.empty() ? std::string() : "; " + detail);
  }
}

PlanResult finish(const PathContext& c, Strategy requested, PathOutcome o, std::string detail) {
  const Strategy law_strategy = o.plan.strategy;
  PlanResult r = std::move(o.plan);
  r.strategy = requested;
  r.prediction = as_prediction(o.prediction, r.prediction.kinematics);
  r.baseline = as_prediction(c.uniform, c.uniform_line.kinematics);
  r.path = PathPlanReport{c.path.length(), o.prediction, c.uniform};
  r.robustness.reset();
  r.worst_case.reset();
  r.uncertainty.reset();
  r.warnings = validity_warnings(
      c.format, o.prediction.a_total_peak, o.prediction.linear.motion.value,
      o.prediction.nonlinear.motion.value, o.model_warning.empty(), o.prediction.linear.rest.value,
      o.prediction.linear_directions ? &*o.prediction.linear_directions : nullptr);
  if (!o.model_warning.empty()) {
    r.warnings.push_back({WarningKind::kNonlinearModelNotValid, o.model_warning});
  }
  for (Warning& reference : detail::reference_model_warnings(
           o.model_warning.empty(), c.uniform_warning, detail::peak_figures(o.prediction),
           detail::peak_figures(c.uniform))) {
    r.warnings.push_back(std::move(reference));
  }
  if (!o.worse.empty()) r.warnings.push_back({WarningKind::kWorseThanBaseline, o.worse});
  if (c.tank) {
    // Along arcs the normal acceleration drives the direction across the motion too.
    for (Warning& t :
         modal_truncation_warnings(*c.format.container.rectangular, c.format.fill_height, *c.tank,
                                   c.format.motion_time, has_arcs(c.path))) {
      r.warnings.push_back(std::move(t));
    }
  }
  add_yaw_warning(c, r, o.prediction.a_total_peak, r.warnings);
  if (c.deadline.expired() && r.status == SolveStatus::kInfeasible &&
      law_strategy == Strategy::kTimeDomain && r.invalid_input == std::nullopt) {
    // time_domain's "no law found" is its search's claim, which a search cut short by the
    // budget does not make (and a later, larger budget must not be answered from a cache of it).
    r.status = SolveStatus::kTimeLimit;
    detail = "the budget ran out before time_domain's search along the path ended; " +
             budget_advice(detail);
  } else if (c.deadline.expired() &&
             (r.status == SolveStatus::kOptimal || r.status == SolveStatus::kAcceptable)) {
    // The budget covers the verification along the path, which on a long path costs more than
    // the solves (a 60 s motion along 10 000 arcs: about a second per law): a plan that ran past
    // it says so, as a solve that ran out does, and is not cached as the budget's answer.
    r.status = SolveStatus::kTimeLimit;
    const std::size_t segments = c.path.elements().size();
    detail = "the budget ran out while the law was verified along the path (" +
             std::to_string(segments) + (segments == 1 ? " segment" : " segments") +
             "); the law is returned with its verified figures" +
             (detail.empty() ? std::string() : "; " + detail);
  }
  const bool not_a_solution = r.status == SolveStatus::kInfeasible;
  take_path_robustness(c, r, detail);
  detail::apply_optimal_caveat(r.status, detail, r.warnings, law_strategy);
  // The eta bound binds time_domain's law and auto's choice (the uniform law promises none).
  std::string violation = path_limit_violation(c.options.limits, o.prediction);
  if (violation.empty() &&
      (law_strategy == Strategy::kTimeDomain || requested == Strategy::kAuto)) {
    violation = bound_violation(c, o.prediction);
  }
  // A law that was not a solution stays one whatever cut its report short.
  if (violation.empty() && not_a_solution && r.status == SolveStatus::kTimeLimit) {
    violation = "the law is not a solution of " + std::string(to_string(law_strategy));
  }
  r.message = path_message(c, r, o.prediction, std::move(detail), violation);
  return r;
}

/// The spectral optima (time_domain's extra starts) from their outcomes.
std::vector<Durations> seeds_of(const std::vector<PathOutcome>& outcomes) {
  std::vector<Durations> seeds;
  for (const PathOutcome& o : outcomes) {
    const Strategy s = o.plan.strategy;
    const bool spectral =
        s == Strategy::kNotch || s == Strategy::kMultiNotch || s == Strategy::kMinJerkBand;
    // The tangential plan's own status: its law is the spectral optimum whatever the path does.
    if (spectral && o.plan.durations && !o.plan.message.empty() &&
        o.plan.message.rfind(to_string(s) + " ", 0) == 0) {
      seeds.push_back(*o.plan.durations);
    }
  }
  return seeds;
}

std::vector<PathOutcome> spectral_outcomes(const PathContext& c) {
  std::vector<PathOutcome> out;
  for (Strategy s : {Strategy::kNotch, Strategy::kMultiNotch, Strategy::kMinJerkBand}) {
    if (c.deadline.expired()) break;
    out.push_back(run_tangential(c, s));
  }
  return out;
}

/// SPEC §5: auto never returns a worse_than_baseline candidate while a usable one is not worse
/// on both. choose_auto keeps the candidates that meet time_domain's eta bound apart from those
/// that break it, so where only flagged candidates meet the bound (along a path the normal
/// acceleration, which no tangential law shapes, often leaves the uniform law far above it) it
/// returned a flagged one as optimal. Then the least infeasible law among the usable candidates
/// that are not flagged is returned, `infeasible`, naming the flagged one that meets the bound.
void refuse_worse_choice(const std::vector<PlanCandidate>& candidates,
                         const std::vector<bool>& worse, const std::vector<BoundVerdict>& bounds,
                         AutoChoice& choice) {
  if (choice.bound_missed || !choice.eligible || !worse[choice.index]) return;
  std::optional<std::size_t> least;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const SolveStatus st = candidates[k].status;
    const bool usable = st == SolveStatus::kOptimal || st == SolveStatus::kAcceptable ||
                        st == SolveStatus::kTimeLimit;
    if (!usable || worse[k]) continue;
    if (!least || bounds[k].value < bounds[*least].value) least = k;
  }
  if (!least) return;
  const std::size_t flagged = choice.index;
  const BoundVerdict& b = bounds[*least];
  const std::string figure = b.on_rest ? "eta_rest" : "eta_motion";
  const std::string option = b.on_rest ? "eta_rest_max_mm" : "eta_motion_max_mm";
  choice.index = *least;
  choice.eligible = false;
  choice.bound_missed = true;
  choice.lost[*least] = CandidateLoss::kNone;
  choice.lost_detail[*least].clear();
  choice.lost[flagged] = CandidateLoss::kWorseThanBaseline;
  choice.lost_detail[flagged] =
      "meets " + figure + " <= " + sig3(b.bound * 1e3) +
      " mm but is worse than the uniform law (its worse_than_baseline warning) while a usable "
      "candidate that is not remains";
  choice.bound_sentence =
      "no candidate that is not worse_than_baseline meets " + figure +
      " <= " + sig3(b.bound * 1e3) + " mm (" + option +
      "): " + to_string(candidates[flagged].strategy) + " meets it (" +
      sig3(bounds[flagged].value * 1e3) +
      " mm) but sloshes more than the uniform law elsewhere (ask for it by name to accept that); "
      "the lowest of the others is " +
      sig3(b.value * 1e3) + " mm (" + to_string(candidates[*least].strategy) +
      "), which auto returns";
}

/// auto's candidates along the path, each planned and verified. Once the budget is spent no
/// further candidate is planned (each costs a verification along the path): auto chooses among
/// those it has, and its plan is time_limit.
std::vector<PathOutcome> auto_outcomes(const PathContext& c, const PlanResult& base) {
  std::vector<PathOutcome> outcomes;
  outcomes.push_back(run_tangential(c, Strategy::kBaseline));
  if (!c.deadline.expired()) {
    std::vector<PathOutcome> spectral = spectral_outcomes(c);
    const std::vector<Durations> seeds = seeds_of(spectral);
    for (PathOutcome& o : spectral) outcomes.push_back(std::move(o));
    if (!c.deadline.expired()) {
      outcomes.push_back(run_time_domain(c, base, seeds));
      std::vector<const PathOutcome*> starts;
      for (std::size_t i = 0; i + 1 < outcomes.size(); ++i) starts.push_back(&outcomes[i]);
      keep_best_start(c, outcomes.back(), starts);
    }
  }
  if (!c.deadline.expired()) outcomes.push_back(run_tangential(c, Strategy::kFirChain));
  if (c.options.drive_profile != DriveProfile::kMoveAbsolute && !c.deadline.expired()) {
    outcomes.push_back(run_tangential(c, Strategy::kShaper));
  }
  return outcomes;
}

PlanResult run_auto(const PathContext& c, const PlanResult& base) {
  std::vector<PathOutcome> outcomes = auto_outcomes(c, base);
  const std::size_t all_candidates =
      c.options.drive_profile != DriveProfile::kMoveAbsolute ? 7U : 6U;
  const bool cut = outcomes.size() < all_candidates;
  std::vector<PlanCandidate> candidates;
  std::vector<bool> worse;
  std::vector<BoundVerdict> bounds;
  std::vector<std::size_t> kept;
  std::vector<bool> in_range;  // the tank's nonlinear model holds for candidate k's law
  int evaluations = 0, starts = 0;
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    const PathOutcome& o = outcomes[i];
    evaluations += o.plan.solver.iterations;
    starts += o.plan.solver.starts;
    if (!finite(o.prediction)) continue;
    PlanCandidate k;
    k.strategy = o.plan.strategy;
    k.status = o.plan.status;
    // As the strategy's own plan along the path: a law worse than the uniform law is not optimal.
    if (!o.worse.empty() && k.strategy != Strategy::kBaseline &&
        k.status == SolveStatus::kOptimal) {
      k.status = SolveStatus::kAcceptable;
    }
    k.durations = o.plan.durations;
    k.law = o.plan.law;
    k.prediction = as_prediction(o.prediction, o.plan.prediction.kinematics);
    k.worse_than_baseline = o.worse;
    worse.push_back(!o.worse.empty());
    bounds.push_back(bound_verdict(c, o));
    candidates.push_back(std::move(k));
    kept.push_back(i);
    in_range.push_back(o.model_warning.empty());
  }
  AutoChoice choice = detail::choose_on_one_model(candidates, in_range, worse, bounds);
  refuse_worse_choice(candidates, worse, bounds, choice);
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    candidates[k].chosen = k == choice.index;
    candidates[k].lost = choice.lost[k];
    candidates[k].lost_detail = choice.lost_detail[k];
  }
  PathOutcome& chosen = outcomes[kept[choice.index]];
  if (choice.bound_missed) {
    // The least infeasible law when no candidate meets the eta bound: never optimal.
    chosen.plan.status = SolveStatus::kInfeasible;
    chosen.detail.clear();
  }
  std::string detail =
      choice.bound_missed ? choice.bound_sentence
      : choice.eligible
          ? "auto chose " + to_string(chosen.plan.strategy) +
                " (lowest eta_rest among the candidates within 5 % of the best eta_motion, "
                "judged on " +
                c.models() + " along the path)"
          : std::string("no candidate meets every constraint; auto returns the uniform law");
  if (choice.ranked_on_linear && !choice.bound_missed) detail += detail::kRankedOnLinearModel;
  if (!chosen.detail.empty()) detail += "; " + chosen.detail;
  if (cut) {
    // The candidates not planned might have met the bound: not infeasible, out of time.
    if (chosen.plan.status == SolveStatus::kInfeasible)
      chosen.plan.status = SolveStatus::kTimeLimit;
    detail = "auto planned " + std::to_string(outcomes.size()) + " of its " +
             std::to_string(all_candidates) +
             " candidates before the budget ran out (each is verified along the path); " +
             budget_advice(detail);
  }
  PlanResult r = finish(c, Strategy::kAuto, std::move(chosen), std::move(detail));
  r.solver.iterations = evaluations;
  r.solver.starts = starts;
  r.candidates = std::move(candidates);
  return r;
}

PlanResult run_single(const PathContext& c, const PlanResult& base, Strategy s) {
  if (s != Strategy::kTimeDomain) {
    PathOutcome o = run_tangential(c, s);
    std::string detail = o.detail;
    return finish(c, s, std::move(o), std::move(detail));
  }
  // Its starts verified along the path: the uniform law and (fresh plans) the spectral optima,
  // which also seed its search.
  std::vector<PathOutcome> starts;
  starts.push_back(run_tangential(c, Strategy::kBaseline));
  if (!c.options.warm_start) {
    for (PathOutcome& o : spectral_outcomes(c)) starts.push_back(std::move(o));
  }
  const std::vector<Durations> seeds = seeds_of(starts);
  PathOutcome o = run_time_domain(c, base, seeds);
  std::vector<const PathOutcome*> verified;
  for (const PathOutcome& k : starts) verified.push_back(&k);
  keep_best_start(c, o, verified);
  std::string detail = o.detail;
  return finish(c, s, std::move(o), std::move(detail));
}

}  // namespace

PathPlanReport path_plan_report(const PlanResult& result, const PlanarPath& path,
                                double motion_time, double rest_time) {
  const MotionLaw uniform = SevenSegmentLaw(uniform_durations(motion_time), path.length()).law();
  return {path.length(),
          verified_on_path(result.model, result.rectangular, path, result.law, rest_time),
          verified_on_path(result.model, result.rectangular, path, uniform, rest_time)};
}

PlanResult plan_on_path(const Format& format, const PlanarPath& path, Strategy strategy,
                        const PlanOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  // One budget for the whole plan: the uniform law's verification along the path, each
  // strategy's solve (with what remains) and each law's verification.
  const detail::Deadline deadline(options.time_limit, options.stop);
  Format f = format;
  f.stroke = path.length();
  PlanOptions o = options;
  o.robustness = false;
  o.uncertainty = Uncertainty{};
  // The uniform law's plan: the inputs' validation, the model and the uniform law's figures.
  PlanResult base = plan(f, Strategy::kBaseline, o);
  if (base.invalid_input) {
    base.strategy = strategy;
    return base;
  }
  const MotionLaw uniform = SevenSegmentLaw(uniform_durations(f.motion_time), f.stroke).law();
  std::string uniform_warning;
  PathContext c{
      f,
      path,
      o,
      base.model,
      verified_on_path(base.model, base.rectangular, path, uniform, o.rest_time, &uniform_warning),
      base.baseline,
      deadline,
      base.rectangular,
      std::move(uniform_warning)};
  c.report = options.robustness;
  if (!finite(c.uniform)) {
    base.strategy = strategy;
    base.status = SolveStatus::kFailed;
    base.invalid_input =
        refused(PlanInput::kUniformResponse, c.uniform.nonlinear.motion.value, non_negative(),
                "the uniform law's predicted sloshing along the path is not "
                "finite for this format");
    base.message = "invalid input: " + base.invalid_input->message + "; nothing was planned";
    return base;
  }
  PlanResult r = strategy == Strategy::kAuto ? run_auto(c, base) : run_single(c, base, strategy);
  r.solver.solve_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return r;
}

}  // namespace slosh
