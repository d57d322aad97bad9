// time_domain: the peaks of the nonlinear model's accurate response as objective and constraints
// (thesis sec. 3.4.3, epigraph form), with exact gradients from the dual-number integrator.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "response/nonlinear_sensitivity.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "slosh/core/response/response.hpp"
#include "solve/admissible_starts.hpp"
#include "strategy/strategies.hpp"
#include "text.hpp"

namespace slosh::detail {

namespace {

/// Samples per period of mode 1 at which |eta| is bounded to start with [-]. Between samples a
/// sinusoid can exceed them by 1 - cos(pi / 32) = 0.5 %; the exchange rounds close that gap.
constexpr double kSamplesPerPeriod{32.0};
/// Periods of mode 1 after T that the starting samples of the rest window cover [-]. After T the
/// model's energy never increases, so no maximum of |eta| after the first turning point exceeds
/// it (docs/models.md, "The rest window ends by an energy argument"), and that turning point
/// lies within half a period of T: later samples can only bind by the sampling gap (0.5 %),
/// which the exchange closes by adding the dense peak. Their rows cost SLSQP's subproblem work
/// at every iteration (two thirds of the rest rows at 1 s of rest) for nothing; the dense check
/// still covers the whole window. A whole period leaves room for the nonlinear model's longer
/// period at large amplitude. Robust plans sample the whole window: measured, over an
/// uncertainty range SLSQP needed 45 % more sensitivity evaluations without the later rows,
/// which cost more than their subproblem work saved (robust auto +-5 % 557 M -> 611 M
/// instructions, +-10 % 794 M -> 971 M; callgrind, one thesis plan).
constexpr double kRestSamplePeriods{1.0};
/// Windows per period of mode 1 of the dense check after each solve [-].
constexpr double kCheckWindowsPerPeriod{4.0};
/// Exchange rounds: dense check, add the peak times that exceed their bound, re-solve.
constexpr int kExchangeRounds{8};
/// Exchange rounds of a robust plan, which also adds the frequencies that break the bound.
constexpr int kRobustExchangeRounds{16};
/// Rounds a rectangular tank's phase may add to correct its bound by the gap between the
/// oscillators and the tank's model, each a re-solve from the last point [-].
constexpr int kGapRounds{8};
/// Change of the gap, relative to 1 + gap, below which it has settled [-]: the bound on the tank's
/// model is then met to this share (far inside the 0.1 % a plan's figures are compared to).
constexpr double kGapSettled{1e-5};
/// Largest violation of the solver's constraints (scaled by eta_ref) at which a rectangular
/// tank's round that SLSQP ended outside its bound solves again with the bound tightened [-].
constexpr double kNearlyFeasible{1e-5};
/// Relative excess over a bound the dense check tolerates [-].
constexpr double kDenseTolerance{1e-7};
/// Relative excess of a dense peak over the epigraph variable that adds a sample [-].
constexpr double kObjectiveTolerance{1e-6};
/// The same while a least infeasible phase's objective is hopeless, more than kHopeless times the
/// bound it seeks to meet: the plan is infeasible whatever the last digits, its value is reported
/// to 3 digits and only ranks infeasible laws (min-time's curve), so the exchange rounds stop once
/// it is resolved to 0.1 % instead of running on for digits nobody reads [-].
constexpr double kHopelessObjectiveTolerance{1e-3};
constexpr double kHopeless{1.01};
/// A least infeasible phase stops refining once every peak of its objective is below this
/// fraction of the bound it seeks to meet: the bound is then met with room, and the bounded phase
/// that runs from its point does the rest [-].
constexpr double kMetWithRoom{0.5};

/// How finely a least infeasible phase resolves its objective: it only has to tell whether the
/// bound is met and, when it is not, by how much to 3 digits [m].
struct LeastResolution {
  double hopeless_above;  ///< above it the objective is resolved to kHopelessObjectiveTolerance
  double met_below;       ///< peaks at or below it take no samples and end the solver's run
};

/// The scheme of the sensitivities the solver and the dense check use: DOP853 with 20 steps per
/// period of mode 1 (half the steps of the accurate prediction, whose 40 are sized for the
/// harshest formats' peaks to 1e-6): its error scales as h^8, 256 times that of the prediction's
/// grid, about 1e-10 of the peak on the thesis format and far below kDenseTolerance on harsh
/// ones. The plan's eta are those of the accurate prediction.
NonlinearOptions sensitivity_options() {
  NonlinearOptions o;
  o.steps_per_period = 20.0;
  return o;
}

/// Half the span, in periods of mode 1, over which the row of an exchanged peak follows it [-]:
/// the peaks move by a small fraction of a period between rounds, and |eta| has one maximum per
/// half period.
constexpr double kFollowPeriods{1.0 / 16.0};

// Times at which |eta| is constrained, sorted; `motion[k]` tells the phase of t[k]; `follow[k]`
// whether the row is the largest |eta| over [t[k] - span, t[k] + span] within its phase (the
// exchange's peaks: such a row follows its peak as the durations move, so the next dense check
// finds it met, where a row at a fixed time leaves the moving peak a little above its bound and
// each round adds another sample beside it). One set per model of the context's sample_models.
struct Samples {
  std::vector<double> t;
  std::vector<char> motion;
  std::vector<char> follow;
  double span{};  ///< half span of a following row [s]

