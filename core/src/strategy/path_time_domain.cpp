// time_domain along a planar path: the epigraph problem of time_domain_strategy.cpp on a model
// along the path (the cylinder's planar nonlinear model, the wave height |E| = K |q| at the wall in
// the direction of q; a rectangular tank's models, the highest corner), closed by exchange
// against the dense response of the solver's point and the verified prediction.

#include "strategy/path_time_domain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>

#include "response/planar_sensitivity.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/response/planar_response.hpp"
#include "slosh/core/strategy/path_plan.hpp"
#include "solve/admissible_starts.hpp"
#include "solve/dual.hpp"
#include "text.hpp"

namespace slosh::detail {

namespace {

/// Samples per period of mode 1 the height is first bounded at [-] (as time_domain).
constexpr double kSamplesPerPeriod{32.0};
/// Periods of mode 1 after T that the starting samples of the rest window cover [-]. After T the
/// model is free and damped, its energy never increases (docs/models.md, "The rest window ends
/// by an energy argument"), and the first maxima after T bind; a later peak that breaks the
/// bound is found by the dense check over the whole window and becomes a row of its own. The
/// solver's evaluations integrate only as far as their rows read.
constexpr double kRestSamplePeriods{1.0};
/// Windows per period of mode 1 of the dense check [-].
constexpr double kWindowsPerPeriod{4.0};
constexpr int kExchangeRounds{8};
/// Times a run that ended outside its rows goes again from its repaired end point [-].
constexpr int kRestarts{3};
/// Relative excess over a bound the dense check tolerates, and of a minimised peak over z [-].
constexpr double kDenseTolerance{1e-7};
constexpr double kObjectiveTolerance{1e-6};
/// Steps per period of mode 1 of the solver's sensitivities [-]. DOP853's error scales as
/// (w h)^8: at 12 steps it is about 1e-8 of the peak, far below the bound's tolerance, and the
/// plan is verified (and the bound tightened on a miss) on the accurate prediction's 40 steps.
constexpr double kSensitivityStepsPerPeriod{12.0};
/// Fractions of every segment where the total acceleration is first bounded [-].
constexpr std::array<double, 5> kAccelerationPoints{0.0, 0.25, 0.5, 0.75, 1.0};

/// Half the span, in periods of mode 1, over which a peak's row follows its peak [-]: the peaks
/// the exchange adds move by a small fraction of a period between rounds, and |q| has at most one
/// interior maximum in a sixteenth of a period either side (its maxima are half a period apart
/// on a line and farther apart where the wave turns).
constexpr double kFollowPeriods{1.0 / 16.0};

/// Where the height is bounded: times, whether each is in the motion window, and whether its row
/// follows the peak next to it (the exchange's peaks: their row is then the local maximum of the
/// height over [t - follow, t + follow] within its window, so the dense check of the next round
/// finds it met, where a row at a fixed time leaves the moving peak a little above its bound and
/// each round adds another sample beside it).
struct Samples {
  std::vector<double> t;
  std::vector<char> motion;
  std::vector<char> follow;
  void add(double time, bool in_motion, bool follows = false) {
    t.push_back(time);
    motion.push_back(static_cast<char>(in_motion));
    follow.push_back(static_cast<char>(follows));
  }
  void erase(std::size_t k) {
    const auto i = static_cast<std::ptrdiff_t>(k);
    t.erase(t.begin() + i);
    motion.erase(motion.begin() + i);
    follow.erase(follow.begin() + i);
  }
};

/// A point of the law where the total acceleration is bounded: segment and fraction of it.
struct LawPoint {
  std::size_t segment;
  double fraction;
};

/// The sensitivity and its last evaluation.
struct Workspace {
  std::unique_ptr<PathSensitivity> sensitivity;
  double follow{};            ///< half span of a following row [s]
  double T{};                 ///< the motion window's end [s]
  double end{};               ///< the rest window's end [s]
  std::vector<double> times;  ///< where each row is evaluated
  std::vector<double> values;
  std::vector<std::array<double, kSegments>> gradients;
  std::array<double, kSegments> last{};
  bool valid{false};
  /// An evaluation kept aside: solve_round evaluates every start for its epigraph level before
  /// the solver runs from any, and the run from a start takes its evaluation back instead of
  /// integrating it again (the steps of both are frozen at that start: the same numbers).
  struct Kept {
    std::array<double, kSegments> x{};
    std::vector<double> times;
    std::vector<double> values;
    std::vector<std::array<double, kSegments>> gradients;
  };
  std::vector<Kept> kept;
  /// Objective "rest": the durations of the solver's evaluation that met every row but the
  /// free window's with the least level those need (nearest_level), since the round began.
  std::optional<Durations> nearest;
  double nearest_level{};
};

/// Records x as the workspace's nearest point when it meets every row but the free window's
/// (`g`, its `count` height rows first) and those need a lower level than the nearest so far.
void record_nearest(Workspace& ws, const Samples& samples, bool minimise_motion, const double* x,
                    const double* g, int count, int rows, double tolerance) {
  double level = 0.0;
  for (int r = 0; r < rows; ++r) {
    const auto k = static_cast<std::size_t>(r);
    const bool free = r < count && static_cast<bool>(samples.motion[k]) == minimise_motion;
    if (free) {
      level = std::max(level, ws.values[k]);
    } else if (!(g[r] <= tolerance)) {
      return;
    }
  }
  if (ws.nearest && !(level < ws.nearest_level)) return;
  Durations d{};
  std::copy(x, x + kSegments, d.begin());
  ws.nearest = d;
  ws.nearest_level = level;
}

void keep_evaluation(Workspace& ws) {
  ws.kept.push_back({ws.last, ws.times, ws.values, ws.gradients});
}

/// Takes back the evaluation kept at x, if any (Workspace::kept).
void restore_evaluation(Workspace& ws, const double* x) {
  for (auto it = ws.kept.begin(); it != ws.kept.end(); ++it) {
    if (!std::equal(x, x + kSegments, it->x.begin())) continue;
    ws.times.swap(it->times);
    ws.values.swap(it->values);
    ws.gradients.swap(it->gradients);
    ws.last = it->x;
    ws.valid = true;
    ws.kept.erase(it);
    return;
  }
}

void evaluate(Workspace& ws, const Samples& samples, double eta_ref, const double* x) {
  if (ws.valid && std::equal(x, x + kSegments, ws.last.begin())) return;
  // The response is integrated as far as the last row reads it: the rest window's starting
  // samples cover its first period only, and the dense check integrates the whole window.
  double until = 0.0;
  for (std::size_t k = 0; k < samples.t.size(); ++k) {
    until =
        std::max(until, samples.t[k] + (static_cast<bool>(samples.follow[k]) ? ws.follow : 0.0));
  }
  ws.sensitivity->compute(x, until);
  ws.times = samples.t;
  for (std::size_t k = 0; k < ws.times.size(); ++k) {
    if (!static_cast<bool>(samples.follow[k])) continue;
    const bool motion = static_cast<bool>(samples.motion[k]);
    const double lo = std::max(samples.t[k] - ws.follow, motion ? 0.0 : ws.T);
    const double hi = std::min(samples.t[k] + ws.follow, motion ? ws.T : ws.end);
    ws.times[k] = ws.sensitivity->peak_time(lo, hi);
  }
  ws.sensitivity->eta_at(ws.times, ws.values, ws.gradients);
  for (double& v : ws.values) v /= eta_ref;
  for (auto& g : ws.gradients) {
    for (double& gi : g) gi /= eta_ref;
  }
  std::copy(x, x + kSegments, ws.last.begin());
  ws.valid = true;
}

/// (s''^2 + (kappa s'^2)^2) / a_max^2 - 1 at a law point, with its gradient over the durations.
double acceleration_row(const PlanarPath& path, const double* x, const LawPoint& p, double a_max,
                        double* grad) {
  std::array<Dual7, kSegments> d;
  for (std::size_t i = 0; i < kSegments; ++i) d[i] = Dual7::variable(x[i], i);
  const auto lv = plateau_levels(d, Dual7(path.length()));
  const std::array<Dual7, kSegments> jerk{lv.A / d[0],  Dual7(0.0), -lv.A / d[2], Dual7(0.0),
                                          -lv.B / d[4], Dual7(0.0), lv.B / d[6]};
  Dual7 s(0.0), v(0.0), a(0.0);
  for (std::size_t k = 0; k <= p.segment; ++k) {
    const Dual7 tau = k == p.segment ? d[k] * p.fraction : d[k];
    s = s + tau * (v + tau * (0.5 * a + tau * jerk[k] * (1.0 / 6.0)));
    v = v + tau * (a + 0.5 * tau * jerk[k]);
    a = a + jerk[k] * tau;
  }
  const double kappa = path.curvature(path.element_at(s.v));
  const Dual7 normal = kappa * v * v;
  const Dual7 f = (a * a + normal * normal) * (1.0 / (a_max * a_max)) - 1.0;
  for (std::size_t i = 0; i < kSegments; ++i) grad[i] = f.d[i];
  return f.v;
}

/// The problem's data that outlives one solve.
struct Setup {
  const StrategyContext* c;
  const PathTarget* target;
  bool minimise_motion;
  double bound;  ///< the solver's bound on the other window [m]
  Samples samples;
  std::vector<LawPoint> points;  ///< total acceleration rows (none without a_max)
};

NlpProblem epigraph(Setup& s, Workspace& ws) {
  const StrategyContext& c = *s.c;
  NlpProblem p = c.space.problem(1);
  constexpr int n = kSegments + 1;
  const int count = static_cast<int>(s.samples.t.size());
  const int points = static_cast<int>(s.points.size());
  const int limits = c.space.limit_count();
  p.inequality_count = count + points + limits;
  const double eta_ref = c.eta_ref;
  const double scaled_bound = s.bound / eta_ref;
  p.inequalities = [&s, &ws, eta_ref, scaled_bound, count, points, limits](const double* x,
                                                                           double* g, double* jac) {
    evaluate(ws, s.samples, eta_ref, x);
    for (int r = 0; r < count; ++r) {
      const auto k = static_cast<std::size_t>(r);
      const bool free = static_cast<bool>(s.samples.motion[k]) == s.minimise_motion;
      g[r] = ws.values[k] - (free ? x[kSegments] : scaled_bound);
      if (jac != nullptr) {
        double* row = jac + static_cast<std::ptrdiff_t>(r) * n;
        std::copy(ws.gradients[k].begin(), ws.gradients[k].end(), row);
        row[kSegments] = free ? -1.0 : 0.0;
      }
    }
    for (int r = 0; r < points; ++r) {
      std::array<double, kSegments> grad{};
      g[count + r] = acceleration_row(*s.target->path, x, s.points[static_cast<std::size_t>(r)],
                                      *s.c->space.limits.a_max, grad.data());
      if (jac != nullptr) {
        double* row = jac + static_cast<std::ptrdiff_t>(count + r) * n;
        std::copy(grad.begin(), grad.end(), row);
        row[kSegments] = 0.0;
      }
    }
    if (limits > 0) {
      double* jrow =
          jac == nullptr ? nullptr : jac + static_cast<std::ptrdiff_t>(count + points) * n;
      if (jrow != nullptr) std::fill(jrow, jrow + static_cast<std::ptrdiff_t>(limits) * n, 0.0);
      s.c->space.limit_constraints(x, g + count + points, jrow, n);
    }
    if (!s.minimise_motion) {
      record_nearest(ws, s.samples, s.minimise_motion, x, g, count, count + points + limits,
                     time_domain_options().constraint_tolerance);
    }
  };
  p.before_start = [&ws](const double* x0) {
    ws.sensitivity->freeze_steps(x0);
    ws.valid = false;
    restore_evaluation(ws, x0);
  };
  return p;
}

Samples initial_samples(const StrategyContext& c, double omega) {
  Samples s;
  const double T = c.format.motion_time;
  const double rest = c.options.rest_time;
  const double dt = 2.0 * std::numbers::pi / omega / kSamplesPerPeriod;
  const auto n_motion = static_cast<std::size_t>(std::ceil(T / dt));
  for (std::size_t i = 1; i <= n_motion; ++i)
    s.add(T * static_cast<double>(i) / static_cast<double>(n_motion), true);
  const auto n_rest = static_cast<std::size_t>(std::ceil(rest / dt));
  const double span = kRestSamplePeriods * kSamplesPerPeriod * dt;
  for (std::size_t i = 1; i <= n_rest; ++i) {
    const double t = rest * static_cast<double>(i) / static_cast<double>(n_rest);
    if (t > span && i > 2) break;
    s.add(T + t, false);
  }
  return s;
}

std::vector<LawPoint> initial_points(const StrategyContext& c) {
  std::vector<LawPoint> points;
  if (!c.space.limits.a_max) return points;
  for (std::size_t k = 0; k < kSegments; ++k) {
    for (double u : kAccelerationPoints) points.push_back({k, u});
  }
  return points;
}

MultiStartResult solve_starts(Setup& s, Workspace& ws, const std::vector<Durations>& starts) {
  const StrategyContext& c = *s.c;
  NlpProblem p = epigraph(s, ws);
  std::vector<std::vector<double>> x0 = as_vectors(starts);
  ws.kept.clear();
  for (std::vector<double>& x : x0) {
    ws.sensitivity->freeze_steps(x.data());
    ws.valid = false;
    evaluate(ws, s.samples, c.eta_ref, x.data());
    keep_evaluation(ws);
    double z = 0.0;
    for (std::size_t k = 0; k < s.samples.t.size(); ++k) {
      if (static_cast<bool>(s.samples.motion[k]) == s.minimise_motion) {
        z = std::max(z, ws.values[k]);
      }
    }
    x.push_back(z);
  }
  ws.valid = false;
  // A run that reaches an optimum an earlier start found ends there (it would find nothing new).
  StartPolicy policy;
  policy.leave_known_optima = true;
  // A run SLSQP left outside the rows (its level z at 0 under rows it does not meet: where the
  // least of the free window's peak is near 0, as for objective "rest", it stops there at once)
  // goes again with z raised onto its rows: the point then meets every row it can by itself.
  policy.restarts = kRestarts;
  policy.repair = [&s, &ws, eta_ref = c.eta_ref](std::vector<double>& x) {
    ws.valid = false;
    evaluate(ws, s.samples, eta_ref, x.data());
    double z = 0.0;
    for (std::size_t k = 0; k < s.samples.t.size(); ++k) {
      if (static_cast<bool>(s.samples.motion[k]) == s.minimise_motion) {
        z = std::max(z, ws.values[k]);
      }
    }
    if (!(z > x[kSegments])) return false;
    x[kSegments] = z;
    return true;
  };
  return multi_start(p, x0, c, time_domain_options(), policy);
}

/// One round of the exchange from `starts`. Objective "rest": SLSQP's first step from a law with
/// a residual wave drops the epigraph level to 0 (the linearised peaks reach 0 within a step),
/// and the iterates that follow, at that level under rows they nearly meet, are infeasible:
/// NLopt then returns its best feasible point, the start, as converged (the default objective's
/// law at 3.00 mm "optimal" with eta_motion 18.7 of 63 mm on a line-arc-line path at 1.65 s,
/// while its iterates had reached 0.001 mm). The run goes again from the evaluation that met
/// every other row with the least level (Workspace::nearest), its level raised onto its rows,
/// while that is lower than the round's best.
MultiStartResult solve_round(Setup& s, Workspace& ws, const std::vector<Durations>& starts) {
  ws.nearest.reset();
  MultiStartResult r = solve_starts(s, ws, starts);
  if (s.minimise_motion) return r;
  for (int again = 0; again < kRestarts && ws.nearest && !r.timed_out; ++again) {
    const double reached = r.feasible ? r.best.objective : std::numeric_limits<double>::infinity();
    if (!(ws.nearest_level < reached * (1.0 - kObjectiveTolerance))) break;
    const Durations from = s.c->space.polish(ws.nearest->data());
    ws.nearest.reset();
    MultiStartResult next = solve_starts(s, ws, {from});
    next.evaluations += r.evaluations;
    next.starts += r.starts;
    const bool better =
        next.feasible && !next.best.x.empty() && (!r.feasible || next.best.objective < reached);
    if (!better) {
      r.evaluations = next.evaluations;
      r.starts = next.starts;
      r.timed_out = r.timed_out || next.timed_out;
      continue;
    }
    r = std::move(next);
  }
  return r;
}

/// Adds the dense response's window peaks above their bound (the minimised window's above z) as
/// following rows, unless a following row holds them already; returns whether any was added and
/// raises `bounded_peak` to the bounded window's largest dense peak [m].
bool add_peaks(Setup& s, Workspace& ws, const double* x, double bound, double& bounded_peak) {
  const StrategyContext& c = *s.c;
  ws.sensitivity->compute(x);
  ws.valid = false;
  const double T = c.format.motion_time;
  const double window = 2.0 * std::numbers::pi / s.target->omega / kWindowsPerPeriod;
  const double z = x[kSegments] * c.eta_ref;
  bool added = false;
  for (const bool motion : {true, false}) {
    const bool free = motion == s.minimise_motion;
    const double limit = free ? z * (1.0 + kObjectiveTolerance) : bound * (1.0 + kDenseTolerance);
    const auto peaks = motion ? ws.sensitivity->window_peaks(0.0, T, window)
                              : ws.sensitivity->window_peaks(T, T + c.options.rest_time, window);
    for (const PlanarWindowPeak& p : peaks) {
      if (!free) bounded_peak = std::max(bounded_peak, p.value);
      if (p.value <= limit) continue;
      // A peak a following row already holds is its row's (met within the solver's tolerance:
      // above it only where the bound the solver saw was not tightened yet).
      bool held = false;
      for (std::size_t k = 0; k < s.samples.t.size() && !held; ++k) {
        held = static_cast<bool>(s.samples.follow[k]) &&
               static_cast<bool>(s.samples.motion[k]) == motion &&
               std::abs(s.samples.t[k] - p.time) < ws.follow;
      }
      if (held || std::find(s.samples.t.begin(), s.samples.t.end(), p.time) != s.samples.t.end()) {
        continue;
      }
      // The row bounds the largest height over [t - follow, t + follow]: the fixed samples
      // inside that span are dominated by it, and as rows nearly parallel to it they would
      // only make SLSQP's subproblems ill-conditioned (it then stalls outside the bound).
      for (std::size_t k = s.samples.t.size(); k-- > 0;) {
        if (!static_cast<bool>(s.samples.follow[k]) &&
            static_cast<bool>(s.samples.motion[k]) == motion &&
            std::abs(s.samples.t[k] - p.time) <= ws.follow) {
          s.samples.erase(k);
        }
      }
      s.samples.add(p.time, motion, true);
      added = true;
    }
  }
  return added;
}

/// Adds the point of the law where the total acceleration breaks a_max most (exact), if any.
bool add_acceleration_point(Setup& s, const Durations& d) {
  const StrategyContext& c = *s.c;
  if (!c.space.limits.a_max) return false;
  const SevenSegmentLaw law(d, c.format.stroke);
  const PathAcceleration a = path_acceleration(*s.target->path, law.law());
  if (a.total <= *c.space.limits.a_max * (1.0 + kDenseTolerance)) return false;
  const auto switches = law.switch_times();
  std::size_t k = 0;
  while (k + 1 < kSegments && switches[k + 1] <= a.time) ++k;
  const double fraction = d[k] > 0.0 ? std::clamp((a.time - switches[k]) / d[k], 0.0, 1.0) : 0.0;
  for (const LawPoint& p : s.points) {
    if (p.segment == k && p.fraction == fraction) return false;
  }
  s.points.push_back({k, fraction});
  return true;
}

/// The bounded window's peak of the verified prediction of d [m].
double verified_bounded_peak(const PathTarget& target, bool minimise_motion, const Durations& d) {
  return target.verified_peak(d, !minimise_motion);
}

/// Whether `d` keeps the machine limits, the total horizontal acceleration along the path among
/// them.
bool keeps_path_limits(const StrategyContext& c, const PathTarget& target, const Durations& d) {
  if (!keeps_limits(c.space, c.space.limits, d, kLimitSlack)) return false;
  if (!c.space.limits.a_max) return true;
  const SevenSegmentLaw law(d, c.format.stroke);
  return path_acceleration(*target.path, law.law()).total <=
         *c.space.limits.a_max * (1.0 + kLimitSlack);
}

/// Whether `d` is a law the phase admits: the machine limits and the bound on the verified
/// prediction.
bool admissible_law(const StrategyContext& c, const PathTarget& target, bool minimise_motion,
                    double bound, const Durations& d) {
  return keeps_path_limits(c, target, d) &&
         verified_bounded_peak(target, minimise_motion, d) <= bound * (1.0 + kDenseTolerance);
}

}  // namespace

namespace {

/// One phase: min the free window's peak s.t. the other window's peak <= bound, from `starts`,
/// closed by exchange (dense check of the sensitivities' response, then the verified prediction).
StrategyOutcome run_phase(const StrategyContext& c, const PathTarget& path, bool minimise_motion,
                          double bound, std::vector<Durations> starts) {
  Setup s{&c, &path, minimise_motion, bound, initial_samples(c, path.omega), initial_points(c)};
  const double period = 2.0 * std::numbers::pi / path.omega;
  Workspace ws{path.sensitivity(kSensitivityStepsPerPeriod),
               kFollowPeriods * period,
               c.format.motion_time,
               c.format.motion_time + c.options.rest_time,
               {},
               {},
               {},
               {},
               false,
               {},
               std::nullopt,
               0.0};
  MultiStartResult total;
  int evaluations = 0, solved = 0;
  // The bound the solver sees is the bound over (1 + scheme), less `margin`: `scheme` is how far
  // the verified prediction's bounded peak lies above the sensitivities' (their coarser steps
  // at the last round's point; it varies slowly with the durations), `margin` twice every miss
  // that still remained on the verified prediction.
  double margin = 0.0, scheme = 0.0, miss = 0.0;
  const std::vector<Durations> first = starts;
  // The last round's point that met the bound on the verified prediction: a budget that ends in
  // a later round returns it rather than that round's point, which no check has passed.
  std::optional<Durations> verified;
  for (int round = 0; round < kExchangeRounds; ++round) {
    s.bound = bound * (1.0 - margin) / (1.0 + scheme);
    MultiStartResult r = solve_round(s, ws, starts);
    evaluations += r.evaluations;
    solved += r.starts;
    if (round > 0 && !r.timed_out && (r.best.x.empty() || !r.feasible)) {
      // SLSQP from the last round's point, just outside the rows this round added, can leave
      // the feasible set for good (one step far out, then stalled there) although the phase's
      // own starts still reach it with those rows: the round goes again from them too.
      std::vector<Durations> again = starts;
      for (const Durations& d : first) {
        if (std::find(again.begin(), again.end(), d) == again.end()) again.push_back(d);
      }
      MultiStartResult retry = solve_round(s, ws, again);
      evaluations += retry.evaluations;
      solved += retry.starts;
      if (!retry.best.x.empty() && (retry.feasible || retry.timed_out)) r = std::move(retry);
    }
    total = std::move(r);
    if (total.best.x.empty() || total.timed_out || !total.feasible) break;
    double dense = 0.0;
    const Durations d = c.space.polish(total.best.x.data());
    bool added = add_peaks(s, ws, total.best.x.data(), bound, dense);
    added = add_acceleration_point(s, d) || added;
    // The bound is met only on the prediction the plan is verified by.
    const double value = verified_bounded_peak(path, minimise_motion, d);
    if (dense > 0.0) scheme = std::max(0.0, value / dense - 1.0);
    miss = value > bound * (1.0 + kDenseTolerance) ? value / bound - 1.0 : 0.0;
    if (miss == 0.0 && keeps_path_limits(c, path, d)) verified = d;
    if (!added && miss == 0.0) break;
    // A miss once the rows hold every peak: the scheme's error moved; the bound is tightened.
    if (!added) margin += 2.0 * miss;
    starts = {d};
  }
  StrategyOutcome o = outcome_from(total, c);
  o.evaluations = evaluations;
  o.starts = solved;
  if (miss > 0.0 && (o.status == SolveStatus::kOptimal || o.status == SolveStatus::kAcceptable)) {
    o.status = SolveStatus::kInfeasible;
  }
  if (o.status == SolveStatus::kTimeLimit &&
      !admissible_law(c, path, minimise_motion, bound, o.durations)) {
    // The budget ended the exchange before its point was verified: a point the verified
    // prediction or the limits reject is not admissible, whatever the wall clock allowed. The
    // last verified one is returned instead, else the phase found none.
    if (verified) {
      o.durations = *verified;
    } else {
      o.status = SolveStatus::kInfeasible;
    }
  }
  return o;
}

/// A bound no wave reaches [m]: the other window's constraint of a least infeasible phase.
constexpr double kUnbounded{1e3};

/// Random starts (DurationSpace::starts, seeded: plans stay deterministic) added to the
/// symmetric families where the first starts fall short [-]: where every deterministic start
/// ends outside the bound, a few Dirichlet draws often reach a basin inside it (1.7 s on a
/// line-arc-line path: 4.6 mm at rest from the families, 3 mm from a draw).
constexpr int kLeastRandomStarts{4};

/// The phase from the starts `from` adds to `starts` (the families and draws of with_families),
/// counting `o`'s work too; nullopt when it adds none.
std::optional<StrategyOutcome> phase_from_families(const StrategyContext& c, const PathTarget& path,
                                                   bool motion, double bound,
                                                   const std::vector<Durations>& starts,
                                                   const std::vector<Durations>& from,
                                                   const StrategyOutcome& o) {
  if (from.size() <= starts.size()) return std::nullopt;
  StrategyOutcome wider =
      run_phase(c, path, motion, bound,
                std::vector<Durations>(from.begin() + static_cast<std::ptrdiff_t>(starts.size()),
                                       from.end()));
  wider.evaluations += o.evaluations;
  wider.starts += o.starts;
  return wider;
}

/// Objective "rest": the least residual wave sits in narrow basins the first starts often miss
/// (12.9 mm at rest "optimal" at 1.55 s on a line-arc-line path, 3 mm from a family): the
/// families and draws run too, and the lower verified eta_rest of `o` and theirs is kept.
StrategyOutcome rest_from_families(const StrategyContext& c, const PathTarget& path,
                                   const std::vector<Durations>& starts, double bound,
                                   StrategyOutcome o) {
  const std::vector<Durations> from = with_families(c, starts, kLeastRandomStarts);
  std::optional<StrategyOutcome> wider =
      phase_from_families(c, path, /*motion=*/false, bound, starts, from, o);
  if (!wider) return o;
  const bool better =
      wider->status != SolveStatus::kInfeasible &&
      verified_bounded_peak(path, true, wider->durations) <
          verified_bounded_peak(path, true, o.durations) * (1.0 - kObjectiveTolerance);
  if (better) return std::move(*wider);
  o.evaluations = wider->evaluations;
  o.starts = wider->starts;
  return o;
}

/// The least infeasible law when no phase met the bound from `from`, the first phase's outcome `o`.
StrategyOutcome least_infeasible(const StrategyContext& c, const PathTarget& path, bool motion,
                                 double bound, const std::vector<Durations>& starts,
                                 const std::vector<Durations>& from, StrategyOutcome o) {
  // Least infeasible (as time_domain on a line): SLSQP from a start far outside the bound often
  // ends outside it although laws inside exist. The bounded window's peak alone is minimised from
  // every start on its own (a multi-start keeps one basin, and from the uniform law alone it can
  // end several times above the one another start reaches) and, for a fresh plan, from the
  // symmetric families too; then the bounded phase runs again from every law that meets the
  // bound, else the least value found is reported.
  int evaluations = o.evaluations, solved = o.starts;
  std::vector<Durations> candidates;
  for (const Durations& start : from) {
    if (c.deadline.expired()) break;
    const StrategyOutcome least = run_phase(c, path, !motion, kUnbounded, {start});
    evaluations += least.evaluations;
    solved += least.starts;
    if (least.status != SolveStatus::kFailed) candidates.push_back(least.durations);
  }
  candidates.insert(candidates.end(), from.begin(), from.end());
  candidates.push_back(o.durations);
  // Only laws that keep the machine limits compete (the limits are hard constraints).
  std::optional<Durations> chosen;
  double reached = 0.0;
  std::vector<Durations> met;  // the laws that meet the bound, distinct
  for (const Durations& d : candidates) {
    // Once the budget has run out the plan ends `time_limit` with the best law verified so far:
    // verifying every other candidate would overrun the budget by as many verifications.
    if (chosen && c.deadline.expired()) break;
    if (!keeps_limits(c.space, c.space.limits, d, kLimitSlack)) continue;
    const double v = verified_bounded_peak(path, motion, d);
    if (v <= bound * (1.0 + kDenseTolerance) && std::find(met.begin(), met.end(), d) == met.end()) {
      met.push_back(d);
    }
    if (!chosen || v < reached) {
      reached = v;
      chosen = d;
    }
  }
  o.evaluations = evaluations;
  o.starts = solved;
  const std::string name = motion ? "eta_rest" : "eta_motion";
  if (!chosen) {
    o.durations = starts.front();
    o.status = c.deadline.expired() ? SolveStatus::kTimeLimit : SolveStatus::kInfeasible;
    o.detail = "the machine limits leave no admissible law";
    return o;
  }
  if (!met.empty() && !c.deadline.expired()) {
    StrategyOutcome again = run_phase(c, path, motion, bound, met);
    again.evaluations += evaluations;
    again.starts += solved;
    if (again.status != SolveStatus::kInfeasible) return again;
    o.evaluations = again.evaluations;
    o.starts = again.starts;
  }
  o.durations = *chosen;
  if (!met.empty()) {
    // The least infeasible point meets the bound: a law that keeps the promise, though its
    // objective is not minimised.
    o.status = SolveStatus::kAcceptable;
    o.detail = name + " <= " + sig3(bound * 1e3) + " mm met (" + sig3(reached * 1e3) +
               " mm), but the " + (motion ? "eta_motion" : "eta_rest") +
               " objective was not minimised";
    return o;
  }
  if (c.deadline.expired()) {
    // The budget, not the motion or the limit, ended the search: no advice to change them.
    o.status = SolveStatus::kTimeLimit;
    o.detail = "the budget ran out before a law that meets " + name + " <= " + sig3(bound * 1e3) +
               " mm was found along the path: the best found is " + sig3(reached * 1e3) + " mm";
    return o;
  }
  o.status = SolveStatus::kInfeasible;
  o.detail = "no law found that meets " + name + " <= " + sig3(bound * 1e3) + " mm in " +
             sig3(c.format.motion_time) + " s along the path: the best found is " +
             sig3(reached * 1e3) + " mm; time_domain searches locally (from " +
             std::to_string(from.size()) +
             " starts), so a law may exist that it did not find: a longer motion or a looser "
             "limit makes one likelier";
  return o;
}

/// Objective "rest" against the default objective's law: min eta_motion s.t. eta_rest <=
/// eta_rest_max is a law the rest problem admits whenever its eta_motion is within the bound,
/// yet the rest objective's own starts often miss its basin (a line-arc-line path at 1.65 s:
/// eta_rest 7.11 mm "optimal" with eta_motion <= 63 mm, while that law reaches 3.00 mm with
/// eta_motion 9 mm). That phase runs from the same starts; when its law meets the bound and rests
/// lower than `o`, the rest phase runs again from it, and the lower verified eta_rest is kept.
StrategyOutcome rest_from_motion_law(const StrategyContext& c, const PathTarget& path,
                                     const std::vector<Durations>& starts, double bound,
                                     StrategyOutcome o) {
  if (c.deadline.expired()) return o;
  StrategyOutcome motion =
      run_phase(c, path, /*minimise_motion=*/true, c.options.eta_rest_max, starts);
  if (motion.status == SolveStatus::kInfeasible && !c.deadline.expired()) {
    // As the default objective does (solve_from): its law often lies in a basin only the
    // families, or the least infeasible phase's second run, reach (1.7 and 1.75 s on that path).
    const std::vector<Durations> from = with_families(c, starts, kLeastRandomStarts);
    if (std::optional<StrategyOutcome> wider = phase_from_families(
            c, path, /*motion=*/true, c.options.eta_rest_max, starts, from, motion)) {
      motion = std::move(*wider);
    }
    if (motion.status == SolveStatus::kInfeasible && !c.deadline.expired()) {
      motion = least_infeasible(c, path, /*motion=*/true, c.options.eta_rest_max, starts, from,
                                std::move(motion));
    }
  }
  o.evaluations += motion.evaluations;
  o.starts += motion.starts;
  if (motion.status == SolveStatus::kFailed || c.deadline.expired() ||
      !keeps_limits(c.space, c.space.limits, motion.durations, kLimitSlack) ||
      verified_bounded_peak(path, false, motion.durations) > bound * (1.0 + kDenseTolerance)) {
    return o;
  }
  const double reached = o.status == SolveStatus::kFailed
                             ? std::numeric_limits<double>::infinity()
                             : verified_bounded_peak(path, true, o.durations);
  const double seed = verified_bounded_peak(path, true, motion.durations);
  if (!(seed < reached * (1.0 - kObjectiveTolerance))) return o;
  StrategyOutcome from = run_phase(c, path, /*minimise_motion=*/false, bound, {motion.durations});
  from.evaluations += o.evaluations;
  from.starts += o.starts;
  if (from.status != SolveStatus::kInfeasible && from.status != SolveStatus::kFailed &&
      verified_bounded_peak(path, true, from.durations) <= seed) {
    return from;
  }
  // The rest phase from it ended no lower (the budget ran out, or SLSQP stalled off it): the law
  // itself is returned, a law that keeps the promise though its eta_rest was not minimised.
  o.evaluations = from.evaluations;
  o.starts = from.starts;
  o.durations = motion.durations;
  o.status = c.deadline.expired() ? SolveStatus::kTimeLimit : SolveStatus::kAcceptable;
  o.detail =
      "eta_motion <= " + sig3(bound * 1e3) + " mm met (" +
      sig3(verified_bounded_peak(path, false, motion.durations) * 1e3) +
      " mm) by the law of min eta_motion s.t. eta_rest <= " + sig3(c.options.eta_rest_max * 1e3) +
      " mm, whose eta_rest " + sig3(seed * 1e3) + " mm is below the " + sig3(reached * 1e3) +
      " mm the rest objective's search reached; the eta_rest objective was not minimised "
      "from it";
  return o;
}

/// time_domain along the path from starts that keep the context's machine limits.
StrategyOutcome solve_from(const StrategyContext& c, const PathTarget& path,
                           const std::vector<Durations>& starts) {
  const bool motion = c.options.objective == TimeDomainObjective::kMotion;
  const double bound = motion ? c.options.eta_rest_max : c.eta_motion_max;
  StrategyOutcome o = run_phase(c, path, motion, bound, starts);
  if (!motion && o.status != SolveStatus::kInfeasible && !c.deadline.expired()) {
    return rest_from_motion_law(c, path, starts, bound,
                                rest_from_families(c, path, starts, bound, std::move(o)));
  }
  if (o.status != SolveStatus::kInfeasible || c.deadline.expired()) return o;
  // A fresh plan then starts from the symmetric families and a few random draws: along a path
  // the uniform law and the spectral optima often lie in basins outside the bound (the normal
  // acceleration on the arcs moves the optimum away from the line's) where one of these reaches
  // a law inside it (1.55 s on a line-arc-line path: 12.9 mm at rest from the first starts, the
  // bound met from a family). Only then: a plan whose first phase meets the bound costs nothing.
  const std::vector<Durations> from = with_families(c, starts, kLeastRandomStarts);
  if (std::optional<StrategyOutcome> wider =
          phase_from_families(c, path, motion, bound, starts, from, o)) {
    if (wider->status != SolveStatus::kInfeasible || c.deadline.expired()) return std::move(*wider);
    o.evaluations = wider->evaluations;
    o.starts = wider->starts;
  }
  return least_infeasible(c, path, motion, bound, starts, from, std::move(o));
}

}  // namespace

PathTarget planar_target(const StrategyContext& c, const PlanarPath& path) {
  PathTarget t;
  t.path = &path;
  t.omega = c.model.omega1();
  const SloshingModel model = c.model;
  const double rest = c.options.rest_time;
  const double stroke = c.format.stroke;
  t.sensitivity = [model, &path, rest](double steps_per_period) {
    return std::make_unique<PlanarSensitivity>(model, path, rest, steps_per_period);
  };
  t.verified_peak = [model, &path, rest, stroke](const Durations& d, bool motion) {
    const PlanarDrive drive(path, SevenSegmentLaw(d, stroke).law());
    const PlanarPeaks p = planar_nonlinear_peaks(model, drive, rest);
    return motion ? p.motion.value : p.rest.value;
  };
  return t;
}

StrategyOutcome solve_path_time_domain(const StrategyContext& c, const PathTarget& path,
                                       const std::vector<Durations>& seeds) {
  std::vector<Durations> starts = c.space.starts(0);
  if (!c.space.warm_start) starts.resize(1);
  for (const Durations& d : seeds) {
    if (std::find(starts.begin(), starts.end(), d) == starts.end()) starts.push_back(d);
  }
  // The machine limits are hard constraints of every phase, and SLSQP from a start outside them
  // can end outside them: every start is first moved onto the set they admit (a_max on the
  // tangential acceleration there, which the total one bounds from above).
  AdmissibleStarts admissible = admissible_starts(c, starts);
  StrategyOutcome o;
  if (!admissible.relaxed) {
    o = solve_from(c, path, admissible.starts);
  } else {
    // A limit no law reaches: the law keeps its least reachable value (and every reachable
    // limit); the verification then names that limit.
    StrategyContext raised = c;
    raised.space.limits = admissible.limits;
    o = solve_from(raised, path, admissible.starts);
  }
  // No law met the bound before the budget ran out: the phases that might have found one did
  // not all run, so the search did not show that none exists (and a later, larger budget must
  // not be answered from a cache of this one).
  if (o.status == SolveStatus::kInfeasible && c.deadline.expired())
    o.status = SolveStatus::kTimeLimit;
  return o;
}

}  // namespace slosh::detail
