// notch, multi_notch and min_jerk_band: objectives and constraints on the closed-form spectrum
// with its exact gradient (SPEC §4-§5).

#include <algorithm>
#include <cmath>
#include <memory>

#include "slosh/core/spectrum.hpp"
#include "strategies.hpp"
#include "text.hpp"

namespace slosh::detail {

namespace {

/// Depth of an exact notch: |Re X|, |Im X| <= kNotchDepth |X_uniform(w1)| [-] (-120 dB).
constexpr double kNotchDepth{1e-6};
/// Random starts of the spectral strategies (after the uniform law and 4 symmetric families).
constexpr int kSpectralRandomStarts{5};
/// Refinement of the band check after a min_jerk_band solve: points per solver interval.
constexpr int kBandCheckRefinement{16};
/// Exchange rounds of min_jerk_band (points added where the fine check finds a violation).
constexpr int kBandExchangeRounds{6};
/// Points inside the band limit from which min_jerk_band minimises the jerk [-].
constexpr int kBandFeasibleStarts{1};
/// Relative excess of |X| over tol_rel |X_uniform(w1)| the fine check accepts [-].
constexpr double kBandTolerance{1e-6};

NlpOptions spectral_options() {
  NlpOptions o;
  o.tolerance = 1e-10;
  o.constraint_tolerance = 1e-9;  // constraints are relative to their bounds
  o.max_iterations = 400;
  return o;
}

// Appends the limit inequalities after `first` rows of a problem over 7 + extra variables.
void add_limits(NlpProblem& p, const StrategyContext& c, int first,
                std::function<void(const double*, double*, double*)> head) {
  const int limits = c.space.limit_count();
  const int n = p.size();
  p.inequality_count = first + limits;
  const DurationSpace* space = &c.space;
  p.inequalities = [head = std::move(head), first, limits, n, space](const double* x, double* g,
                                                                     double* jac) {
    if (first > 0) head(x, g, jac);
    if (limits > 0) {
      double* jrow = jac == nullptr ? nullptr : jac + static_cast<std::ptrdiff_t>(first) * n;
      if (jrow != nullptr) std::fill(jrow, jrow + static_cast<std::ptrdiff_t>(limits) * n, 0.0);
      space->limit_constraints(x, g + first, jrow, n);
    }
  };
}

// sum_i w_i |X(omega_i)|^2 / x_ref^2 and its gradient.
double weighted_power(const double* x, double* grad, const StrategyContext& c,
                      const std::vector<double>& omegas, const std::vector<double>& weights) {
  Durations d;
  std::copy(x, x + kSegments, d.begin());
  const double scale = 1.0 / (c.x_ref * c.x_ref);
  double f = 0.0;
  if (grad != nullptr) std::fill(grad, grad + kSegments, 0.0);
  for (std::size_t k = 0; k < omegas.size(); ++k) {
    if (weights[k] == 0.0) continue;
    const auto pg = spectrum_power_gradient(d, c.format.stroke, omegas[k]);
    f += weights[k] * scale * pg.power;
    if (grad != nullptr) {
      for (std::size_t i = 0; i < kSegments; ++i) grad[i] += weights[k] * scale * pg.gradient[i];
    }
  }
  return f;
}

// Minimise a weighted spectral power over the starts (limits as constraints).
MultiStartResult minimise_power(const StrategyContext& c, const std::vector<double>& omegas,
                                const std::vector<double>& weights) {
  NlpProblem p = c.space.problem();
  p.objective = [&c, omegas, weights](const double* x, double* grad) {
    return weighted_power(x, grad, c, omegas, weights);
  };
  add_limits(p, c, 0, nullptr);
  return multi_start(p, as_vectors(c.space.starts(kSpectralRandomStarts)), c, spectral_options());
}

double jerk_objective(const double* x, double* grad, const StrategyContext& c) {
  const double f = jerk_integral(x, c.format.stroke, grad) / c.jerk_ref;
  if (grad != nullptr) {
    for (std::size_t i = 0; i < kSegments; ++i) grad[i] /= c.jerk_ref;
  }
  return f;
}

}  // namespace

std::vector<double> band_frequencies(double omega1, double band, int count) {
  std::vector<double> w(static_cast<std::size_t>(count));
  const double lo = (1.0 - band) * omega1;
  const double hi = (1.0 + band) * omega1;
  for (int k = 0; k < count; ++k) {
    w[static_cast<std::size_t>(k)] = count == 1 ? omega1 : lo + (hi - lo) * k / (count - 1);
  }
  return w;
}

StrategyOutcome solve_notch(const StrategyContext& c) {
  const double w1 = c.model.omega1();
  // Among the exact zeros of X(w1) (a 4-dimensional manifold of the 6 free durations), the one
  // with the least jerk integral: min int j^2 dt s.t. |Re X|, |Im X| <= kNotchDepth x_ref.
  NlpProblem p = c.space.problem();
  p.objective = [&c](const double* x, double* grad) { return jerk_objective(x, grad, c); };
  const double stroke = c.format.stroke;
  const double inv = 1.0 / c.x_ref;
  add_limits(p, c, 4, [stroke, w1, inv](const double* x, double* g, double* jac) {
    Durations d;
    std::copy(x, x + kSegments, d.begin());
    const SpectrumGradient sg = spectrum_gradient(d, stroke, w1);
    const double re = sg.X.real() * inv, im = sg.X.imag() * inv;
    g[0] = re - kNotchDepth;
    g[1] = -re - kNotchDepth;
    g[2] = im - kNotchDepth;
    g[3] = -im - kNotchDepth;
    if (jac != nullptr) {
      for (std::size_t i = 0; i < kSegments; ++i) {
        jac[0 * kSegments + i] = sg.dX[i].real() * inv;
        jac[1 * kSegments + i] = -sg.dX[i].real() * inv;
        jac[2 * kSegments + i] = sg.dX[i].imag() * inv;
        jac[3 * kSegments + i] = -sg.dX[i].imag() * inv;
      }
    }
  });
  MultiStartResult m =
      multi_start(p, as_vectors(c.space.starts(kSpectralRandomStarts)), c, spectral_options());
  if (m.feasible) {
    StrategyOutcome o = outcome_from(m, c);
    o.detail =
        "exact notch at f1 (|X(w1)| <= 1e-6 of the uniform law's), the one with the least "
        "jerk integral among the zeros (" +
        percent(o.objective) + " of the uniform law's)";
    return o;
  }
  // No zero reachable within the bounds and limits: the deepest notch instead.
  MultiStartResult deepest = minimise_power(c, {w1}, {1.0});
  deepest.evaluations += m.evaluations;
  deepest.starts += m.starts;
  StrategyOutcome o = outcome_from(deepest, c);
  if (o.status != SolveStatus::kInfeasible) {
    o.detail =
        "no exact zero of X(w1) is reachable within the bounds and limits; the deepest "
        "notch leaves |X(w1)| at " +
        percent(std::sqrt(o.objective)) + " of the uniform law's";
  }
  return o;
}

StrategyOutcome solve_multi_notch(const StrategyContext& c) {
  const double w1 = c.model.omega1();
  const double p_notch = c.options.p_notch;
  const std::vector<double> omegas{(1.0 - p_notch) * w1, w1, (1.0 + p_notch) * w1};
  const std::vector<double> weights(c.options.weights.begin(), c.options.weights.end());
  const MultiStartResult m = minimise_power(c, omegas, weights);
  StrategyOutcome o = outcome_from(m, c);
  if (o.status != SolveStatus::kInfeasible) {
    Durations d = o.durations;
    std::string parts;
    for (double w : omegas) {
      if (!parts.empty()) parts += ", ";
      parts += percent(std::abs(seven_segment_spectrum(d, c.format.stroke, w)) / c.x_ref);
    }
    o.detail = "|X| at (1-p) f1, f1, (1+p) f1 = " + parts + " of the uniform law's |X(f1)|";
  }
  return o;
}

StrategyOutcome solve_min_jerk_band(const StrategyContext& c) {
  const double w1 = c.model.omega1();
  const PlanOptions& opt = c.options;
  std::vector<double> omegas = band_frequencies(w1, opt.band, opt.n_band);
  const double tol = opt.tol_rel;
  const double stroke = c.format.stroke;
  // Band constraints relative to their bound: |X(w_k)|^2 / (tol x_ref)^2 - 1 <= 0.
  const double scale = 1.0 / (c.x_ref * c.x_ref * tol * tol);
  const std::vector<double> fine =
      band_frequencies(w1, opt.band, (opt.n_band - 1) * kBandCheckRefinement + 1);
  // The largest |X| / x_ref over the continuous band: the fine grid, then golden section around
  // every local maximum of it.
  struct BandMax {
    double ratio{};
    double omega{};
  };
  auto band_max = [&](const Durations& d) {
    std::vector<double> v(fine.size());
    for (std::size_t k = 0; k < fine.size(); ++k) {
      v[k] = std::abs(seven_segment_spectrum(d, stroke, fine[k])) / c.x_ref;
    }
    BandMax best{v[0], fine[0]};
    for (std::size_t k = 0; k < fine.size(); ++k) {
      if (v[k] > best.ratio) best = {v[k], fine[k]};
      const bool interior_max =
          k > 0 && k + 1 < fine.size() && v[k] >= v[k - 1] && v[k] >= v[k + 1];
      if (!interior_max) continue;
      double a = fine[k - 1], b = fine[k + 1];
      const double g = 0.5 * (std::sqrt(5.0) - 1.0);
      auto f = [&](double w) { return std::abs(seven_segment_spectrum(d, stroke, w)) / c.x_ref; };
      double x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = f(x1), f2 = f(x2);
      for (int it = 0; it < 60 && b - a > 1e-12 * w1; ++it) {
        if (f1 > f2) {
          b = x2, x2 = x1, f2 = f1, x1 = b - g * (b - a), f1 = f(x1);
        } else {
          a = x1, x1 = x2, f1 = f2, x2 = a + g * (b - a), f2 = f(x2);
        }
      }
      if (std::max(f1, f2) > best.ratio) best = f1 > f2 ? BandMax{f1, x1} : BandMax{f2, x2};
    }
    return best;
  };
  auto band_ratio = [&](const Durations& d) { return band_max(d).ratio; };
  // g_k = |X(w_k)|^2 scale - z (epigraph, phase 1) or - limit (phase 2).
  auto band_rows = [stroke, scale](std::vector<double> w, bool epigraph, double limit = 1.0) {
    auto powers = std::make_shared<std::vector<SpectrumPowerGradient>>();
    const int n = kSegments + (epigraph ? 1 : 0);
    return [w = std::move(w), stroke, scale, epigraph, limit, n, powers](const double* x, double* g,
                                                                         double* jac) {
      Durations d;
      std::copy(x, x + kSegments, d.begin());
      spectrum_power_gradients(d, stroke, w, powers.get());
      for (std::size_t k = 0; k < w.size(); ++k) {
        const auto& pg = (*powers)[k];
        g[k] = pg.power * scale - (epigraph ? x[kSegments] : limit);
        if (jac != nullptr) {
          for (std::size_t i = 0; i < kSegments; ++i) jac[k * n + i] = pg.gradient[i] * scale;
          if (epigraph) jac[k * n + kSegments] = -1.0;
        }
      }
    };
  };
  const int m0 = static_cast<int>(omegas.size());
  StrategyOutcome o;
  o.solver = solver_name(c);

  // Phase 1, from every start: min z s.t. the band powers <= z (feasible from anywhere, unlike
  // the band constraint itself, on which SLSQP stalls from most infeasible starts). It stops at
  // the first point inside the band limit; its minimum is the best band reachable.
  NlpProblem p1 = c.space.problem(1, 1e20);  // z is (|X| / (tol x_ref))^2: large for small tol
  add_limits(p1, c, m0, band_rows(omegas, true));
  std::vector<std::vector<double>> phase2_starts;
  // Phase 1a, cheap: the band energy on 5 points (unconstrained but for the limits) from each
  // start, until kBandFeasibleStarts points inside the band limit are found.
  {
    NlpProblem pe = c.space.problem();
    const std::vector<double> probe = band_frequencies(w1, opt.band, 5);
    const std::vector<double> ones(probe.size(), 1.0);
    pe.objective = [&c, probe, ones](const double* x, double* grad) {
      return weighted_power(x, grad, c, probe, ones);
    };
    add_limits(pe, c, 0, nullptr);
    for (const Durations& start : c.space.starts(kSpectralRandomStarts)) {
      const MultiStartResult r =
          multi_start(pe, {std::vector<double>(start.begin(), start.end())}, c, spectral_options());
      o.evaluations += r.evaluations;
      o.starts += r.starts;
      if (r.timed_out) break;
      if (!r.feasible || r.best.x.empty()) continue;
      if (band_ratio(c.space.polish(r.best.x.data())) <= tol) {
        phase2_starts.push_back(r.best.x);
        if (static_cast<int>(phase2_starts.size()) == kBandFeasibleStarts) break;
      }
    }
  }
  // Phase 1b, when 1a found nothing: min z s.t. the band powers <= z (feasible from anywhere,
  // unlike the band constraint itself, on which SLSQP stalls from most infeasible starts). It
  // stops at the first point inside the band limit; its minimum is the best band reachable.
  MultiStartResult best_band;
  NlpOptions o1 = spectral_options();
  o1.stop_value = 0.5;  // half the band limit in power: well inside
  bool have_band = false;
  MultiStartResult least_infeasible;
  for (const Durations& start : c.space.starts(kSpectralRandomStarts)) {
    if (!phase2_starts.empty()) break;
    std::vector<double> x(start.begin(), start.end());
    x.push_back(std::pow(band_ratio(start) / tol, 2) * 1.01);
    const MultiStartResult r = multi_start(p1, {x}, c, o1);
    o.evaluations += r.evaluations;
    o.starts += r.starts;
    if (r.timed_out) break;
    if (!r.feasible && !r.best.x.empty() &&
        (least_infeasible.best.x.empty() ||
         r.best.max_violation < least_infeasible.best.max_violation)) {
      least_infeasible = r;
    }
    if (!r.feasible || r.best.x.empty()) continue;
    if (!have_band || r.best.objective < best_band.best.objective) {
      best_band = r;
      have_band = true;
    }
    if (r.best.objective <= 1.0) phase2_starts.emplace_back(r.best.x.begin(), r.best.x.end() - 1);
  }
  if (phase2_starts.empty()) {
    if (c.deadline.expired()) {
      o.status = SolveStatus::kTimeLimit;
      o.durations = c.space.starts(0).front();
      return o;
    }
    if (!have_band) {
      // Not even the band-free problem is feasible: the machine limits cannot hold.
      o.status = least_infeasible.best.x.empty() ? SolveStatus::kFailed : SolveStatus::kInfeasible;
      o.durations = least_infeasible.best.x.empty()
                        ? c.space.starts(0).front()
                        : c.space.polish(least_infeasible.best.x.data());
      return o;
    }
    // Not reachable: polish the best band to its minimum and report it.
    o1.stop_value.reset();
    const MultiStartResult r = multi_start(p1, {best_band.best.x}, c, o1);
    o.evaluations += r.evaluations;
    o.starts += r.starts;
    const MultiStartResult& b = r.feasible ? r : best_band;
    o.status = SolveStatus::kInfeasible;
    o.durations = c.space.polish(b.best.x.data());
    o.objective = b.best.objective;
    o.detail = "the band limit |X| <= " + percent(tol) +
               " of the uniform law's |X(f1)| is not reachable in " + sig3(c.format.motion_time) +
               " s: the best is " + percent(band_ratio(o.durations)) +
               "; raise tol_rel, narrow the band or lengthen the motion";
    return o;
  }

  // Phase 2: min jerk integral inside the band limit, from the phase-1 points; the constraint is
  // semi-infinite, so the band is checked 16x finer than the solver saw it and the worst
  // frequency is added for a re-solve from the current point until the check passes.
  // Between the solver's frequencies the maximum moves with the durations, so from the second
  // round on the bound is tightened by twice the excess still found.
  std::vector<std::vector<double>> starts = phase2_starts;
  double margin = 0.0;
  double excess = 0.0;
  for (int round = 0; round < kBandExchangeRounds; ++round) {
    NlpProblem p = c.space.problem();
    p.objective = [&c](const double* x, double* grad) { return jerk_objective(x, grad, c); };
    const double limit = (1.0 - margin) * (1.0 - margin);
    add_limits(p, c, static_cast<int>(omegas.size()), band_rows(omegas, false, limit));
    MultiStartResult r = multi_start(p, starts, c, spectral_options());
    // SLSQP sometimes stops short of the optimum (line search on round-off); one restart from
    // where it stopped finishes the job.
    if (r.feasible && !r.timed_out) {
      MultiStartResult again = multi_start(p, {r.best.x}, c, spectral_options());
      r.evaluations += again.evaluations;
      r.starts += again.starts;
      if (again.feasible && again.best.objective < r.best.objective) {
        again.evaluations = r.evaluations;
        again.starts = r.starts;
        r = std::move(again);
      }
    }
    const int evaluations = o.evaluations + r.evaluations;
    const int solved = o.starts + r.starts;
    o = outcome_from(r, c);
    o.evaluations = evaluations;
    o.starts = solved;
    if (o.status != SolveStatus::kOptimal && o.status != SolveStatus::kAcceptable) break;
    const BandMax worst = band_max(o.durations);
    excess = worst.ratio / tol - 1.0;
    if (excess <= kBandTolerance) break;
    omegas.push_back(worst.omega);
    if (round >= 1) margin += 2.0 * excess;
    starts = {std::vector<double>(o.durations.begin(), o.durations.end())};
  }
  if (o.status == SolveStatus::kOptimal && excess > kBandTolerance) {
    o.status = SolveStatus::kAcceptable;  // met to within `excess`, reported in the detail
  }
  if (o.status == SolveStatus::kOptimal || o.status == SolveStatus::kAcceptable) {
    o.detail = "|X| <= " + percent(band_ratio(o.durations)) +
               " of the uniform law's |X(f1)| over the whole band (limit " + percent(tol) +
               "), jerk integral " + percent(o.objective) + " of the uniform law's";
  }
  return o;
}

}  // namespace slosh::detail
