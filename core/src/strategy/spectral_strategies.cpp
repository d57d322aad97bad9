// notch, multi_notch and min_jerk_band: objectives and constraints on the closed-form spectrum
// with its exact gradient (SPEC §4-§5).

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "slosh/core/response/peak_finder.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "strategy/strategies.hpp"
#include "text.hpp"

namespace slosh::detail {

namespace {

/// Depth of an exact notch: |Re X|, |Im X| <= kNotchDepth X_ref [-] (-120 dB).
constexpr double kNotchDepth{1e-6};
/// Random starts of the spectral strategies (after the uniform law and 4 symmetric families).
constexpr int kSpectralRandomStarts{5};
/// Random starts of notch in a row that find no lower optimum after which it stops.
constexpr int kNotchPatience{2};
/// Random starts of multi_notch (after the uniform law and 4 symmetric families): its objective
/// has many basins on short moves (a 24-start reference found optima 4x lower than 10 starts).
constexpr int kMultiNotchRandomStarts{8};
/// multi_notch's StartPolicy::approach_basin [-]: most of its starts end in basins an earlier
/// start reached (the thesis format: 8 of 13, most of them 1000 times above the best), and SLSQP
/// spends their last third converging there. Measured (callgrind) with the mirrored optima: 0.03
/// saved the thesis plan 8 % of its instructions; 0.12 saves another 10 % (12.4 M -> 11.2 M,
/// BM_PlanFormats' 8 formats 9 % of the evaluations) and returns the same law as 0.03 to the
/// last bit on StartPolicy's first 1000 formats (SLOSH_PROPERTY_FORMATS=1000), where 0.15 lost
/// one best optimum; without the kPoorOptimum restriction one of the first 40 lost the best
/// optimum to its twin 2e-4 above it.
constexpr double kMultiNotchApproach{0.12};
/// A weighted spectral power (relative to X_ref^2) this low is an exact zero [-].
constexpr double kExactZero{1e-14};
/// Refinement of the band check after a min_jerk_band solve: points per solver interval.
constexpr int kBandCheckRefinement{16};
/// Exchange rounds of min_jerk_band (points added where the fine check finds a violation).
constexpr int kBandExchangeRounds{6};
/// Constraint violation (relative to the bounds) up to which a solver point is judged by the
/// verification rather than discarded [-].
constexpr double kSolverSlack{1e-6};
/// The same inside the exchange rounds, whose points the fine check judges anyway [-].
constexpr double kExchangeSlack{1e-3};
/// Random starts of min_jerk_band's screening (after the uniform law and 4 symmetric families).
constexpr int kBandRandomStarts{12};
/// Screening starts in a row without a lower screened optimum after which the random ones stop
/// (once a screened point exists). Over 380 seeded formats (the property tests' ranges, half with
/// random machine limits) every plan kept the jerk integral of all 18 screening starts to 1e-6,
/// with about half of the evaluations: the best screened basin is the band-free optimum's or a
/// symmetric family's, and the random starts mostly stall outside the band.
constexpr int kScreenPatience{2};
/// Band frequencies of min_jerk_band's screening solves (at most n_band) [-]. The screening only
/// ranks the starts (the finishing solves use all n_band and the exchange): 6 instead of 11 costs
/// each screening evaluation about half, for the same optimum on the thesis format.
constexpr int kScreenPoints{6};
/// Evaluations of one screening solve at most, and its relative tolerance [-].
constexpr int kScreenEvaluations{80};
constexpr double kScreenTolerance{1e-7};
/// Screened points min_jerk_band finishes on the n_band frequencies, and tries at most [-].
constexpr std::size_t kRefinedStarts{2};
constexpr std::size_t kRefineAttempts{5};
/// Golden-section refinement of a band maximum: relative bracket width and iterations at most.
constexpr double kBandPeakTolerance{1e-12};
constexpr int kBandPeakIterations{60};
/// Intervals of the band check grid at least (the solver's n_band - 1 when larger) [-].
constexpr int kBandCheckIntervals{50};

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

/// |X|^2 and its gradient at the objective's frequencies for the durations `of` (empty until the
/// first evaluation). SLSQP evaluates a backtracked line-search point without its gradient and
/// then, once it accepts it, again with it: the second call reuses the first's powers (which
/// carry the gradient anyway).
struct PowerScratch {
  std::vector<SpectrumPowerGradient> powers;
  std::optional<Durations> of;
};

// sum_i w_i |X(omega_i)|^2 / X_ref^2 and its gradient; the frequencies share the jerks and
// their derivatives (spectrum_power_gradients), written into `scratch` (reused between calls).
double weighted_power(const double* x, double* grad, const StrategyContext& c,
                      const std::vector<double>& omegas, const std::vector<double>& weights,
                      PowerScratch* scratch) {
  Durations d;
  std::copy(x, x + kSegments, d.begin());
  const double scale = 1.0 / (c.x_ref * c.x_ref);
  double f = 0.0;
  if (grad != nullptr) std::fill(grad, grad + kSegments, 0.0);
  if (scratch->of != d) {
    spectrum_power_gradients(d, c.format.stroke, omegas, &scratch->powers);
    scratch->of = d;
  }
  for (std::size_t k = 0; k < omegas.size(); ++k) {
    const SpectrumPowerGradient& pg = scratch->powers[k];
    f += weights[k] * scale * pg.power;
    if (grad != nullptr) {
      for (std::size_t i = 0; i < kSegments; ++i) grad[i] += weights[k] * scale * pg.gradient[i];
    }
  }
  return f;
}

// Minimise a weighted spectral power over the starts (limits as constraints).
MultiStartResult minimise_power(const StrategyContext& c, const std::vector<double>& omegas,
                                const std::vector<double>& weights, int random_starts,
                                const StartPolicy& policy) {
  NlpProblem p = c.space.problem();
  // The frequencies of zero weight contribute nothing: left out.
  std::vector<double> used_omegas, used_weights;
  for (std::size_t k = 0; k < omegas.size(); ++k) {
    if (weights[k] == 0.0) continue;
    used_omegas.push_back(omegas[k]);
    used_weights.push_back(weights[k]);
  }
  p.objective = [&c, o = std::move(used_omegas), w = std::move(used_weights),
                 scratch = PowerScratch()](const double* x, double* grad) mutable {
    return weighted_power(x, grad, c, o, w, &scratch);
  };
  add_limits(p, c, 0, nullptr);
  NlpOptions options = spectral_options();
  options.stop_value = kExactZero;  // nothing is below an exact zero: the other starts can go
  return multi_start(p, as_vectors(c.space.starts(random_starts)), c, options, policy);
}

/// The notch's multi-start: the deterministic starts (the uniform law and the symmetric
/// families, or the warm start) all run; the random ones only while they keep finding lower
/// optima (or, none feasible, less violation), and runs that reach an optimum found already are
/// left there. On 300 random formats, half with random machine limits, this found every optimum
/// the plain multi-start found with 48 % of its evaluations; the deterministic starts alone missed
/// 4 in 150 by 0.4-2.6 %.
StartPolicy notch_policy(const StrategyContext& c, StartUse uses) {
  StartPolicy policy;
  if (uses == StartUse::kEvery) return policy;
  policy.leave_known_optima = true;
  policy.optional_from = static_cast<int>(c.space.starts(0).size());
  policy.patience = kNotchPatience;
  return policy;
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

namespace {

/// True when `grid` is omega0 + k step to round-off (band_frequencies' grids).
bool equally_spaced(const std::vector<double>& grid, double* step) {
  const std::size_t n = grid.size();
  if (n < 3) return false;
  *step = (grid.back() - grid.front()) / static_cast<double>(n - 1);
  const double slack = 1e-12 * std::abs(grid.back());
  for (std::size_t k = 1; k + 1 < n; ++k) {
    if (std::abs(grid[k] - (grid.front() + *step * static_cast<double>(k))) > slack) return false;
  }
  return true;
}

}  // namespace

BandPeak band_peak(const Durations& d, double stroke, const std::vector<double>& grid) {
  auto f = [&](double w) { return std::abs(seven_segment_spectrum(d, stroke, w)); };
  std::vector<double> v;
  double step = 0.0;
  if (equally_spaced(grid, &step)) {
    // The grid's values only choose the brackets refined below and the best grid point, whose
    // value is then evaluated directly.
    seven_segment_magnitudes(d, stroke, grid.front(), step, grid.size(), &v);
  } else {
    v.resize(grid.size());
    for (std::size_t k = 0; k < grid.size(); ++k) v[k] = f(grid[k]);
  }
  std::size_t top = 0;
  for (std::size_t k = 1; k < grid.size(); ++k) {
    if (v[k] > v[top]) top = k;
  }
  BandPeak best{f(grid[top]), grid[top]};
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const bool interior_max = k > 0 && k + 1 < grid.size() && v[k] >= v[k - 1] && v[k] >= v[k + 1];
    if (!interior_max) continue;
    const Peak p = refine_max(f, grid[k - 1], grid[k + 1], kBandPeakTolerance * grid[k],
                              kBandPeakIterations, TieRule::kDiscardLower);
    if (p.value > best.value) best = {p.value, p.time};
  }
  return best;
}

std::vector<double> band_check_grid(double omega, double band, int n_band) {
  return band_frequencies(omega, band,
                          std::max(n_band - 1, kBandCheckIntervals) * kBandCheckRefinement + 1);
}

const std::vector<double>& band_check_grid(const StrategyContext& c) {
  return c.band_grid;
}

std::string band_limit_sentence(const StrategyContext& c, double best_ratio) {
  return "|X| <= " + percent(c.options.tol_rel) + " of X_ref on the band is not reachable in " +
         sig3(c.format.motion_time) + " s: the best is " + percent(best_ratio) +
         " (X_ref = the uniform law's largest |X| on the band); raise tol_rel, narrow the band or "
         "lengthen the motion";
}

namespace {

std::string hz(double omega) {
  return sig3(omega / (2.0 * std::numbers::pi)) + " Hz";
}

/// "the length's f1 = 2.37 Hz (share 1) and the width's f1 = 3.06 Hz (share 0.431)".
std::string notch_list(const std::vector<NotchTarget>& targets) {
  std::string out;
  for (std::size_t k = 0; k < targets.size(); ++k) {
    if (k > 0) out += " and ";
    out += std::string("the ") + targets[k].name + "'s f1 = " + hz(targets[k].omega) + " (share " +
           sig3(targets[k].weight) + ")";
  }
  return out;
}

/// "0.1 % and 2.3 %": |X| / X_ref of `d` at each target.
std::string residual_list(const StrategyContext& c, const std::vector<NotchTarget>& targets,
                          const Durations& d) {
  std::string out;
  for (std::size_t k = 0; k < targets.size(); ++k) {
    if (k > 0) out += " and ";
    out +=
        percent(std::abs(seven_segment_spectrum(d, c.format.stroke, targets[k].omega)) / c.x_ref);
  }
  return out;
}

}  // namespace

StrategyOutcome solve_notch(const StrategyContext& c) {
  return solve_notch(c, StartUse::kEconomical);
}

namespace {

// No zero reachable within the bounds and limits: the deepest notch instead (on a turned tank,
// the least sum of the directions' residual powers, each weighed by its share). `m` is the
// search for the zeros, whose work the outcome counts.
StrategyOutcome deepest_notch(const StrategyContext& c, const std::vector<NotchTarget>& targets,
                              StartUse uses, const MultiStartResult& m) {
  std::vector<double> omegas, weights;
  for (const NotchTarget& t : targets) {
    omegas.push_back(t.omega);
    weights.push_back(t.weight * t.weight);
  }
  MultiStartResult deepest =
      minimise_power(c, omegas, weights, kSpectralRandomStarts, notch_policy(c, uses));
  deepest.evaluations += m.evaluations;
  deepest.starts += m.starts;
  StrategyOutcome o = outcome_from(deepest, c);
  const std::string stopped = o.detail;  // why a feasible point is only acceptable
  if (o.status != SolveStatus::kInfeasible) {
    if (targets.size() == 1) {
      o.detail =
          "no exact zero of X(w1) is reachable within the bounds and limits; the deepest "
          "notch leaves |X(w1)| at " +
          percent(std::sqrt(o.objective)) + " of X_ref";
    } else {
      o.detail = "no exact zero of X at both " + notch_list(targets) +
                 " is reachable within the bounds and limits; the deepest notches leave |X| at " +
                 residual_list(c, targets, o.durations) + " of X_ref";
    }
    if (!stopped.empty()) o.detail = stopped + "; " + o.detail;
  }
  return o;
}

}  // namespace

namespace {

/// Two first modes closer than this (relative to their middle) are also notched double [-]: as
/// the two close, the zeros at both force a double zero of X (flat across them) while one zero
/// at their common frequency does not, so the law would change in kind between a square tank and
/// one a micrometre off square. Below this span a condition that X be equal at the span's ends
/// (weighed by the less excited direction's share times 1 - separation / span) takes over
/// continuously; at and above it the two zeros are what they always were.
constexpr double kDoubleNotchSpan{1e-3};

/// One condition of notch: sum_j coeff_j X(omega_j), its Re and Im held to kNotchDepth X_ref.
struct NotchCondition {
  std::vector<double> omegas;
  std::vector<double> coeffs;
};

/// The double notch of two targets closer than kDoubleNotchSpan, or nothing.
std::optional<NotchCondition> double_notch(const std::vector<NotchTarget>& targets) {
  if (targets.size() != 2) return std::nullopt;
  const double middle = 0.5 * (targets[0].omega + targets[1].omega);
  const double span = kDoubleNotchSpan * middle;
  const double gap = std::abs(targets[1].omega - targets[0].omega);
  const double weight = std::min(targets[0].weight, targets[1].weight) * (1.0 - gap / span);
  if (!(weight > 0.0)) return std::nullopt;
  return NotchCondition{{middle - 0.5 * span, middle + 0.5 * span}, {-weight, weight}};
}

std::vector<NotchCondition> notch_conditions(const std::vector<NotchTarget>& targets) {
  std::vector<NotchCondition> out;
  for (const NotchTarget& t : targets) out.push_back({{t.omega}, {t.weight}});
  if (std::optional<NotchCondition> d = double_notch(targets)) out.push_back(std::move(*d));
  return out;
}

/// X and its gradient at the conditions' frequencies for the durations `of`: SLSQP evaluates an
/// accepted line-search point twice (without, then with the Jacobian), the second call reuses
/// the first's.
struct ConditionSpectra {
  std::optional<Durations> of;
  std::vector<std::vector<SpectrumGradient>> at;
};

/// The 4 rows per condition (+-Re, +-Im of its sum minus kNotchDepth, relative to X_ref) and
/// their Jacobian when `jac` is not null.
void notch_rows(const std::vector<NotchCondition>& conditions, double stroke, double inv,
                ConditionSpectra& cache, const double* x, double* g, double* jac) {
  Durations d;
  std::copy(x, x + kSegments, d.begin());
  if (cache.of != d) {
    cache.at.resize(conditions.size());
    for (std::size_t k = 0; k < conditions.size(); ++k) {
      cache.at[k].clear();
      for (double w : conditions[k].omegas) cache.at[k].push_back(spectrum_gradient(d, stroke, w));
    }
    cache.of = d;
  }
  for (std::size_t k = 0; k < conditions.size(); ++k) {
    SpectrumGradient sum{};
    for (std::size_t j = 0; j < conditions[k].omegas.size(); ++j) {
      const double scale = conditions[k].coeffs[j] * inv;
      const SpectrumGradient& sg = cache.at[k][j];
      sum.X += sg.X * scale;
      for (std::size_t i = 0; i < kSegments; ++i) sum.dX[i] += sg.dX[i] * scale;
    }
    double* gk = g + 4 * k;
    gk[0] = sum.X.real() - kNotchDepth;
    gk[1] = -sum.X.real() - kNotchDepth;
    gk[2] = sum.X.imag() - kNotchDepth;
    gk[3] = -sum.X.imag() - kNotchDepth;
    if (jac == nullptr) continue;
    double* jk = jac + 4 * k * kSegments;
    for (std::size_t i = 0; i < kSegments; ++i) {
      jk[0 * kSegments + i] = sum.dX[i].real();
      jk[1 * kSegments + i] = -sum.dX[i].real();
      jk[2 * kSegments + i] = sum.dX[i].imag();
      jk[3 * kSegments + i] = -sum.dX[i].imag();
    }
  }
}

std::string exact_notch_sentence(const std::vector<NotchTarget>& targets, double jerk_share) {
  std::string out =
      targets.size() == 1
          ? std::string(
                "exact notch at f1 (|Re X(w1)|, |Im X(w1)| <= 1e-6 of X_ref, so |X(w1)| "
                "<= 1.42e-6 of X_ref)")
          : "exact notches at " + notch_list(targets) +
                " (for each, |Re X|, |Im X| times its share of the residual wave <= 1e-6 of "
                "X_ref)";
  if (double_notch(targets)) {
    out +=
        ", made double as the two lie within 0.1 % of each other (X held equal at 0.05 % on "
        "either side of their middle, weighed by the lesser share), so that the law does not "
        "jump as the tank's sides become equal";
  }
  return out + ", the one with the least jerk integral among the zeros (" + percent(jerk_share) +
         " of the uniform law's)";
}

}  // namespace

StrategyOutcome solve_notch(const StrategyContext& c, StartUse uses) {
  const std::vector<NotchTarget> targets = notch_targets(c);
  // Among the exact zeros of X at every target (a 4-dimensional manifold of the 6 free durations
  // for one, 2-dimensional for a turned tank's two), the one with the least jerk integral:
  // min int j^2 dt s.t. w_k |Re X(w_k)|, w_k |Im X(w_k)| <= kNotchDepth x_ref. The weight w_k
  // (a direction's share of the residual wave) makes each zero exact on the tank's walls, and
  // lets the law move continuously to the one-direction notch as the orientation nears an axis
  // (the second target's rows go slack once its share is small enough).
  NlpProblem p = c.space.problem();
  p.objective = [&c](const double* x, double* grad) { return jerk_objective(x, grad, c); };
  const double stroke = c.format.stroke;
  const double inv = 1.0 / c.x_ref;
  const std::vector<NotchCondition> conditions = notch_conditions(targets);
  const int rows = 4 * static_cast<int>(conditions.size());
  ConditionSpectra spectra;
  add_limits(p, c, rows,
             [&conditions, stroke, inv, cache = &spectra](const double* x, double* g, double* jac) {
               notch_rows(conditions, stroke, inv, *cache, x, g, jac);
             });
  MultiStartResult m = multi_start(p, as_vectors(c.space.starts(kSpectralRandomStarts)), c,
                                   spectral_options(), notch_policy(c, uses));
  if (m.feasible) {
    StrategyOutcome o = outcome_from(m, c);
    const std::string stopped = o.detail;
    o.detail = exact_notch_sentence(targets, o.objective);
    if (!stopped.empty()) o.detail = stopped + "; " + o.detail;
    return o;
  }
  return deepest_notch(c, targets, uses, m);
}

StrategyOutcome solve_multi_notch(const StrategyContext& c) {
  return solve_multi_notch(c, StartUse::kEconomical);
}

StrategyOutcome solve_multi_notch(const StrategyContext& c, StartUse uses) {
  const double p_notch = c.p_notch;
  // Three notches around each target; on a turned tank each direction's weighed by the square
  // of its share of the residual wave (the objective is a power), so that the law moves
  // continuously to the one-direction law as the orientation nears an axis.
  const std::vector<NotchTarget> targets = notch_targets(c);
  std::vector<double> omegas, weights;
  for (const NotchTarget& t : targets) {
    for (std::size_t i = 0; i < 3; ++i) {
      omegas.push_back((1.0 + (static_cast<double>(i) - 1.0) * p_notch) * t.omega);
      weights.push_back(c.options.weights[i] * t.weight * t.weight);
    }
  }
  // Every start runs (its objective has many basins), each left once it reaches a known one.
  StartPolicy policy;
  policy.leave_known_optima = uses == StartUse::kEconomical;
  policy.mirror_symmetric = true;
  policy.approach_basin = kMultiNotchApproach;
  const MultiStartResult m = minimise_power(c, omegas, weights, kMultiNotchRandomStarts, policy);
  StrategyOutcome o = outcome_from(m, c);
  const std::string stopped = o.detail;
  if (o.status != SolveStatus::kInfeasible) {
    Durations d = o.durations;
    std::string parts;
    for (double w : omegas) {
      if (!parts.empty()) parts += ", ";
      parts += percent(std::abs(seven_segment_spectrum(d, c.format.stroke, w)) / c.x_ref);
    }
    o.detail = targets.size() == 1
                   ? "|X| at (1-p) f1, f1, (1+p) f1 = " + parts + " of X_ref"
                   : "|X| at (1-p) f, f, (1+p) f around " + notch_list(targets) + " = " + parts +
                         " of X_ref (each direction weighed by the square of its share "
                         "of the residual wave)";
    if (!stopped.empty()) o.detail = stopped + "; " + o.detail;
  }
  return o;
}

namespace {

/// Scratch of the band rows: |X|^2 and its gradient at the rows' frequencies `omegas` for the
/// durations `of`, refilled when either differs. Owned by the caller beside the rows' data (as
/// Pinocchio passes Data beside Model) and outliving every problem that evaluates into it; the
/// solves run one at a time. SLSQP evaluates a backtracked line-search point without its
/// Jacobian and then, once it accepts it, again with it: the second call reuses the first's
/// powers (which carry the gradient anyway), so the rows' numbers are the same either way.
struct BandWorkspace {
  std::vector<SpectrumPowerGradient> powers;
  std::vector<double> omegas;
  std::optional<Durations> of;
};

/// Band rows relative to their bound: |X(w_k)|^2 scale - limit <= 0 (phase J), or
/// |X(w_k)|^2 scale - z <= 0 (phase E, epigraph: z is the last variable).
struct BandRows {
  std::vector<double> omegas;  ///< [rad/s]
  double stroke{};             ///< [m]
  double scale{};              ///< 1 / (tol X_ref)^2 (phase J) or 1 / X_ref^2 (phase E)
  bool epigraph{false};
  double limit{1.0};  ///< phase J's bound on the scaled rows
};

void evaluate_band_rows(const BandRows& rows, BandWorkspace& ws, const double* x, double* g,
                        double* jac) {
  const int n = kSegments + (rows.epigraph ? 1 : 0);
  Durations d;
  std::copy(x, x + kSegments, d.begin());
  if (ws.of != d || ws.omegas != rows.omegas) {
    spectrum_power_gradients(d, rows.stroke, rows.omegas, &ws.powers);
    ws.of = d;
    ws.omegas = rows.omegas;
  }
  for (std::size_t k = 0; k < rows.omegas.size(); ++k) {
    const auto& pg = ws.powers[k];
    g[k] = pg.power * rows.scale - (rows.epigraph ? x[kSegments] : rows.limit);
    if (jac != nullptr) {
      for (std::size_t i = 0; i < kSegments; ++i) jac[k * n + i] = pg.gradient[i] * rows.scale;
      if (rows.epigraph) jac[k * n + kSegments] = -1.0;
    }
  }
}

/// What min_jerk_band's phases share: the problem data, the fine check grid, the starts, the
/// rows' workspace and the outcome whose evaluations and starts they add to.
struct BandSearch {
  const StrategyContext& c;
  double w1{};      ///< [rad/s]
  double tol{};     ///< tol_rel [-]
  double stroke{};  ///< [m]
  /// Phase J's rows: |X(w_k)|^2 / (tol X_ref)^2 - 1 <= 0.
  double scale{};
  /// Phase E's z is (|X| / X_ref)^2: of order 1 like the durations' gradients, which SLSQP needs
  /// (in units of the tolerance it stalls on small tol_rel).
  double scale_e{};
  const std::vector<double>& fine;  ///< band_check_grid (the context's, built once)
  std::vector<double> base_omegas;  ///< the n_band solver frequencies
  std::vector<Durations> starts;
  /// The screening tries more random points than the other phases: the band-constrained optimum
  /// is often asymmetric and reached from few starts.
  std::vector<Durations> screen_starts;
  BandWorkspace& workspace;
  StrategyOutcome& out;
  /// The rows phase J's solves carry (kActive, the default, or all of them).
  BandRowSelection row_selection{BandRowSelection::kActive};