  void add(double time, bool in_motion, bool follows = false) {
    auto it = std::lower_bound(t.begin(), t.end(), time);
    if (it != t.end() && std::abs(*it - time) < 1e-12) return;
    const auto k = it - t.begin();
    t.insert(it, time);
    motion.insert(motion.begin() + k, static_cast<char>(in_motion));
    follow.insert(follow.begin() + k, static_cast<char>(follows));
  }
  // Whether a following row of the phase holds `time` in its span.
  [[nodiscard]] bool held(double time, bool in_motion) const {
    for (std::size_t k = 0; k < t.size(); ++k) {
      if (static_cast<bool>(follow[k]) && static_cast<bool>(motion[k]) == in_motion &&
          std::abs(t[k] - time) < span) {
        return true;
      }
    }
    return false;
  }
  // A following row at the peak `time`; the fixed samples of its phase within its span go: the
  // row dominates them, and as rows nearly parallel to it they would only make SLSQP's
  // subproblems ill-conditioned.
  void add_following(double time, bool in_motion) {
    for (std::size_t k = t.size(); k-- > 0;) {
      if (!static_cast<bool>(follow[k]) && static_cast<bool>(motion[k]) == in_motion &&
          std::abs(t[k] - time) <= span) {
        const auto i = static_cast<std::ptrdiff_t>(k);
        t.erase(t.begin() + i);
        motion.erase(motion.begin() + i);
        follow.erase(follow.begin() + i);
      }
    }
    add(time, in_motion, true);
  }
};
using ModelSamples = std::vector<Samples>;

// |eta| at the samples of every model for the last evaluated durations, shared by the objective
// and constraint callbacks of one problem (the solvers call both at the same point): the
// explicit scratch of the time-domain problems, owned by solve_phase beside the samples (as
// Pinocchio passes Data beside Model) and outliving every problem that evaluates into it.
struct TimeDomainWorkspace {
  TimeDomainWorkspace(const StrategyContext& c, const std::vector<SloshingModel>& models) {
    for (const SloshingModel& m : models) {
      sensitivity.emplace_back(m, c.format.stroke, c.options.rest_time, sensitivity_options());
    }
    values.resize(models.size());
    gradients.resize(models.size());
    motion_time = c.format.motion_time;
    end = c.format.motion_time + c.options.rest_time;
  }

  std::vector<NonlinearSensitivity> sensitivity;
  std::vector<std::vector<double>> values;  ///< per model: |eta(t_k)| / eta_ref
  std::vector<std::vector<std::array<double, kSegments>>> gradients;
  double motion_time{};                  ///< the motion window's end [s]
  double end{};                          ///< the rest window's end [s]
  std::array<double, kSegments> last{};  ///< the durations values and gradients are of
  bool valid{false};                     ///< false: values and gradients are stale
  /// The gradients are those at `last` too (an evaluation for values alone leaves them stale).
  bool with_gradients{false};

