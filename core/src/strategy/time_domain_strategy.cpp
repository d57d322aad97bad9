// time_domain: the peaks of the nonlinear model's accurate response as objective and constraints
// (thesis sec. 3.4.3, epigraph form), with exact gradients from the dual-number integrator.

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "response/nonlinear_sensitivity.hpp"
#include "slosh/core/response/response.hpp"
#include "strategy/strategies.hpp"
#include "text.hpp"

namespace slosh::detail {

namespace {

/// Samples per period of mode 1 at which |eta| is bounded to start with [-]. Between samples a
/// sinusoid can exceed them by 1 - cos(pi / 32) = 0.5 %; the exchange rounds close that gap.
constexpr double kSamplesPerPeriod{32.0};
/// Windows per period of mode 1 of the dense check after each solve [-].
constexpr double kCheckWindowsPerPeriod{4.0};
/// Exchange rounds: dense check, add the peak times that exceed their bound, re-solve.
constexpr int kExchangeRounds{8};
/// Relative excess over a bound the dense check tolerates [-].
constexpr double kDenseTolerance{1e-7};
/// Relative excess of a dense peak over the epigraph variable that adds a sample [-].
constexpr double kObjectiveTolerance{1e-6};

NlpOptions time_domain_options() {
  NlpOptions o;
  o.tolerance = 1e-9;             // of eta / eta_ref: far below a micrometre
  o.constraint_tolerance = 1e-9;  // ditto
  o.max_iterations = 400;
  return o;
}

// Times at which |eta| is constrained, sorted; `motion[k]` tells the phase of t[k].
struct Samples {
  std::vector<double> t;
  std::vector<char> motion;

  void add(double time, bool in_motion) {
    auto it = std::lower_bound(t.begin(), t.end(), time);
    if (it != t.end() && std::abs(*it - time) < 1e-12) return;
    const auto k = it - t.begin();
    t.insert(it, time);
    motion.insert(motion.begin() + k, static_cast<char>(in_motion));
  }
};

// |eta| at the samples for the last evaluated durations, shared by the objective and constraint
// callbacks of one problem (the solvers call both at the same point).
class Workspace {
 public:
  Workspace(const StrategyContext& c, Samples samples)
      : sens_(c.model, c.format.stroke, c.options.rest_time),
        eta_ref_(c.eta_ref),
        samples_(std::move(samples)) {}

  [[nodiscard]] const Samples& samples() const { return samples_; }
  [[nodiscard]] const std::vector<double>& values() const { return values_; }
  [[nodiscard]] const std::vector<std::array<double, kSegments>>& gradients() const {
    return gradients_;
  }

  // Evaluates at x (scaled by eta_ref) unless x is the last point.
  void at(const double* x) {
    if (valid_ && std::equal(x, x + kSegments, last_.begin())) return;
    sens_.compute(x);
    sens_.abs_eta_at(samples_.t, &values_, &gradients_);
    for (double& v : values_) v /= eta_ref_;
    for (auto& g : gradients_) {
      for (double& gi : g) gi /= eta_ref_;
    }
    std::copy(x, x + kSegments, last_.begin());
    valid_ = true;
  }

  NonlinearSensitivity& sensitivity() { return sens_; }

