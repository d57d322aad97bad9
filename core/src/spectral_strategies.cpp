// notch, multi_notch and min_jerk_band: objectives and constraints on the closed-form spectrum
// with its exact gradient (SPEC §4-§5).

#include <algorithm>
#include <cmath>

#include "slosh/core/spectrum.hpp"
#include "strategies.hpp"
#include "text.hpp"

namespace slosh::detail {

namespace {

/// Depth of an exact notch: |Re X|, |Im X| <= kNotchDepth |X_uniform(w1)| [-] (-120 dB).
constexpr double kNotchDepth{1e-6};
/// Random starts of the spectral strategies (after the uniform law and 4 symmetric families).
constexpr int kSpectralRandomStarts{7};
/// Refinement of the band check after a min_jerk_band solve: points per solver interval.
constexpr int kBandCheckRefinement{16};
/// Exchange rounds of min_jerk_band (points added where the fine check finds a violation).
constexpr int kBandExchangeRounds{4};

NlpOptions spectral_options() {
  NlpOptions o;
  o.tolerance = 1e-10;
  o.constraint_tolerance = 1e-10;
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

StrategyOutcome outcome_from(const MultiStartResult& m, const StrategyContext& c) {
  StrategyOutcome o;
  o.evaluations = m.evaluations;
  o.starts = m.starts;
  o.solver = solver_name(c);
  if (m.best.x.empty()) {
    o.status = m.timed_out ? SolveStatus::kTimeLimit : SolveStatus::kFailed;
    o.durations = c.space.starts(0).front();
    return o;
  }
  o.durations = c.space.polish(m.best.x.data());
  o.objective = m.best.objective;
  if (!m.feasible) {
    o.status = SolveStatus::kInfeasible;
  } else if (m.timed_out) {
    o.status = SolveStatus::kTimeLimit;
  } else {
    o.status = m.best.status == SolveStatus::kAcceptable ? SolveStatus::kAcceptable
                                                         : SolveStatus::kOptimal;
  }
  return o;
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
    o.detail = "exact notch at f1 (|X(w1)| <= 1e-6 of the uniform law's), the one with the least "
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
    o.detail = "no exact zero of X(w1) is reachable within the bounds and limits; the deepest "
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
  const double tol2 = opt.tol_rel * opt.tol_rel;
  const double stroke = c.format.stroke;
  const double scale = 1.0 / (c.x_ref * c.x_ref);
  const std::vector<double> fine =
      band_frequencies(w1, opt.band, (opt.n_band - 1) * kBandCheckRefinement + 1);
  auto band_ratio = [&](const Durations& d, std::size_t* worst) {
    double r = 0.0;
    for (std::size_t k = 0; k < fine.size(); ++k) {
      const double v = std::abs(seven_segment_spectrum(d, stroke, fine[k])) / c.x_ref;
      if (v > r) {
        r = v;
        if (worst != nullptr) *worst = k;
      }
    }
    return r;
  };

  std::vector<std::vector<double>> starts = as_vectors(c.space.starts(kSpectralRandomStarts));
  StrategyOutcome o;
  int evaluations = 0, solved = 0;
  for (int round = 0; round < kBandExchangeRounds; ++round) {
    NlpProblem p = c.space.problem();
    p.objective = [&c](const double* x, double* grad) { return jerk_objective(x, grad, c); };
    const int m = static_cast<int>(omegas.size());
    add_limits(p, c, m, [omegas, stroke, scale, tol2](const double* x, double* g, double* jac) {
      Durations d;
      std::copy(x, x + kSegments, d.begin());
      for (std::size_t k = 0; k < omegas.size(); ++k) {
        const auto pg = spectrum_power_gradient(d, stroke, omegas[k]);
        g[k] = pg.power * scale - tol2;
        if (jac != nullptr) {
          for (std::size_t i = 0; i < kSegments; ++i) {
            jac[k * kSegments + i] = pg.gradient[i] * scale;
          }
        }
      }
    });
    const MultiStartResult r = multi_start(p, starts, c, spectral_options());
    evaluations += r.evaluations;
    solved += r.starts;
    o = outcome_from(r, c);
    if (o.status == SolveStatus::kInfeasible || o.status == SolveStatus::kTimeLimit ||
        o.status == SolveStatus::kFailed) {
      break;
    }
    // Semi-infinite constraint: check the band 16x finer than the solver saw it; where it is
    // exceeded, add the worst frequency and re-solve from the current point.
    std::size_t worst = 0;
    const double ratio = band_ratio(o.durations, &worst);
    if (ratio <= opt.tol_rel * (1.0 + 1e-9)) break;
    omegas.push_back(fine[worst]);
    starts = {std::vector<double>(o.durations.begin(), o.durations.end())};
  }
  o.evaluations = evaluations;
  o.starts = solved;
  if (o.status == SolveStatus::kInfeasible) {
    // The best reachable band: min z s.t. |X(w_k)|^2 / x_ref^2 <= z.
    NlpProblem p = c.space.problem(1);
    p.objective = [](const double* x, double* grad) {
      if (grad != nullptr) {
        std::fill(grad, grad + kSegments, 0.0);
        grad[kSegments] = 1.0;
      }
      return x[kSegments];
    };
    const int m = static_cast<int>(omegas.size());
    add_limits(p, c, m, [omegas, stroke, scale](const double* x, double* g, double* jac) {
      Durations d;
      std::copy(x, x + kSegments, d.begin());
      for (std::size_t k = 0; k < omegas.size(); ++k) {
        const auto pg = spectrum_power_gradient(d, stroke, omegas[k]);
        g[k] = pg.power * scale - x[kSegments];
        if (jac != nullptr) {
          for (std::size_t i = 0; i < kSegments; ++i) {
            jac[k * (kSegments + 1) + i] = pg.gradient[i] * scale;
          }
          jac[k * (kSegments + 1) + kSegments] = -1.0;
        }
      }
    });
    std::vector<std::vector<double>> s = as_vectors(c.space.starts(kSpectralRandomStarts));
    for (auto& x : s) {
      Durations d;
      std::copy(x.begin(), x.end(), d.begin());
      const double r = band_ratio(d, nullptr);
      x.push_back(r * r);
    }
    const MultiStartResult best = multi_start(p, s, c, spectral_options());
    o.evaluations += best.evaluations;
    o.starts += best.starts;
    if (!best.best.x.empty() && best.feasible) {
      o.durations = c.space.polish(best.best.x.data());
      o.detail = "the band limit |X| <= " + percent(opt.tol_rel) +
                 " of the uniform law's |X(f1)| is not reachable in " +
                 sig3(c.format.motion_time) + " s: the best is " +
                 percent(band_ratio(o.durations, nullptr)) +
                 "; raise tol_rel, narrow the band or lengthen the motion";
    }
  } else if (o.status != SolveStatus::kFailed) {
    o.detail = "|X| <= " + percent(band_ratio(o.durations, nullptr)) +
               " of the uniform law's |X(f1)| over the whole band (limit " + percent(opt.tol_rel) +
               "), jerk integral " + percent(o.objective) + " of the uniform law's";
  }
  return o;
}

}  // namespace slosh::detail