  /// An evaluation kept aside: solve_epigraph evaluates every start for its epigraph level
  /// before the solver runs from any, and the run from a start takes its evaluation back
  /// instead of integrating it again.
  struct Kept {
    std::array<double, kSegments> x{};
    bool with_gradients{};
    std::vector<NonlinearSensitivity> sensitivity;
    std::vector<std::vector<double>> values;
    std::vector<std::vector<std::array<double, kSegments>>> gradients;
  };
  std::vector<Kept> kept;
};

// Fixes every model's step counts to those of the start x for the solver's run from it (the
// responses are then smooth in the durations during the run); forgets the last evaluation when
// they changed.
void freeze_steps(TimeDomainWorkspace& ws, const double* x) {
  bool changed = false;
  for (NonlinearSensitivity& s : ws.sensitivity) changed = s.freeze_steps(x) || changed;
  if (changed) ws.valid = false;
}

// Keeps the workspace's current evaluation aside (TimeDomainWorkspace::kept).
void keep_evaluation(TimeDomainWorkspace& ws) {
  ws.kept.push_back({ws.last, ws.with_gradients, ws.sensitivity, ws.values, ws.gradients});
}

// Takes back the evaluation kept at x, when there is one and the workspace does not hold x: the
// steps of both were frozen at x, so it is the one evaluate_samples would integrate.
void restore_evaluation(TimeDomainWorkspace& ws, const double* x) {
  if (ws.valid && std::equal(x, x + kSegments, ws.last.begin())) return;
  for (auto it = ws.kept.begin(); it != ws.kept.end(); ++it) {
    if (!std::equal(x, x + kSegments, it->x.begin())) continue;
    ws.sensitivity.swap(it->sensitivity);
    ws.values.swap(it->values);
    ws.gradients.swap(it->gradients);
    ws.last = it->x;
    ws.with_gradients = it->with_gradients;
    ws.valid = true;
    ws.kept.erase(it);
    return;
  }
}

// Evaluates |eta| / eta_ref and, with `gradients`, its gradient at the samples of every model for
// the durations x into `ws`, unless x is the last point evaluated (with its gradients when they
// are asked for). SLSQP asks for no gradients at the trial points of its line search, and most of
// those it then steps away from: their values alone are integrated (the same bits).
void evaluate_samples(TimeDomainWorkspace& ws, const ModelSamples& samples, double eta_ref,
                      const double* x, bool gradients = true) {
  if (ws.valid && (ws.with_gradients || !gradients) &&
      std::equal(x, x + kSegments, ws.last.begin())) {
    return;
  }
  for (std::size_t m = 0; m < samples.size(); ++m) {
    const Samples& sm = samples[m];
    // Nothing after the last sample (or its following row's span) is read: the rest window's
    // later steps are left out (most of it, as the samples end a period after T).
    double until = 0.0;
    for (std::size_t k = 0; k < sm.t.size(); ++k) {
      until = std::max(until, static_cast<bool>(sm.follow[k]) ? sm.t[k] + sm.span : sm.t[k]);
    }
    ws.sensitivity[m].compute(x, until, gradients);
    ws.sensitivity[m].abs_eta_at(sm.t, &ws.values[m], gradients ? &ws.gradients[m] : nullptr);
    for (std::size_t k = 0; k < sm.t.size(); ++k) {
      if (!static_cast<bool>(sm.follow[k])) continue;
      // Its phase: the motion up to T, the rest window after it (T fixed by the equality).
      const bool motion = static_cast<bool>(sm.motion[k]);
      const double lo = std::max(sm.t[k] - sm.span, motion ? 0.0 : ws.motion_time + 1e-12);
      const double hi = std::min(sm.t[k] + sm.span, motion ? ws.motion_time : ws.end);
      const WindowPeak p = ws.sensitivity[m].window_peak(lo, hi);
      ws.values[m][k] = p.value;
      if (gradients) ws.gradients[m][k] = p.gradient;
    }
    for (double& v : ws.values[m]) v /= eta_ref;
    if (!gradients) continue;
    for (auto& g : ws.gradients[m]) {
      for (double& gi : g) gi /= eta_ref;
    }
  }
  std::copy(x, x + kSegments, ws.last.begin());
  ws.valid = true;
  ws.with_gradients = gradients;
}

// A constrained sample: model m, sample k.
struct SampleRow {
  std::size_t m;
  std::size_t k;
};

// min z s.t. |eta_m(t_k)| / eta_ref <= z at the samples of the minimised phase and
// |eta_m(t_k)| / eta_ref <= bound / eta_ref at those of the other phase (none without a bound),
// for every model m. The problem evaluates into `ws` and reads `samples`: both must outlive the
// solve. A run ends once z <= stop_below / eta_ref when that is given.
MultiStartResult solve_epigraph(const StrategyContext& c, bool minimise_motion,
                                std::optional<double> bound, const ModelSamples& samples,
                                const std::vector<Durations>& starts, TimeDomainWorkspace& ws,
                                std::optional<double> stop_below) {
  ws.valid = false;             // the samples may have changed since the last evaluation
  std::vector<SampleRow> rows;  // samples that carry a constraint
  for (std::size_t m = 0; m < samples.size(); ++m) {
    for (std::size_t k = 0; k < samples[m].t.size(); ++k) {
      if (static_cast<bool>(samples[m].motion[k]) == minimise_motion || bound)
        rows.push_back({m, k});
    }
  }
  constexpr int n = kSegments + 1;
  NlpProblem p = c.space.problem(1);
  const double scaled_bound = bound ? *bound / c.eta_ref : 0.0;
  const int count = static_cast<int>(rows.size());
  const int limits = c.space.limit_count();
  p.inequality_count = count + limits;
  const DurationSpace* space = &c.space;
  TimeDomainWorkspace* work = &ws;
  const ModelSamples* sampled = &samples;
  const double eta_ref = c.eta_ref;
  p.inequalities = [work, sampled, eta_ref, rows, minimise_motion, scaled_bound, count, limits,
                    space](const double* x, double* g, double* jac) {
    evaluate_samples(*work, *sampled, eta_ref, x, jac != nullptr);
    for (int r = 0; r < count; ++r) {
      const SampleRow& row_of = rows[static_cast<std::size_t>(r)];
      const bool free = static_cast<bool>((*sampled)[row_of.m].motion[row_of.k]) == minimise_motion;
      g[r] = work->values[row_of.m][row_of.k] - (free ? x[kSegments] : scaled_bound);
      if (jac != nullptr) {
        double* row = jac + static_cast<std::ptrdiff_t>(r) * n;
        const auto& grad = work->gradients[row_of.m][row_of.k];
        std::copy(grad.begin(), grad.end(), row);
        row[kSegments] = free ? -1.0 : 0.0;
      }
    }
    if (limits > 0) {
      double* jrow = jac == nullptr ? nullptr : jac + static_cast<std::ptrdiff_t>(count) * n;
      if (jrow != nullptr) std::fill(jrow, jrow + static_cast<std::ptrdiff_t>(limits) * n, 0.0);
      space->limit_constraints(x, g + count, jrow, n);
    }
  };
  p.before_start = [work](const double* x0) {
    freeze_steps(*work, x0);
    restore_evaluation(*work, x0);
  };
  std::vector<std::vector<double>> x0 = as_vectors(starts);
  // Last start first: the workspace then holds the first start's response, where the solver
  // begins, and the others' are kept aside for their runs: no start is integrated twice.
  ws.kept.clear();
  for (auto it = x0.rbegin(); it != x0.rend(); ++it) {
    std::vector<double>& x = *it;
    freeze_steps(ws, x.data());
    evaluate_samples(ws, samples, eta_ref, x.data());
    if (it + 1 != x0.rend()) keep_evaluation(ws);
    double z = 0.0;
    for (std::size_t m = 0; m < samples.size(); ++m) {
      for (std::size_t k = 0; k < samples[m].t.size(); ++k) {
        if (static_cast<bool>(samples[m].motion[k]) == minimise_motion) {
          z = std::max(z, ws.values[m][k]);
        }
      }
    }
    x.push_back(z);
  }
  NlpOptions o = time_domain_options();
  if (stop_below) o.stop_value = *stop_below / c.eta_ref;
  return multi_start(p, x0, c, o);
}

// The starting samples: kSamplesPerPeriod per period of the model's mode 1 over the motion and
// over the first kRestSamplePeriods of the rest window (the grid of the whole window, cut there;
// a robust plan's over the whole window).
Samples initial_samples(const StrategyContext& c, const SloshingModel& model) {
  const double T = c.format.motion_time;
  const double rest = c.options.rest_time;
  const double period = 2.0 * std::numbers::pi / model.omega1();
  Samples samples;
  samples.span = kFollowPeriods * period;
  const int km = std::max(2, static_cast<int>(std::ceil(T / period * kSamplesPerPeriod)));
  const int kr = std::max(2, static_cast<int>(std::ceil(rest / period * kSamplesPerPeriod)));
  for (int k = 1; k <= km; ++k) samples.add(T * k / km, true);
  const double span = c.robust() ? rest : kRestSamplePeriods * period;
  for (int k = 1; k <= kr; ++k) {
    const double t = rest * k / kr;
    if (t > span && k > 2) break;
    samples.add(T + t, false);
  }
  return samples;
}

// The dense check of the point x on one model: every window peak above its bound (or above the
// epigraph value z for the minimised phase) becomes a sample. Returns whether one was added;
// `excess` grows to the largest relative excess over the bound.
// `computed` is the model's sensitivity already integrated at x (the solver's workspace when its
// last evaluation was x), or null to integrate it here.
// `least` (least infeasible phases): how finely the objective's peaks are sampled.
bool check_dense(const StrategyContext& c, const SloshingModel& model, const double* x, double z,
                 bool minimise_motion, std::optional<double> bound,
                 const std::optional<LeastResolution>& least, Samples& samples, double& excess,
                 NonlinearSensitivity* computed) {
  const double T = c.format.motion_time;
  const double rest = c.options.rest_time;
  const double period = 2.0 * std::numbers::pi / model.omega1();
  const int kw = std::max(1, static_cast<int>(std::ceil(T / period * kCheckWindowsPerPeriod)));
  const int kwr = std::max(1, static_cast<int>(std::ceil(rest / period * kCheckWindowsPerPeriod)));
  std::optional<NonlinearSensitivity> own;
  // The solver's evaluations stop the rest window after their last sample; the check reads the
  // whole window (the same steps, so the values it shares with the samples are unchanged).
  if (computed != nullptr) computed->complete_rest();
  if (computed == nullptr) {
    own.emplace(model, c.format.stroke, rest, sensitivity_options());
    own->compute(x, INFINITY, false);  // its peaks' values and times alone are read
    computed = &*own;
  }
  const NonlinearSensitivity& sens = *computed;
  const bool hopeless = least && z > least->hopeless_above;
  const double level = z * (1.0 + (hopeless ? kHopelessObjectiveTolerance : kObjectiveTolerance));
  bool added = false;
  for (int w = 0; w < kw + kwr; ++w) {
    const bool in_motion = w < kw;
    const bool free = in_motion == minimise_motion;
    if (!free && !bound) continue;
    const double a = in_motion ? T * w / kw : T + rest * (w - kw) / kwr;
    const double b = in_motion ? T * (w + 1) / kw : T + rest * (w + 1 - kw) / kwr;
    const WindowPeak peak = sens.window_peak(in_motion ? a : std::max(a, T + 1e-12), b);
    // A peak a following row holds is met by it (within the solver's tolerance).
    if (samples.held(peak.time, peak.time <= T)) continue;
    if (free) {
      // The objective's own peaks: sampled for accuracy (the reported eta is the dense one).
      if (peak.value > level && !(least && peak.value <= least->met_below)) {
        samples.add_following(peak.time, peak.time <= T);
        added = true;
      }
    } else if (peak.value > *bound * (1.0 + kDenseTolerance)) {
      samples.add_following(peak.time, peak.time <= T);
      added = true;
      excess = std::max(excess, peak.value / *bound - 1.0);
    }
  }
  return added;
}

// Whether the solver's models differ from the one the plan is verified by, so that the bound it
// sees is corrected by their gap: a rectangular tank's time_domain bounds each direction's
// oscillator (doubled for the corners when both are driven), and the tank's nonlinear model adds
// the second mode and the coupling of the directions. (A robust rectangular plan is judged over
// the range's sweep of the tank's model: its check models stay the oscillators', see the docs.)
bool corrects_model_gap(const StrategyContext& c) {
  return c.rectangular != nullptr && !c.robust();
}

// The dense value of the constrained quantity (eta_rest for objective kMotion) at d, the largest
// over the sample models [m]; a rectangular tank's is its verified nonlinear prediction's.
double constrained_value(const StrategyContext& c, bool motion, const Durations& d) {
  // The uniform law at the nominal model alone was simulated once for the plan.
  if (!c.robust() && c.uniform_prediction != nullptr &&
      d == uniform_durations(c.format.motion_time)) {
    const SloshPeaks& p = c.uniform_prediction->nonlinear;
    return motion ? p.rest.value : p.motion.value;
  }
  const MotionLaw law = SevenSegmentLaw(d, c.format.stroke).law();
  if (corrects_model_gap(c)) {
    // A rectangular tank is verified on its own nonlinear model (the second mode, the corners).
    const SloshPeaks p =
        rectangular_nonlinear_peaks(*c.rectangular, law, c.options.rest_time).peaks.highest;
    return motion ? p.rest.value : p.motion.value;
  }
  double value = 0.0;
  for (const SloshingModel& m : c.check_models) {
    const SloshPeaks p = nonlinear_peaks(m, law, c.options.rest_time);
    value = std::max(value, motion ? p.rest.value : p.motion.value);
  }
  return value;
}

// Robust plans: the check model (of the robustness grid over the uncertainty range) whose bounded
// peak breaks the bound the most at x, appended to `models` (exchange in frequency, as the dense
// check is in time). Returns whether one was added; `excess` grows to its relative excess and
// `accurate` is set to the largest bounded peak over the check models [m].
bool add_breaking_model(const StrategyContext& c, const double* x, bool minimise_motion,
                        double bound, std::vector<SloshingModel>& models, double& excess,
                        double& accurate) {
  if (!c.robust()) return false;
  Durations d;
  std::copy(x, x + kSegments, d.begin());
  const MotionLaw law = SevenSegmentLaw(d, c.format.stroke).law();
  double worst = bound * (1.0 + kDenseTolerance);
  const SloshingModel* breaking = nullptr;
  accurate = 0.0;
  for (const SloshingModel& m : c.check_models) {
    const SloshPeaks p = nonlinear_peaks(m, law, c.options.rest_time);
    const double value = minimise_motion ? p.rest.value : p.motion.value;
    accurate = std::max(accurate, value);
    if (value > worst) {
      worst = value;
      breaking = &m;
    }
  }
  if (breaking == nullptr) return false;
  for (const SloshingModel& m : models) {
    if (m.omega1() == breaking->omega1()) return false;  // already sampled: time exchange's job
  }
  models.push_back(*breaking);
  excess = std::max(excess, worst / bound - 1.0);
  return true;
}

// The relative excess of the bounded peak of the solver's point x over `bound` on the accurate
// prediction the plan is verified by (`robust_value`: the worst over the check models, computed
// by add_breaking_model), 0 within kDenseTolerance. The sensitivities run at half the
// prediction's steps (frozen at the run's start): where the motion's peak is tens of times the
// bounded one (short motions) their error at the bounded peak reaches 1e-4 of the bound, so a
// point they accept can break it on that prediction.
double accurate_miss(const StrategyContext& c, bool minimise_motion, double bound,
                     const std::vector<double>& x, double robust_value) {
  const double value =
      c.robust() ? robust_value : constrained_value(c, minimise_motion, c.space.polish(x.data()));
  return value > bound * (1.0 + kDenseTolerance) ? value / bound - 1.0 : 0.0;
}

// The gap of the solver's oscillators to a rectangular tank's verified model at x: how far the
// verified bounded peak lies above the largest dense bounded peak of the sample models, as a
// share of the latter, at least 0. `ws` holds the sample models' responses at x, or is null.
double model_gap(const StrategyContext& c, bool minimise_motion, const double* x,
                 const TimeDomainWorkspace* ws, const std::vector<SloshingModel>& models) {
  const double T = c.format.motion_time;
  const double end = T + c.options.rest_time;
  double dense = 0.0;
  for (std::size_t m = 0; m < models.size(); ++m) {
    std::optional<NonlinearSensitivity> own;
    const NonlinearSensitivity* sens = ws != nullptr ? &ws->sensitivity[m] : nullptr;
    if (sens == nullptr) {
      own.emplace(models[m], c.format.stroke, c.options.rest_time, sensitivity_options());
      own->compute(x, INFINITY, false);
      sens = &*own;
    }
    dense = std::max(dense, minimise_motion ? sens->window_peak(T + 1e-12, end).value
                                            : sens->window_peak(0.0, T).value);
  }
  const double verified = constrained_value(c, minimise_motion, c.space.polish(x));
  return dense > 0.0 ? std::max(0.0, verified / dense - 1.0) : 0.0;
}

// The gap a rectangular tank's next round corrects its bound by: the root of
// F(gap) = measured(gap) - gap, `measured` the gap at the point solved for with `gap`. The plain
// iteration gap <- measured converges slowly both where the point's gap falls as the bound
// tightens (on the docs' cup F' is about -1.6: each round overshoots by two thirds of its step)
// and where it grows (F' about -0.4 on the same cup moved 200 mm, whose nonlinear model leaves
// its range: each round makes a third of its way), so the step is the secant's through the last
// two settled rounds: inside their bracket when they bracket the root, else along the plain
// step and at most kMaxGapExtrapolation times it.
class GapRoot {
 public:
  // The gap to solve for next, after the point solved for with `used` measured `measured`.
  double next(double used, double measured) {
    const double f = measured - used;
    double out = measured;
    if (has_last_ && f != f_last_) {
      const double step = -f * (used - used_last_) / (f - f_last_);
      const bool bracketed = (f < 0.0) != (f_last_ < 0.0);
      const bool along =
          (step < 0.0) == (f < 0.0) && std::abs(step) <= kMaxGapExtrapolation * std::abs(f);
      if (bracketed || along) out = std::max(0.0, used + step);
    }
    used_last_ = used;
    f_last_ = f;
    has_last_ = true;
    return out;
  }