 private:
  NonlinearSensitivity sens_;
  double eta_ref_;
  Samples samples_;
  std::vector<double> values_;
  std::vector<std::array<double, kSegments>> gradients_;
  std::array<double, kSegments> last_{};
  bool valid_{false};
};

// min z s.t. |eta(t_k)| / eta_ref <= z at the samples of the minimised phase and
// |eta(t_k)| / eta_ref <= bound / eta_ref at those of the other phase (none without a bound).
MultiStartResult solve_epigraph(const StrategyContext& c, bool minimise_motion,
                                std::optional<double> bound, const Samples& samples,
                                const std::vector<Durations>& starts) {
  auto ws = std::make_shared<Workspace>(c, samples);
  std::vector<std::size_t> rows;  // samples that carry a constraint
  for (std::size_t k = 0; k < samples.t.size(); ++k) {
    if (static_cast<bool>(samples.motion[k]) == minimise_motion || bound) rows.push_back(k);
  }
  const int n = kSegments + 1;
  NlpProblem p = c.space.problem(1);
  const double scaled_bound = bound ? *bound / c.eta_ref : 0.0;
  const int m = static_cast<int>(rows.size());
  const int limits = c.space.limit_count();
  p.inequality_count = m + limits;
  const DurationSpace* space = &c.space;
  p.inequalities = [ws, rows, minimise_motion, scaled_bound, m, limits, n, space](
                       const double* x, double* g, double* jac) {
    ws->at(x);
    const auto& values = ws->values();
    const auto& grads = ws->gradients();
    const auto& motion = ws->samples().motion;
    for (int r = 0; r < m; ++r) {
      const std::size_t k = rows[static_cast<std::size_t>(r)];
      const bool free = static_cast<bool>(motion[k]) == minimise_motion;
      g[r] = values[k] - (free ? x[kSegments] : scaled_bound);
      if (jac != nullptr) {
        double* row = jac + static_cast<std::ptrdiff_t>(r) * n;
        std::copy(grads[k].begin(), grads[k].end(), row);
        row[kSegments] = free ? -1.0 : 0.0;
      }
    }
    if (limits > 0) {
      double* jrow = jac == nullptr ? nullptr : jac + static_cast<std::ptrdiff_t>(m) * n;
      if (jrow != nullptr) std::fill(jrow, jrow + static_cast<std::ptrdiff_t>(limits) * n, 0.0);
      space->limit_constraints(x, g + m, jrow, n);
    }
  };
  std::vector<std::vector<double>> x0 = as_vectors(starts);
  for (auto& x : x0) {
    ws->at(x.data());
    double z = 0.0;
    for (std::size_t k = 0; k < samples.t.size(); ++k) {
      if (static_cast<bool>(samples.motion[k]) == minimise_motion) {
        z = std::max(z, ws->values()[k]);
      }
    }
    x.push_back(z);
  }
  return multi_start(p, x0, c, time_domain_options());
}

// The epigraph problem with its semi-infinite constraint closed by exchange: after each solve the
// dense accurate response is checked window by window, and every peak above its bound becomes a
// new sample for the next solve (started from the current point).
MultiStartResult solve_phase(const StrategyContext& c, bool minimise_motion,
                             std::optional<double> bound, std::vector<Durations> starts,
                             double* bound_excess) {
  const double T = c.format.motion_time;
  const double rest = c.options.rest_time;
  const double period = 2.0 * std::numbers::pi / c.model.omega1();
  Samples samples;
  const int km = std::max(2, static_cast<int>(std::ceil(T / period * kSamplesPerPeriod)));
  const int kr = std::max(2, static_cast<int>(std::ceil(rest / period * kSamplesPerPeriod)));
  for (int k = 1; k <= km; ++k) samples.add(T * k / km, true);
  for (int k = 1; k <= kr; ++k) samples.add(T + rest * k / kr, false);
  const int kw = std::max(1, static_cast<int>(std::ceil(T / period * kCheckWindowsPerPeriod)));
  const int kwr = std::max(1, static_cast<int>(std::ceil(rest / period * kCheckWindowsPerPeriod)));

  // Between samples the peaks move with the durations, so from the second round on the bound
  // given to the solver is tightened by twice the excess the dense check still finds.
  MultiStartResult total;
  double margin = 0.0;
  *bound_excess = 0.0;
  for (int round = 0; round < kExchangeRounds; ++round) {
    std::optional<double> solver_bound;
    if (bound) solver_bound = *bound * (1.0 - margin);
    MultiStartResult r = solve_epigraph(c, minimise_motion, solver_bound, samples, starts);
    r.evaluations += total.evaluations;
    r.starts += total.starts;
    total = std::move(r);
    if (total.best.x.empty() || total.timed_out) break;
    // Dense check of the returned point.
    NonlinearSensitivity sens(c.model, c.format.stroke, rest);
    sens.compute(total.best.x.data());
    const double z = total.best.x[kSegments] * c.eta_ref;
    bool added = false;
    double excess = 0.0;
    for (int w = 0; w < kw + kwr; ++w) {
      const bool in_motion = w < kw;
      const double a = in_motion ? T * w / kw : T + rest * (w - kw) / kwr;
      const double b = in_motion ? T * (w + 1) / kw : T + rest * (w + 1 - kw) / kwr;
      const WindowPeak peak = sens.window_peak(in_motion ? a : std::max(a, T + 1e-12), b);
      const bool free = in_motion == minimise_motion;
      if (!free && !bound) continue;
      if (free) {
        // The objective's own peaks: sampled for accuracy (the reported eta is the dense one).
        if (peak.value > z * (1.0 + kObjectiveTolerance)) {
          samples.add(peak.time, peak.time <= T);
          added = true;
        }
      } else if (peak.value > *bound * (1.0 + kDenseTolerance)) {
        samples.add(peak.time, peak.time <= T);
        added = true;
        excess = std::max(excess, peak.value / *bound - 1.0);
      }
    }
    *bound_excess = excess;
    if (!added) break;
    if (round >= 1) margin += 2.0 * excess;
    Durations d;
    std::copy(total.best.x.begin(), total.best.x.begin() + kSegments, d.begin());
    starts = {d};
  }
  return total;
}

}  // namespace

StrategyOutcome solve_time_domain(const StrategyContext& c, const std::vector<Durations>& seeds) {
  const bool motion = c.options.objective == TimeDomainObjective::kMotion;
  const double bound = motion ? c.options.eta_rest_max : c.eta_motion_max;
  std::vector<Durations> starts{c.space.starts(0).front()};
  for (const Durations& d : seeds) {
    if (std::find(starts.begin(), starts.end(), d) == starts.end()) starts.push_back(d);
  }
  // The bounded phase (dense excess within kDenseTolerance counts as met).
  auto bounded = [&](const std::vector<Durations>& from, StrategyOutcome* out) {
    double excess = 0.0;
    const MultiStartResult m = solve_phase(c, motion, bound, from, &excess);
    const int evaluations = out->evaluations + m.evaluations;
    const int solved = out->starts + m.starts;
    *out = outcome_from(m, c);
    out->evaluations = evaluations;
    out->starts = solved;
    if ((out->status == SolveStatus::kOptimal || out->status == SolveStatus::kAcceptable) &&
        excess > kDenseTolerance) {
      // The exchange rounds ran out before the dense check passed: not met.
      out->status = SolveStatus::kInfeasible;
    }
  };
  StrategyOutcome o;
  bounded(starts, &o);
  if (o.status != SolveStatus::kInfeasible) return o;
  // Least infeasible phase: the constrained quantity alone minimised from the same starts (the
  // min of eta_rest, or of eta_motion for objective kRest). When it meets the bound, the bounded
  // phase runs again from it (a feasible start); failing that, it is itself a law that meets the
  // bound.
  double unused = 0.0;
  const MultiStartResult best = solve_phase(c, !motion, std::nullopt, starts, &unused);
  const int evaluations = o.evaluations + best.evaluations;
  const int solved = o.starts + best.starts;
  const Durations infeasible_point = o.durations;
  o.evaluations = evaluations;
  o.starts = solved;
  if (best.best.x.empty() || !best.feasible) {
    o.status = c.deadline.expired() ? SolveStatus::kTimeLimit : SolveStatus::kInfeasible;
    o.detail = "the machine limits leave no admissible law";
    return o;
  }
  const Durations least = c.space.polish(best.best.x.data());
  // The dense value of the constrained quantity at a point, and the best of the starts.
  const SloshingModel& model = c.model;
  auto dense = [&](const Durations& d) {
    const SloshPeaks p =
        NonlinearResponse(model, SevenSegmentLaw(d, c.format.stroke).law(), c.options.rest_time)
            .peaks();
    return motion ? p.rest.value : p.motion.value;
  };
  Durations chosen = least;
  double reached = dense(least);
  std::vector<Durations> others = starts;
  others.push_back(infeasible_point);
  for (const Durations& d : others) {
    const double v = dense(d);
    if (v < reached) {
      reached = v;
      chosen = d;
    }
  }
  if (reached <= bound * (1.0 + kDenseTolerance)) {
    StrategyOutcome again;
    again.evaluations = o.evaluations;
    again.starts = o.starts;
    bounded({chosen}, &again);
    if (again.status != SolveStatus::kInfeasible) return again;
    o.evaluations = again.evaluations;
    o.starts = again.starts;
    // The least infeasible point meets the bound: a law that keeps the promise, though its
    // objective is not minimised.
    o.status = SolveStatus::kAcceptable;
    o.durations = chosen;
    o.objective = best.best.objective;
    o.detail = std::string(motion ? "eta_rest" : "eta_motion") + " <= " + sig3(bound * 1e3) +
               " mm met (" + sig3(reached * 1e3) + " mm), but the " +
               (motion ? "eta_motion" : "eta_rest") + " objective was not minimised";
    return o;
  }
  o.status = SolveStatus::kInfeasible;
  o.durations = chosen;
  o.detail = std::string(motion ? "eta_rest" : "eta_motion") + " <= " + sig3(bound * 1e3) +
             " mm is not reachable in " + sig3(c.format.motion_time) + " s: the best is " +
             sig3(reached * 1e3) + " mm; lengthen the motion or relax the limit";
  return o;
}

}  // namespace slosh::detail