  void count(const MultiStartResult& r) {
    out.evaluations += r.evaluations;
    out.starts += r.starts;
  }
  /// The problem's inequalities: the band rows on `omegas`, then the limits.
  std::function<void(const double*, double*, double*)> rows(std::vector<double> omegas,
                                                            bool epigraph, double limit = 1.0) {
    BandRows r{std::move(omegas), stroke, epigraph ? scale_e : scale, epigraph, limit};
    BandWorkspace* ws = &workspace;
    return [r = std::move(r), ws](const double* x, double* g, double* jac) {
      evaluate_band_rows(r, *ws, x, g, jac);
    };
  }
  /// min int j^2 dt over the durations (limits and rows added by the caller).
  [[nodiscard]] NlpProblem jerk_problem() const {
    NlpProblem p = c.space.problem();
    const StrategyContext* ctx = &c;
    p.objective = [ctx](const double* x, double* grad) { return jerk_objective(x, grad, *ctx); };
    return p;
  }
};

/// A point of a phase, checked on the fine grid.
struct BandPoint {
  MultiStartResult r;
  Durations d{};
  double ratio{INFINITY};  // largest |X| / X_ref on the fine grid
  bool met{false};         // ratio <= tol (1 + kBandTolerance), limits held by the solver
};

bool limits_met(const StrategyContext& c, const Durations& d) {
  const int m = c.space.limit_count();
  if (m == 0) return true;
  std::vector<double> g(static_cast<std::size_t>(m));
  c.space.limit_constraints(d.data(), g.data(), nullptr, kSegments);
  return *std::max_element(g.begin(), g.end()) <= kBandTolerance;
}

double band_ratio(const BandSearch& s, const Durations& d) {
  return band_peak(d, s.stroke, s.fine).value / s.c.x_ref;
}

/// The band checker: the polished solver point `x` on the fine grid (band_peak refines every
/// local maximum with refine_max); returns the point and writes the worst frequency.
BandPoint check_band(const BandSearch& s, const std::vector<double>& x, double* worst_omega) {
  BandPoint here;
  here.d = s.c.space.polish(x.data());
  const BandPeak worst = band_peak(here.d, s.stroke, s.fine);
  here.ratio = worst.value / s.c.x_ref;
  here.met = here.ratio <= s.tol * (1.0 + kBandTolerance) && limits_met(s.c, here.d);
  *worst_omega = worst.omega;
  return here;
}

/// min int j^2 dt s.t. the band rows on `omegas` (bound `limit`) and the limits, from `from`.
MultiStartResult solve_on_rows(BandSearch& s, const std::vector<double>& omegas, double limit,
                               const std::vector<std::vector<double>>& from) {
  NlpProblem p = s.jerk_problem();
  add_limits(p, s.c, static_cast<int>(omegas.size()), s.rows(omegas, false, limit));
  MultiStartResult r = multi_start(p, from, s.c, spectral_options());
  // SLSQP sometimes stops short of the optimum (line search on round-off); one restart from
  // where it stopped finishes the job.
  if (r.feasible && !r.timed_out) {
    MultiStartResult again = multi_start(p, {r.best.x}, s.c, spectral_options());
    s.count(again);
    if (again.feasible && again.best.objective < r.best.objective) {
      again.evaluations = r.evaluations;
      again.starts = r.starts;
      r = std::move(again);
    }
  }
  s.count(r);
  return r;
}

/// Marks the band rows that can be active near a point whose scaled rows (g <= 0 is met) are
/// `g`: every local maximum of g over frequency with its two neighbours (a maximum of |X| moves
/// with the durations, but between neighbouring rows), and every row within kNearActive of its
/// bound. `order` sorts the rows by frequency (the exchange appends its points at the end).
void mark_candidate_rows(const std::vector<double>& g, const std::vector<std::size_t>& order,
                         std::vector<char>* chosen) {
  constexpr double kNearActive{0.05};
  const std::size_t n = order.size();
  for (std::size_t j = 0; j < n; ++j) {
    const double here = g[order[j]];
    const bool left = j == 0 || here >= g[order[j - 1]];
    const bool right = j + 1 == n || here >= g[order[j + 1]];
    if (here >= -kNearActive) (*chosen)[order[j]] = 1;
    if (!(left && right)) continue;
    for (std::size_t k = j == 0 ? 0 : j - 1; k <= std::min(j + 1, n - 1); ++k) {
      (*chosen)[order[k]] = 1;
    }
  }
}

/// solve_on_rows with only the rows that can be active: SLSQP's work per iteration grows with
/// its rows (its least-squares subproblem carries every row), and of the n_band rows only the
/// few near the band's local maxima of |X| bind. The rows left out are checked at the solution;
/// any above its bound joins and the solve resumes from there, so the point returned meets every
/// row and is a KKT point of the full problem (the rows left out are inactive there).
MultiStartResult solve_on_active_rows(BandSearch& s, const std::vector<double>& omegas,
                                      double limit, std::vector<std::vector<double>> from) {
  const std::size_t rows = omegas.size();
  NlpProblem full = s.jerk_problem();
  add_limits(full, s.c, static_cast<int>(rows), s.rows(omegas, false, limit));
  std::vector<std::size_t> order(rows);
  for (std::size_t k = 0; k < rows; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return omegas[a] < omegas[b]; });
  std::vector<double> g(static_cast<std::size_t>(full.inequality_count));
  std::vector<char> chosen(rows, 0);
  for (const auto& x0 : from) {
    full.inequalities(x0.data(), g.data(), nullptr);
    mark_candidate_rows(g, order, &chosen);
  }
  const double row_slack = spectral_options().constraint_tolerance;
  for (;;) {
    std::vector<double> active;
    for (std::size_t k = 0; k < rows; ++k) {
      if (chosen[k] != 0) active.push_back(omegas[k]);
    }
    MultiStartResult r = solve_on_rows(s, active, limit, from);
    if (r.best.x.empty() || active.size() == rows) return r;
    full.inequalities(r.best.x.data(), g.data(), nullptr);
    bool added = false;
    for (std::size_t k = 0; k < rows; ++k) {
      if (chosen[k] == 0 && g[k] > row_slack) added = true;
    }
    if (!added || r.timed_out) {
      r.best.max_violation = max_violation(full, r.best.x);
      return r;
    }
    // Rows above their bound: they, and the rows that can be active around the new point, join.
    for (std::size_t k = 0; k < rows; ++k) {
      if (g[k] > row_slack) chosen[k] = 1;
    }
    mark_candidate_rows(g, order, &chosen);
    from = {r.best.x};
  }
}

/// Phase J: min int j^2 dt s.t. the band on n_band points, from `x0`; the constraint is
/// semi-infinite, so the band is then checked on the fine grid and its worst frequency added for
/// a re-solve from the current point until the check passes (exchange rounds). Between the
/// solver's frequencies the maximum moves with the durations, so from the second round on the
/// bound is tightened by twice the excess still found.
BandPoint solve_jerk(BandSearch& s, const std::vector<std::vector<double>>& x0) {
  std::vector<double> omegas = s.base_omegas;
  std::vector<std::vector<double>> from = x0;
  double margin = 0.0;
  BandPoint best;
  for (int round = 0; round < kBandExchangeRounds; ++round) {
    const double limit = (1.0 - margin) * (1.0 - margin);
    MultiStartResult r = s.row_selection == BandRowSelection::kAll
                             ? solve_on_rows(s, omegas, limit, from)
                             : solve_on_active_rows(s, omegas, limit, from);
    // SLSQP may stop a hair outside a constraint (4e-8 of the bound): far inside what the
    // verification tolerates, so the point is judged by the verification, not by the solver.
    if (r.best.x.empty() || r.best.max_violation > kExchangeSlack) break;
    double worst_omega = 0.0;
    BandPoint here = check_band(s, r.best.x, &worst_omega);
    here.r = std::move(r);
    const bool timed_out = here.r.timed_out;
    const double excess = here.ratio / s.tol - 1.0;
    best = std::move(here);
    if (best.met || timed_out) break;
    omegas.push_back(worst_omega);
    if (round >= 1) margin += 2.0 * excess;
    from = {best.r.best.x};
  }
  return best;
}

/// Phase E's solve on `omegas` from `from`: with kActive only the rows that can be active (those
/// near the band's local maxima of |X| and within 5 % of the level z, as in phase J), the rest
/// checked at the solution and added, and the solve resumed, while any is above z; the point
/// returned is then a KKT point of the min-max on every row.
MultiStartResult solve_excess_rows(BandSearch& s, const std::vector<double>& omegas,
                                   std::vector<std::vector<double>> from) {
  const NlpOptions options = spectral_options();
  auto solve = [&](const std::vector<double>& rows_omegas,
                   const std::vector<std::vector<double>>& x0) {
    NlpProblem p = s.c.space.problem(1, 1e6);
    add_limits(p, s.c, static_cast<int>(rows_omegas.size()), s.rows(rows_omegas, true));
    MultiStartResult r = multi_start(p, x0, s.c, options);
    s.count(r);
    return r;
  };
  if (s.row_selection == BandRowSelection::kAll) return solve(omegas, from);
  const std::size_t rows = omegas.size();
  NlpProblem full = s.c.space.problem(1, 1e6);
  add_limits(full, s.c, static_cast<int>(rows), s.rows(omegas, true));
  std::vector<std::size_t> order(rows);
  for (std::size_t k = 0; k < rows; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return omegas[a] < omegas[b]; });
  std::vector<double> g(static_cast<std::size_t>(full.inequality_count));
  std::vector<double> relative(rows);
  std::vector<char> chosen(rows, 0);
  // The rows relative to the level z (g_k = |X_k|^2 / X_ref^2 - z; g_k / z >= -5 % is near it).
  auto mark = [&](const std::vector<double>& x) {
    full.inequalities(x.data(), g.data(), nullptr);
    const double z = std::max(x[kSegments], 1e-300);
    for (std::size_t k = 0; k < rows; ++k) relative[k] = g[k] / z;
    mark_candidate_rows(relative, order, &chosen);
  };
  for (const auto& x0 : from) mark(x0);
  const double row_slack = spectral_options().constraint_tolerance;
  for (;;) {
    std::vector<double> active;
    for (std::size_t k = 0; k < rows; ++k) {
      if (chosen[k] != 0) active.push_back(omegas[k]);
    }
    MultiStartResult r = solve(active, from);
    if (r.best.x.empty() || active.size() == rows || r.timed_out) return r;
    full.inequalities(r.best.x.data(), g.data(), nullptr);
    bool added = false;
    for (std::size_t k = 0; k < rows; ++k) {
      if (chosen[k] == 0 && g[k] > row_slack) {
        chosen[k] = 1;
        added = true;
      }
    }
    if (!added) {
      r.best.max_violation = max_violation(full, r.best.x);
      return r;
    }
    mark(r.best.x);
    from = {r.best.x};
  }
}

/// Phase E (least infeasible): min z s.t. |X(w_k)|^2 / X_ref^2 <= z on the band, the min-max of
/// the band excess, with the same exchange on the fine grid.
BandPoint solve_excess(BandSearch& s, const std::vector<Durations>& x0) {
  std::vector<double> omegas = s.base_omegas;
  BandPoint best;
  if (const std::optional<Durations> only = s.c.space.only_point()) {
    // One admissible point: its band maximum is the least excess (z is then a 1-D min-max).
    double worst_omega = 0.0;
    best = check_band(s, std::vector<double>(only->begin(), only->end()), &worst_omega);
    best.r.best.x.assign(only->begin(), only->end());
    best.r.best.x.push_back(best.ratio * best.ratio);
    best.r.best.status = SolveStatus::kOptimal;
    best.r.feasible = limits_met(s.c, *only);
    best.r.starts = 1;
    return best;
  }
  std::vector<std::vector<double>> from;
  for (const Durations& d : x0) {
    std::vector<double> x(d.begin(), d.end());
    x.push_back(std::pow(band_ratio(s, d), 2) * 1.01);
    from.push_back(std::move(x));
  }
  for (int round = 0; round < kBandExchangeRounds; ++round) {
    MultiStartResult r = solve_excess_rows(s, omegas, from);
    if (r.best.x.empty()) break;
    double worst_omega = 0.0;
    BandPoint here = check_band(s, r.best.x, &worst_omega);
    const double sampled = std::sqrt(std::max(r.best.x[kSegments], 0.0));
    const bool timed_out = r.timed_out;
    here.r = std::move(r);
    if (here.ratio < best.ratio || (here.r.feasible && !best.r.feasible)) best = here;
    if (timed_out || here.ratio <= sampled * (1.0 + kBandTolerance)) break;
    omegas.push_back(worst_omega);
    std::vector<double> x = here.r.best.x;
    x[kSegments] = std::pow(here.ratio, 2) * 1.01;
    from = {std::move(x)};
  }
  return best;
}

/// Phase 0: the least jerk integral without the band (the limits only; nearly convex, so the
/// uniform start suffices). True when it meets the band: the band is inactive, it is the optimum
/// and `s.out` holds it. Otherwise its point, when any, is put first in `jerk_starts`.
bool band_free_optimum(BandSearch& s, std::vector<std::vector<double>>& jerk_starts) {
  NlpProblem p = s.jerk_problem();
  add_limits(p, s.c, 0, nullptr);
  const MultiStartResult free = multi_start(p, {jerk_starts.front()}, s.c, spectral_options());
  s.count(free);
  if (!free.feasible || free.best.x.empty()) return false;
  const Durations d = s.c.space.polish(free.best.x.data());
  const double ratio = band_ratio(s, d);
  if (ratio <= s.tol * (1.0 + kBandTolerance) && !free.timed_out) {
    StrategyOutcome& o = s.out;
    o.durations = d;
    o.objective = jerk_objective(d.data(), nullptr, s.c);
    o.status = free.best.status == SolveStatus::kOptimal ? SolveStatus::kOptimal
                                                         : SolveStatus::kAcceptable;
    o.detail = "|X| <= " + percent(ratio) + " of X_ref over the whole band (limit " +
               percent(s.tol) + ", not binding), jerk integral " + percent(o.objective) +
               " of the uniform law's";
    if (o.status == SolveStatus::kAcceptable) o.detail = not_converged(free.best) + "; " + o.detail;
    return true;
  }
  jerk_starts.insert(jerk_starts.begin(), free.best.x);
  return false;
}

/// The screening solves on kScreenPoints band frequencies from the starts, capped: the feasible
/// points (objective, x), and those the cap stopped outside the band in `unfinished`. The starts
/// from `random_from` on end once a screened point exists and kScreenPatience starts in a row
/// have not lowered the best screened objective.
std::vector<std::pair<double, std::vector<double>>> screen_starts(
    BandSearch& s, const NlpProblem& p, const std::vector<std::vector<double>>& jerk_starts,
    std::size_t random_from, std::vector<std::vector<double>>* unfinished) {
  std::vector<std::pair<double, std::vector<double>>> screened;
  NlpOptions capped = spectral_options();
  capped.max_iterations = kScreenEvaluations;  // a ranking: the best are finished below
  capped.tolerance = kScreenTolerance;
  double best = INFINITY;
  int stale = 0;  // starts in a row that did not lower `best`
  for (std::size_t k = 0; k < jerk_starts.size(); ++k) {
    if (k >= random_from && !screened.empty() && stale >= kScreenPatience) break;
    const MultiStartResult r = multi_start(p, {jerk_starts[k]}, s.c, capped);
    s.count(r);
    if (r.timed_out) break;
    ++stale;
    if (r.best.x.empty()) continue;
    if (r.best.max_violation <= kSolverSlack) {
      // A tie with the best (the same optimum to the screening's tolerance) is no progress.
      if (r.best.objective < best * (1.0 - kScreenTolerance)) stale = 0;
      best = std::min(best, r.best.objective);
      screened.emplace_back(r.best.objective, r.best.x);
    } else {
      // SLSQP also stops outside the constraints (its objective stalls while infeasible):
      // finished below when nothing better turns up.
      unfinished->push_back(r.best.x);
    }
  }
  return screened;
}

/// Phase J's screening: SLSQP on the band constraint itself (scaled by X_ref it is well
/// conditioned) on kScreenPoints band frequencies from every start; the distinct screened points,
/// best first.
std::vector<std::vector<double>> screen(BandSearch& s,
                                        const std::vector<std::vector<double>>& jerk_starts) {
  NlpProblem p = s.jerk_problem();
  const std::vector<double> coarse =
      band_frequencies(s.w1, s.c.band, std::min(s.c.options.n_band, kScreenPoints));
  add_limits(p, s.c, static_cast<int>(coarse.size()), s.rows(coarse, false));
  std::vector<std::vector<double>> unfinished;  // stopped by the cap outside the band
  // jerk_starts: the band-free optimum (when any), the deterministic starts, the random ones.
  const std::size_t random =
      s.screen_starts.size() - std::min(s.screen_starts.size(), s.c.space.starts(0).size());
  auto screened = screen_starts(s, p, jerk_starts, jerk_starts.size() - random, &unfinished);
  // Hard formats (few starts reach the band): the solves that stopped outside it continue from
  // where they stopped, without the cap and with a fresh Hessian.
  double best_screened = INFINITY;
  for (const auto& [f, x] : screened) best_screened = std::min(best_screened, f);
  for (const auto& x0 : unfinished) {
    // Worth finishing: too few screened points, or a lower jerk than the best of them.
    if (screened.size() >= kRefinedStarts &&
        !(jerk_objective(x0.data(), nullptr, s.c) < best_screened)) {
      continue;
    }
    const MultiStartResult r = multi_start(p, {x0}, s.c, spectral_options());
    s.count(r);
    if (r.timed_out) break;
    if (!r.best.x.empty() && r.best.max_violation <= kSolverSlack) {
      screened.emplace_back(r.best.objective, r.best.x);
    }
  }
  std::stable_sort(screened.begin(), screened.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  // Distinct points only (many starts land on the same screened optimum).
  std::vector<std::vector<double>> refine_from;
  for (const auto& point : screened) {
    const auto& x = point.second;  // (clang 14 cannot capture a structured binding)
    const bool seen = std::any_of(refine_from.begin(), refine_from.end(), [&](const auto& y) {
      for (std::size_t i = 0; i < kSegments; ++i) {
        if (std::abs(x[i] - y[i]) > 1e-6 * s.c.format.motion_time) return false;
      }
      return true;
    });
    if (!seen) refine_from.push_back(x);
  }
  return refine_from;
}

/// The best screened points in order until kRefinedStarts of them meet the band (at most
/// kRefineAttempts tries: a screened point far outside the full band may not come back), each
/// solved on the n_band points with the exchange on the fine grid.
BandPoint refine(BandSearch& s, const std::vector<std::vector<double>>& refine_from) {
  BandPoint jerk;
  int met = 0;
  for (std::size_t k = 0; k < refine_from.size() && k < kRefineAttempts; ++k) {
    if (met == static_cast<int>(kRefinedStarts) || s.c.deadline.expired()) break;
    BandPoint here = solve_jerk(s, {refine_from[k]});
    if (here.met) ++met;
    const bool better =
        (here.met && !jerk.met) ||
        (here.met == jerk.met &&
         (here.met ? here.r.best.objective < jerk.r.best.objective : here.ratio < jerk.ratio));
    if (better) jerk = std::move(here);
  }
  return jerk;
}

/// The band is not reachable from the starts by phase J: the least infeasible point of the band
/// excess, from the starts, then the points phase J got closest with (its best and the screened
/// points). When it meets the band after all, phase J runs from it.
void fall_back_to_least_excess(BandSearch& s, const std::vector<std::vector<double>>& refine_from,
                               BandPoint& jerk) {
  std::vector<Durations> excess_starts = s.screen_starts;
  auto add_start = [&](const Durations& d) {
    if (std::find(excess_starts.begin(), excess_starts.end(), d) == excess_starts.end()) {
      excess_starts.push_back(d);
    }
  };
  if (jerk.ratio < INFINITY) add_start(jerk.d);
  for (const auto& x : refine_from) add_start(s.c.space.polish(x.data()));
  BandPoint least = solve_excess(s, excess_starts);
  // Never worse than a start.
  for (const Durations& d : s.starts) {
    const double rs = band_ratio(s, d);
    if (rs < least.ratio) {
      least.ratio = rs;
      least.d = d;
      least.met = false;
    }
  }
  if (least.met) {
    BandPoint from_least = solve_jerk(s, {std::vector<double>(least.d.begin(), least.d.end())});
    jerk = from_least.met ? std::move(from_least) : std::move(least);
  } else if (!jerk.r.feasible || least.ratio < jerk.ratio) {
    jerk = std::move(least);
  }
}

/// The outcome of the best point found.
void finish_band(BandSearch& s, const BandPoint& jerk) {
  StrategyOutcome& o = s.out;
  const StrategyContext& c = s.c;
  if (jerk.r.best.x.empty() && jerk.ratio == INFINITY) {
    o.status = c.deadline.expired() ? SolveStatus::kTimeLimit : SolveStatus::kFailed;
    o.durations = s.starts.front();
    return;
  }
  o.durations = jerk.d;
  o.objective = jerk_objective(jerk.d.data(), nullptr, c);
  if (jerk.met && limits_met(c, jerk.d)) {
    o.status = jerk.r.timed_out                              ? SolveStatus::kTimeLimit
               : jerk.r.best.status == SolveStatus::kOptimal ? SolveStatus::kOptimal
                                                             : SolveStatus::kAcceptable;
    o.detail = "|X| <= " + percent(jerk.ratio) + " of X_ref over the whole band (limit " +
               percent(s.tol) + "), jerk integral " + percent(o.objective) +
               " of the uniform law's";
    if (o.status == SolveStatus::kAcceptable) {
      o.detail = not_converged(jerk.r.best) + "; " + o.detail;
    }
    return;
  }
  if (c.deadline.expired()) {
    o.status = SolveStatus::kTimeLimit;
    o.durations = s.starts.front();
    return;
  }
  o.status = SolveStatus::kInfeasible;
  o.detail = band_limit_sentence(c, jerk.ratio);
}

}  // namespace

StrategyOutcome solve_min_jerk_band(const StrategyContext& c) {
  return solve_min_jerk_band(c, BandRowSelection::kActive);
}

StrategyOutcome solve_min_jerk_band(const StrategyContext& c, BandRowSelection rows) {
  StrategyOutcome o;
  o.solver = solver_name(c);
  BandWorkspace workspace;
  const double w1 = c.design_model.omega1();
  const double tol = c.options.tol_rel;
  BandSearch s{c,
               w1,
               tol,
               c.format.stroke,
               1.0 / (c.x_ref * c.x_ref * tol * tol),
               1.0 / (c.x_ref * c.x_ref),
               band_check_grid(c),
               band_frequencies(w1, c.band, c.options.n_band),
               c.space.starts(kSpectralRandomStarts),
               c.space.starts(kBandRandomStarts),
               workspace,
               o,
               rows};
  std::vector<std::vector<double>> jerk_starts = as_vectors(s.screen_starts);
  if (band_free_optimum(s, jerk_starts)) return o;
  // Phase J from the band-free optimum and every start: screened, then the best screened points
  // solved on the n_band points with the exchange on the fine grid.
  const std::vector<std::vector<double>> refine_from = screen(s, jerk_starts);
  BandPoint jerk = refine(s, refine_from);
  if (!jerk.met && !c.deadline.expired()) fall_back_to_least_excess(s, refine_from, jerk);
  finish_band(s, jerk);
  return o;
}

}  // namespace slosh::detail