 private:
  /// Largest secant step outside a bracket, in plain steps [-].
  static constexpr double kMaxGapExtrapolation{4.0};
  double used_last_{};
  double f_last_{};
  bool has_last_{false};
};

// The durations of a solver's point.
Durations point_of(const MultiStartResult& r) {
  Durations d;
  std::copy(r.best.x.begin(), r.best.x.begin() + kSegments, d.begin());
  return d;
}

// Whether the best run's step counts, frozen at its start, had to grow on the way to its point:
// the response it saw jumped there, and SLSQP can stop at such a jump short of the optimum.
bool outgrew_steps(const MultiStartResult& total, const std::vector<Durations>& starts,
                   const TimeDomainWorkspace& ws) {
  if (total.best_start < 0 || static_cast<std::size_t>(total.best_start) >= starts.size()) {
    return false;
  }
  const Durations& from = starts[static_cast<std::size_t>(total.best_start)];
  bool outgrown = false;
  for (const NonlinearSensitivity& s : ws.sensitivity) {
    outgrown = outgrown || s.outgrows_frozen_steps(from.data(), total.best.x.data());
  }
  return outgrown;
}

// The correction of a rectangular tank's bound (solve_phase). Its bound is met on the tank's own
// model, not on the oscillators the solver sees: the bound they are given is divided by
// (1 + gap), `gap` how far the verified bounded peak lies above the oscillators' dense one. The
// gap is measured only where the oscillators' exchange has settled (no new sample, no outgrown
// steps), the first time at the optimum of the uncorrected problem, and each new gap is solved
// for again from that point until it no longer moves: the plan is then the fixed point of a
// continuation from the oscillators' own optimum. (A gap measured at the first rounds' points,
// far from any optimum, where it can be twice its final value, would steer the search by
// wherever those rounds happened to land.)
struct GapCorrection {
  bool active{false};
  double gap{0.0};
  GapRoot root;
  /// The last settled point that met the bound on the tank's model: it stands when a corrected
  /// bound turns out infeasible, or when the rounds run out on a point that breaks it.
  std::optional<MultiStartResult> met;
  int hair_retries{0};  ///< solves again after SLSQP stopped a hair outside the bound

  // Measures the gap at the settled point of `total` (`missed`: its miss on the tank's model,
  // `ws` its responses or null) and takes the next one; returns whether the gap moved.
  bool settle(const StrategyContext& c, bool minimise_motion, const MultiStartResult& total,
              const TimeDomainWorkspace* ws, const std::vector<SloshingModel>& models,
              double missed) {
    const double measured = model_gap(c, minimise_motion, total.best.x.data(), ws, models);
    const bool moved = std::abs(measured - gap) > kGapSettled * (1.0 + gap);
    gap = root.next(gap, measured);
    if (missed == 0.0) met = total;
    return moved;
  }
  // SLSQP can stop converged a hair outside its bound (1e-7 of eta_ref where its tolerance is
  // 1e-8, which alone made the docs' cup infeasible): whether to tighten the bound by twice the
  // excess (into `margin`) and solve again from the point.
  bool hair_retry(const StrategyContext& c, const MultiStartResult& total, double solver_bound,
                  double& margin) {
    if (!active || total.best.max_violation > kNearlyFeasible || hair_retries >= 2) return false;
    ++hair_retries;
    margin += 2.0 * total.best.max_violation * c.eta_ref / solver_bound;
    return true;
  }
  // The last point that met the bound replaces `total` (its counts kept), when there is one.
  void restore(MultiStartResult& total, double* bound_excess) {
    if (!met) return;
    met->evaluations = total.evaluations;
    met->starts = total.starts;
    total = std::move(*met);
    met.reset();
    *bound_excess = 0.0;
  }
};

// One exchange step at the solver's point: the dense check of every sample model (every peak
// above its bound becomes a sample) and, for robust plans, the check model that breaks the bound
// the most (a new sample model).
struct Exchange {
  const StrategyContext& c;
  bool minimise_motion;
  std::optional<double> bound;
  const std::optional<LeastResolution>& least;
  double excess{0.0};    ///< the largest relative excess over the bound found
  double accurate{0.0};  ///< the bounded peak of the accurate prediction (robust: worst case)

  // Returns whether a sample or a model was added; `at_last`: `ws` holds the point's responses.
  bool add(const MultiStartResult& total, bool at_last, std::vector<SloshingModel>& models,
           ModelSamples& samples, TimeDomainWorkspace& ws) {
    const double z = total.best.x[kSegments] * c.eta_ref;
    bool added = false;
    for (std::size_t m = 0; m < samples.size(); ++m) {
      added = check_dense(c, models[m], total.best.x.data(), z, minimise_motion, bound, least,
                          samples[m], excess, at_last ? &ws.sensitivity[m] : nullptr) ||
              added;
    }
    if (bound && add_breaking_model(c, total.best.x.data(), minimise_motion, *bound, models, excess,
                                    accurate)) {
      samples.push_back(initial_samples(c, models.back()));
      ws = TimeDomainWorkspace(c, models);  // one sensitivity per model
      added = true;
    }
    return added;
  }
};

// The epigraph problem with its semi-infinite constraint closed by exchange: after each solve the
// dense accurate response of every sample model is checked window by window, and every peak
// above its bound becomes a new sample for the next solve (started from the current point).
// A rectangular tank's bound is corrected by its gap to the tank's model (GapCorrection).
MultiStartResult solve_phase(const StrategyContext& c, bool minimise_motion,
                             std::optional<double> bound, std::vector<Durations> starts,
                             double* bound_excess,
                             const std::optional<LeastResolution>& least = std::nullopt) {
  std::vector<SloshingModel> models = c.sample_models;
  ModelSamples samples;
  for (const SloshingModel& m : models) samples.push_back(initial_samples(c, m));
  // Between samples the peaks move with the durations, so from the second round on the bound
  // given to the solver is tightened by twice the excess the dense check still finds.
  MultiStartResult total;
  double margin = 0.0;
  *bound_excess = 0.0;
  GapCorrection gc;
  gc.active = bound && corrects_model_gap(c);
  const int rounds =
      (c.robust() ? kRobustExchangeRounds : kExchangeRounds) + (gc.active ? kGapRounds : 0);
  TimeDomainWorkspace ws(c, models);
  bool rerun = false;  // this round re-runs the last point on the same samples
  for (int round = 0; round < rounds; ++round) {
    std::optional<double> solver_bound;
    if (bound) solver_bound = *bound * (1.0 - margin) / (1.0 + gc.gap);
    MultiStartResult r = solve_epigraph(c, minimise_motion, solver_bound, samples, starts, ws,
                                        least ? std::optional(least->met_below) : std::nullopt);
    r.evaluations += total.evaluations;
    r.starts += total.starts;
    if (rerun && (r.best.x.empty() || (total.feasible && !r.feasible) ||
                  r.best.objective > total.best.objective)) {
      // Nothing better on the same samples: the last point stands (its counts are kept). Its gap
      // was not measured (its steps had outgrown their frozen counts): a moved gap re-solves.
      total.evaluations = r.evaluations;
      total.starts = r.starts;
      if (!gc.active) break;
      const double missed = accurate_miss(c, minimise_motion, *bound, total.best.x, 0.0);
      *bound_excess = std::max(*bound_excess, missed);
      if (!gc.settle(c, minimise_motion, total, nullptr, models, missed)) break;
      rerun = false;
      starts = {point_of(total)};
      continue;
    }
    total = std::move(r);
    if (total.best.x.empty() || total.timed_out) break;
    // A round that cannot meet the bound on its samples is final: the exchange only adds samples,
    // and a problem with more constraints is no more feasible than one with fewer.
    if (bound && !total.feasible) {
      if (gc.hair_retry(c, total, *solver_bound, margin)) {
        rerun = false;
        starts = {point_of(total)};
        continue;
      }
      gc.restore(total, bound_excess);
      break;
    }
    // The solver's last evaluation is usually its returned point: its responses are reused.
    const bool at_last = ws.valid && std::equal(total.best.x.begin(),
                                                total.best.x.begin() + kSegments, ws.last.begin());
    // An outgrown run goes again from its point with the counts frozen there (no new samples).
    const bool outgrown = outgrew_steps(total, starts, ws);
    Exchange e{c, minimise_motion, bound, least};
    const bool added = e.add(total, at_last, models, samples, ws);
    double excess = e.excess;
    const double accurate = e.accurate;
    // The bound is met only on the prediction the plan is verified by; a miss tightens the bound
    // the solver sees by twice the miss (unless a moved gap answers it) and solves again.
    const double missed = bound && !added && !outgrown
                              ? accurate_miss(c, minimise_motion, *bound, total.best.x, accurate)
                              : 0.0;
    const bool gap_moved =
        gc.active && !added && !outgrown &&
        gc.settle(c, minimise_motion, total, at_last ? &ws : nullptr, models, missed);
    const double dense_excess = excess;
    excess = std::max(excess, missed);
    *bound_excess = excess;
    if (!added && !outgrown && missed == 0.0 && !gap_moved) break;
    rerun = !added && missed == 0.0 && !gap_moved;  // a new gap is a new problem
    const double unexplained = gap_moved ? 0.0 : missed;
    if (round >= 1) margin += 2.0 * std::max(dense_excess, unexplained);
    if (round == 0) margin += 2.0 * unexplained;
    starts = {point_of(total)};
  }
  if (*bound_excess > kDenseTolerance && !total.timed_out) gc.restore(total, bound_excess);
  return total;
}

// The bounded phase from `from` (starts that keep the machine limits) into `out`, adding to its
// counts (dense excess within kDenseTolerance counts as met).
void run_bounded(const StrategyContext& c, bool motion, double bound,
                 const std::vector<Durations>& from, StrategyOutcome* out) {
  double excess = 0.0;
  const MultiStartResult m = solve_phase(c, motion, bound, from, &excess);
  const int evaluations = out->evaluations + m.evaluations;
  const int solved = out->starts + m.starts;
  *out = outcome_from(m, c);
  out->evaluations = evaluations;
  out->starts = solved;
  if ((out->status == SolveStatus::kTimeLimit || out->status == SolveStatus::kFailed) &&
      !keeps_limits(c.space, c.space.limits, out->durations, kLimitSlack)) {
    // Out of time before any feasible point, outcome_from falls back on the uniform law, which
    // may break the limits; every start here keeps them.
    out->durations = from.front();
  }
  if ((out->status == SolveStatus::kOptimal || out->status == SolveStatus::kAcceptable) &&
      excess > kDenseTolerance) {
    // The exchange rounds ran out before the dense check passed: not met.
    out->status = SolveStatus::kInfeasible;
  }
}

// When the bounds leave no room (4 min_ramp plus the plateau minimums fill T), the clause
// saying so: the options, not the search, then fix the law; else empty.
std::string one_admissible_law(const StrategyContext& c) {
  double room = c.format.motion_time;
  for (double lo : c.space.lower) room -= lo;
  if (room > kZeroDuration) return {};
  return " (4 x min_ramp_s = " + sig3(4.0 * c.options.min_ramp) +
         " s plus the plateau minimums fill the motion time: one admissible law)";
}

// Least infeasible phase after the bounded phase `o` was infeasible (SLSQP from a start far
// outside the bound often ends outside it although laws inside exist). First, from every start
// and, for a fresh plan, the symmetric families too, the constrained quantity alone is minimised
// (eta_rest, or eta_motion for objective kRest) until it is met with room: each start its own run,
// since from the uniform law alone it often ends in a local minimum tens of times the one the
// other starts reach. Then the bounded phase runs again from every point that meets the bound
// (feasible starts); failing that, the best of them is itself a law that meets the bound. The
// machine limits stay hard constraints: only laws that keep them compete. time_domain is a local
// method: when no law it finds meets the bound it says so, with what the best found reaches, and
// does not claim that none exists.
StrategyOutcome least_infeasible(const StrategyContext& c, bool motion, double bound,
                                 const std::vector<Durations>& starts, StrategyOutcome o) {
  const std::vector<Durations> from = with_families(c, starts, 0);
  const LeastResolution least{bound * kHopeless, bound * kMetWithRoom};
  // The admissible laws at hand: the minimisers' points, the starts and the bounded phase's point.
  std::vector<Durations> candidates;
  bool minimised = false;  // some run of the first step ended
  for (const Durations& start : from) {
    if (c.deadline.expired()) break;
    double unused = 0.0;
    const MultiStartResult r = solve_phase(c, !motion, std::nullopt, {start}, &unused, least);
    o.evaluations += r.evaluations;
    o.starts += r.starts;
    if (r.best.x.empty() || !r.feasible) continue;
    minimised = true;
    candidates.push_back(c.space.polish(r.best.x.data()));
  }
  candidates.insert(candidates.end(), from.begin(), from.end());
  candidates.push_back(o.durations);
  std::optional<Durations> chosen;  // the least value of the constrained quantity
  double reached = 0.0;
  std::vector<Durations> met;  // the laws that meet the bound, distinct
  for (const Durations& d : candidates) {
    if (!keeps_limits(c.space, c.space.limits, d, kLimitSlack)) continue;
    const double v = constrained_value(c, motion, d);
    if (v <= bound * (1.0 + kDenseTolerance) && std::find(met.begin(), met.end(), d) == met.end()) {
      met.push_back(d);
    }
    if (!chosen || v < reached) {
      reached = v;
      chosen = d;
    }
  }
  if (!chosen || (!minimised && c.deadline.expired())) {
    o.status = c.deadline.expired() ? SolveStatus::kTimeLimit : SolveStatus::kInfeasible;
    if (chosen) o.durations = *chosen;
    o.detail = chosen ? "the time budget ran out before the least infeasible search ended"
                      : "the machine limits leave no admissible law";
    return o;
  }
  const std::string bounded_name = motion ? "eta_rest" : "eta_motion";
  if (!met.empty()) {
    StrategyOutcome again;
    again.evaluations = o.evaluations;
    again.starts = o.starts;
    run_bounded(c, motion, bound, met, &again);
    if (again.status != SolveStatus::kInfeasible) return again;
    o.evaluations = again.evaluations;
    o.starts = again.starts;
    // The least infeasible point meets the bound: a law that keeps the promise, though its
    // objective is not minimised.
    o.status = SolveStatus::kAcceptable;
    o.durations = *chosen;
    o.detail = bounded_name + " <= " + sig3(bound * 1e3) + " mm met (" + sig3(reached * 1e3) +
               " mm), but the " + (motion ? "eta_motion" : "eta_rest") +
               " objective was not minimised";
    return o;
  }
  o.status = SolveStatus::kInfeasible;
  o.durations = *chosen;
  // Over several models (an uncertainty range's samples, a turned tank's two directions at
  // their bounding factors) the figure is the design's largest, not one the plan reports.
  const std::string over = c.sample_models.size() > 1
                               ? " on the design's " + std::to_string(c.sample_models.size()) +
                                     " models (the plan's verified figures follow)"
                               : "";
  o.detail = "no law found that meets " + bounded_name + " <= " + sig3(bound * 1e3) + " mm in " +
             sig3(c.format.motion_time) + " s: the best found is " + sig3(reached * 1e3) + " mm" +
             over + " (time_domain searches locally, from " + std::to_string(from.size()) +
             " starts)" + one_admissible_law(c) + "; lengthen the motion or relax the limit";
  return o;
}

// The objective of the durations d on the dense response of every sample model (the largest
// peak of the minimised phase / eta_ref), or nothing when a bounded peak breaks the bound or d
// breaks a machine limit.
std::optional<double> dense_objective(const StrategyContext& c, bool minimise_motion, double bound,
                                      const Durations& d) {
  std::vector<double> limits(static_cast<std::size_t>(c.space.limit_count()));
  if (!limits.empty()) c.space.limit_constraints(d.data(), limits.data(), nullptr, kSegments);
  for (double g : limits) {
    if (g > time_domain_options().constraint_tolerance) return std::nullopt;
  }
  const double T = c.format.motion_time;
  const double rest = c.options.rest_time;
  // The bound on the prediction the plan is verified by (as the exchange's last check).
  if (constrained_value(c, minimise_motion, d) > bound * (1.0 + kDenseTolerance)) {
    return std::nullopt;
  }
  double value = 0.0;
  for (const SloshingModel& m : c.sample_models) {
    NonlinearSensitivity sens(m, c.format.stroke, rest, sensitivity_options());
    sens.compute(d.data(), INFINITY, false);
    value = std::max(value, minimise_motion ? sens.window_peak(0.0, T).value
                                            : sens.window_peak(T + 1e-12, T + rest).value);
  }
  return value / c.eta_ref;
}

// time_domain from starts that keep the context's machine limits.
StrategyOutcome solve_from(const StrategyContext& c, const std::vector<Durations>& starts) {
  const bool motion = c.options.objective == TimeDomainObjective::kMotion;
  const double bound = motion ? c.options.eta_rest_max : c.eta_motion_max;
  StrategyOutcome o;
  run_bounded(c, motion, bound, starts, &o);
  if (o.status != SolveStatus::kInfeasible) {
    // A continuation never returns worse than its warm start: the exchange rounds resolve the
    // objective to about kObjectiveTolerance and their path differs from the one that found the
    // warm start, so from an optimum they can end a few 1e-6 above it.
    // (Not for robust plans: their bound also holds on check models the samples do not carry.)
    if (c.space.warm_start && !c.robust() && !starts.empty() && starts.front() != o.durations) {
      const std::optional<double> warm = dense_objective(c, motion, bound, starts.front());
      if (warm && *warm <= o.objective) {
        o.durations = starts.front();
        o.objective = *warm;
      }
    }
    return o;
  }
  return least_infeasible(c, motion, bound, starts, std::move(o));
}

}  // namespace

NlpOptions time_domain_options() {
  NlpOptions o;
  o.tolerance = 1e-9;             // of eta / eta_ref: far below a micrometre
  o.constraint_tolerance = 1e-9;  // ditto
  o.max_iterations = 400;
  return o;
}

StrategyOutcome solve_time_domain(const StrategyContext& c, const std::vector<Durations>& seeds) {
  // The uniform law; with a warm start, the warm start and then the uniform law.
  std::vector<Durations> starts = c.space.starts(0);
  if (!c.space.warm_start) starts.resize(1);
  for (const Durations& d : seeds) {
    if (std::find(starts.begin(), starts.end(), d) == starts.end()) starts.push_back(d);
  }
  // The machine limits are hard constraints of every phase, and SLSQP from a start outside them
  // can end outside them: every start is first moved onto the set they admit.
  AdmissibleStarts admissible = admissible_starts(c, starts);
  if (!admissible.relaxed) return solve_from(c, admissible.starts);
  // A limit no law reaches: the law keeps its least reachable value (and every reachable limit);
  // the verification then names that limit.
  StrategyContext raised = c;
  raised.space.limits = admissible.limits;
  return solve_from(raised, admissible.starts);
}

}  // namespace slosh::detail
