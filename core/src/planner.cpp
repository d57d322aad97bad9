#include "slosh/core/planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "slosh/core/spectrum.hpp"
#include "strategies.hpp"
#include "text.hpp"

namespace slosh {

namespace {

using detail::sig3;

/// Tie tolerance of the `auto` rule on eta_rest (relative) [-].
constexpr double kAutoTieTolerance{1e-6};
/// `auto` keeps candidates whose eta_motion is within this factor of the best one (SPEC §5).
constexpr double kAutoMotionSlack{1.05};

LawPrediction predict(const SloshingModel& model, const Durations& d, double stroke,
                      double rest_time) {
  const SevenSegmentLaw law(d, stroke);
  LawPrediction p;
  p.kinematics = law.law().summary();
  p.linear = LinearResponse(model, law.law(), rest_time).peaks();
  p.nonlinear = NonlinearResponse(model, law.law(), rest_time).peaks();
  return p;
}

double reduction(double baseline, double value) {
  return baseline > 0.0 ? 100.0 * (1.0 - value / baseline) : 0.0;
}

std::string summary_sentence(const LawPrediction& p, const LawPrediction& b) {
  auto change = [](double base, double v) {
    const double r = reduction(base, v);
    std::string text(r >= 0.0 ? "-" : "+");
    text.append(sig3(std::abs(r)));
    text.append(" %");
    return text;
  };
  return "nonlinear model: eta_motion " + sig3(p.nonlinear.motion.value * 1e3) + " mm (" +
         change(b.nonlinear.motion.value, p.nonlinear.motion.value) + " vs the uniform law), " +
         "eta_rest " + sig3(p.nonlinear.rest.value * 1e3) + " mm (" +
         change(b.nonlinear.rest.value, p.nonlinear.rest.value) + ")";
}

}  // namespace

std::string to_string(Strategy strategy) {
  switch (strategy) {
    case Strategy::kBaseline:
      return "baseline";
    case Strategy::kNotch:
      return "notch";
    case Strategy::kMultiNotch:
      return "multi_notch";
    case Strategy::kMinJerkBand:
      return "min_jerk_band";
    case Strategy::kTimeDomain:
      return "time_domain";
    case Strategy::kAuto:
      return "auto";
  }
  return "baseline";
}

std::optional<Strategy> parse_strategy(std::string_view name) {
  for (Strategy s : {Strategy::kBaseline, Strategy::kNotch, Strategy::kMultiNotch,
                     Strategy::kMinJerkBand, Strategy::kTimeDomain, Strategy::kAuto}) {
    if (to_string(s) == name) return s;
  }
  return std::nullopt;
}

std::string to_string(SolverChoice solver) {
  switch (solver) {
    case SolverChoice::kAuto:
      return "auto";
    case SolverChoice::kNlopt:
      return "nlopt";
    case SolverChoice::kIpopt:
      return "ipopt";
  }
  return "auto";
}

bool PlanOptions::is_valid(const Format& format, std::string* error) const {
  auto fail = [error](std::string message) {
    if (error != nullptr) *error = std::move(message);
    return false;
  };
  const double T = format.motion_time;
  if (!(min_ramp > 0.0) || !std::isfinite(min_ramp)) {
    return fail("min_ramp_s = " + sig3(min_ramp) + " s must be > 0");
  }
  const double floor_sum = 4.0 * min_ramp + plateau_min[0] + plateau_min[1];
  if (floor_sum > T) {
    return fail("min_ramp_s = " + sig3(min_ramp) + " s and plateau_min_s = [" +
                sig3(plateau_min[0]) + ", " + sig3(plateau_min[1]) +
                "] s need 4 ramps + 2 plateaus = " + sig3(floor_sum) +
                " s, more than the motion time " + sig3(T) +
                " s: allowed min_ramp_s <= (T - plateau minimums) / 4 = " +
                sig3((T - plateau_min[0] - plateau_min[1]) / 4.0) + " s");
  }
  for (int i = 0; i < 2; ++i) {
    if (!(plateau_min[i] >= 0.0)) {
      return fail("plateau_min_s[" + std::to_string(i) + "] = " + sig3(plateau_min[i]) +
                  " s must be >= 0");
    }
  }
  double weight_sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (!(weights[i] >= 0.0) || !std::isfinite(weights[i])) {
      return fail("weights[" + std::to_string(i) + "] = " + sig3(weights[i]) +
                  " must be finite and >= 0");
    }
    weight_sum += weights[i];
  }
  if (weight_sum <= 0.0) return fail("weights = [0, 0, 0]: at least one weight must be > 0");
  if (!(p_notch > 0.0 && p_notch < 1.0)) {
    return fail("p_notch = " + sig3(p_notch) + " must be > 0 and < 1");
  }
  if (!(band > 0.0 && band < 1.0)) return fail("band = " + sig3(band) + " must be > 0 and < 1");
  if (n_band < 1) return fail("n_band = " + std::to_string(n_band) + " must be >= 1");
  if (!(tol_rel > 0.0)) return fail("tol_rel = " + sig3(tol_rel) + " must be > 0");
  if (!(eta_rest_max > 0.0)) {
    return fail("eta_rest_max_mm = " + sig3(eta_rest_max * 1e3) + " mm must be > 0");
  }
  if (eta_motion_max && !(*eta_motion_max > 0.0)) {
    return fail("eta_motion_max_mm = " + sig3(*eta_motion_max * 1e3) + " mm must be > 0");
  }
  if (!(rest_time > 0.0)) return fail("rest_time_s = " + sig3(rest_time) + " s must be > 0");
  const std::pair<const std::optional<double>*, const char*> lims[] = {
      {&limits.a_max, "limits.a_max"},
      {&limits.v_max, "limits.v_max"},
      {&limits.j_max, "limits.j_max"}};
  for (const auto& [value, name] : lims) {
    if (*value && !(**value > 0.0 && std::isfinite(**value))) {
      return fail(std::string(name) + " = " + sig3(**value) + " must be finite and > 0");
    }
  }
  if (!(time_limit > 0.0)) return fail("time_limit_s = " + sig3(time_limit) + " s must be > 0");
  return true;
}

namespace detail {

std::string explain_limits(const StrategyContext& c) {
  const MachineLimits& lim = c.space.limits;
  const double s = c.format.stroke, T = c.format.motion_time;
  // The least reachable value of each limited quantity alone: min z s.t. quantity / limit <= z.
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
  const int total = c.space.limit_count();
  const DurationSpace* space = &c.space;
  for (const Quantity& q : quantities) {
    if (!q.limit) continue;
    NlpProblem p = c.space.problem(1);
    p.inequality_count = q.rows;
    const int first = q.first, rows = q.rows;
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
    const MultiStartResult m = multi_start(p, starts, c, NlpOptions{});
    if (m.feasible && m.best.objective > 1.0 + 1e-6) {
      return std::string(q.name) + " = " + sig3(*q.limit) + " " + q.unit +
             " is not reachable: " + sig3(s * 1e3) + " mm in " + sig3(T) +
             " s with ramps >= " + sig3(c.options.min_ramp) + " s needs at least " +
             sig3(m.best.objective * *q.limit) + " " + q.unit + "; lengthen the motion or raise " +
             q.name;
    }
  }
  // Each limit alone is reachable: check them together from the strategy-free problem.
  NlpProblem p = c.space.problem();
  p.objective = [](const double*, double* grad) {
    if (grad != nullptr) std::fill(grad, grad + kSegments, 0.0);
    return 0.0;
  };
  p.inequality_count = total;
  p.inequalities = [space](const double* x, double* g, double* jac) {
    space->limit_constraints(x, g, jac, kSegments);
  };
  const MultiStartResult m = multi_start(p, as_vectors(c.space.starts(4)), c, NlpOptions{});
  if (!m.feasible) {
    return "the machine limits are each reachable but not together for " + sig3(s * 1e3) +
           " mm in " + sig3(T) + " s; raise one of them or lengthen the motion";
  }
  return {};
}

}  // namespace detail

PlanResult plan(const Format& format, Strategy strategy, const PlanOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const detail::Deadline deadline(options.time_limit);
  PlanResult r;
  r.strategy = strategy;
  r.model = make_sloshing_model(format, options.model);
  const double w1 = r.model.omega1();
  r.band_omega = {(1.0 - options.band) * w1, (1.0 + options.band) * w1};
  const Durations uniform = uniform_durations(format.motion_time);
  r.baseline = predict(r.model, uniform, format.stroke, options.rest_time);

  detail::StrategyContext c{format, options, r.model, detail::DurationSpace(format, options),
                            deadline};
  c.x_ref = std::abs(seven_segment_spectrum(uniform, format.stroke, w1));
  c.jerk_ref = SevenSegmentLaw(uniform, format.stroke).jerk_integral();
  c.eta_ref = r.baseline.nonlinear.motion.value;
  c.eta_motion_max = options.eta_motion_max.value_or(c.eta_ref);

  auto finish = [&](const detail::StrategyOutcome& o) {
    r.status = o.status;
    r.durations = o.durations;
    r.solver.name = o.solver;
    r.solver.iterations = o.evaluations;
    r.solver.starts = o.starts;
    r.solver.objective = o.objective;
  };

  auto run = [&](Strategy s, const std::vector<Durations>& seeds) -> detail::StrategyOutcome {
    switch (s) {
      case Strategy::kNotch:
        return detail::solve_notch(c);
      case Strategy::kMultiNotch:
        return detail::solve_multi_notch(c);
      case Strategy::kMinJerkBand:
        return detail::solve_min_jerk_band(c);
      case Strategy::kTimeDomain:
        return detail::solve_time_domain(c, seeds);
      default: {
        detail::StrategyOutcome o;
        o.status = SolveStatus::kOptimal;
        o.durations = uniform;
        o.solver = "none";
        return o;
      }
    }
  };
  // The spectral optima seed the time-domain starts (SPEC §5).
  auto spectral_seeds = [&](std::vector<detail::StrategyOutcome>* outcomes) {
    std::vector<Durations> seeds;
    for (Strategy s : {Strategy::kNotch, Strategy::kMultiNotch, Strategy::kMinJerkBand}) {
      detail::StrategyOutcome o = run(s, {});
      if (o.status == SolveStatus::kOptimal || o.status == SolveStatus::kAcceptable) {
        seeds.push_back(o.durations);
      }
      if (outcomes != nullptr) outcomes->push_back(std::move(o));
    }
    return seeds;
  };

  std::string detail_text;
  if (strategy == Strategy::kAuto) {
    std::vector<detail::StrategyOutcome> outcomes;
    outcomes.push_back(run(Strategy::kBaseline, {}));
    const std::vector<Durations> seeds = spectral_seeds(&outcomes);
    outcomes.push_back(run(Strategy::kTimeDomain, seeds));
    const Strategy order[] = {Strategy::kBaseline, Strategy::kNotch, Strategy::kMultiNotch,
                              Strategy::kMinJerkBand, Strategy::kTimeDomain};
    int evaluations = 0, starts = 0;
    for (std::size_t k = 0; k < outcomes.size(); ++k) {
      PlanCandidate cand;
      cand.strategy = order[k];
      cand.status = outcomes[k].status;
      cand.durations = outcomes[k].durations;
      cand.prediction = predict(r.model, cand.durations, format.stroke, options.rest_time);
      r.candidates.push_back(cand);
      evaluations += outcomes[k].evaluations;
      starts += outcomes[k].starts;
    }
    // SPEC §5: the lowest eta_rest among those whose eta_motion is within 5 % of the best
    // (ties: lower peak acceleration); infeasible or failed candidates do not compete.
    auto eligible = [](const PlanCandidate& k) {
      return k.status == SolveStatus::kOptimal || k.status == SolveStatus::kAcceptable ||
             k.status == SolveStatus::kTimeLimit;
    };
    double best_motion = INFINITY;
    for (const auto& k : r.candidates) {
      if (eligible(k)) best_motion = std::min(best_motion, k.prediction.nonlinear.motion.value);
    }
    std::size_t chosen = 0;
    bool have = false;
    for (std::size_t k = 0; k < r.candidates.size(); ++k) {
      const auto& cand = r.candidates[k];
      if (!eligible(cand) ||
          cand.prediction.nonlinear.motion.value > kAutoMotionSlack * best_motion) {
        continue;
      }
      if (!have) {
        chosen = k;
        have = true;
        continue;
      }
      const auto& cur = r.candidates[chosen];
      const double a = cand.prediction.nonlinear.rest.value,
                   b = cur.prediction.nonlinear.rest.value;
      const double peak_a = std::max(cand.prediction.kinematics.a_peak_positive,
                                     cand.prediction.kinematics.a_peak_negative);
      const double peak_b = std::max(cur.prediction.kinematics.a_peak_positive,
                                     cur.prediction.kinematics.a_peak_negative);
      if (a < b * (1.0 - kAutoTieTolerance) ||
          (std::abs(a - b) <= kAutoTieTolerance * b && peak_a < peak_b)) {
        chosen = k;
      }
    }
    r.candidates[chosen].chosen = true;
    detail::StrategyOutcome o = outcomes[chosen];
    o.evaluations = evaluations;
    o.starts = starts;
    finish(o);
    r.prediction = r.candidates[chosen].prediction;
    detail_text = "auto chose " + to_string(order[chosen]) +
                  " (lowest eta_rest among the candidates within 5 % of the best eta_motion)";
    if (!outcomes[chosen].detail.empty()) detail_text += "; " + outcomes[chosen].detail;
  } else {
    std::vector<Durations> seeds;
    if (strategy == Strategy::kTimeDomain) seeds = spectral_seeds(nullptr);
    const detail::StrategyOutcome o = run(strategy, seeds);
    finish(o);
    detail_text = o.detail;
    r.prediction = predict(r.model, r.durations, format.stroke, options.rest_time);
  }

  const SevenSegmentLaw law(r.durations, format.stroke);
  r.A = law.A();
  r.B = law.B();
  r.solver.solve_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();

  // The message: what happened, then what the law does.
  std::string message;
  switch (r.status) {
    case SolveStatus::kOptimal:
    case SolveStatus::kAcceptable:
      message = to_string(strategy) + " " + to_string(r.status);
      break;
    case SolveStatus::kTimeLimit:
      message = "the time budget of " + sig3(options.time_limit) +
                " s ran out; returning the best admissible point found";
      break;
    case SolveStatus::kInfeasible: {
      const std::string limits = c.space.limit_count() > 0 ? detail::explain_limits(c) : "";
      message = !limits.empty()
                    ? limits
                    : (!detail_text.empty() ? detail_text : "the constraints cannot be met");
      detail_text.clear();
      message += "; the durations returned are the least infeasible found, not a solution";
      break;
    }
    case SolveStatus::kFailed:
      message = "the solver failed; the durations returned are the uniform law";
      r.durations = uniform;
      break;
  }
  if (!detail_text.empty()) message += ": " + detail_text;
  message += ". " + summary_sentence(r.prediction, r.baseline);
  r.message = message;

  r.warnings = validity_warnings(
      format,
      std::max(r.prediction.kinematics.a_peak_positive, r.prediction.kinematics.a_peak_negative),
      r.prediction.linear.motion.value, r.prediction.nonlinear.motion.value);
  if (strategy == Strategy::kTimeDomain && r.usable()) {
    // The constraint re-verified on the dense accurate simulation.
    const bool motion = options.objective == TimeDomainObjective::kMotion;
    const double verified =
        motion ? r.prediction.nonlinear.rest.value : r.prediction.nonlinear.motion.value;
    const double bound = motion ? options.eta_rest_max : c.eta_motion_max;
    if (verified > bound * (1.0 + 1e-6)) {
      r.warnings.push_back("verification: the dense simulation gives " +
                           std::string(motion ? "eta_rest " : "eta_motion ") +
                           detail::fixed(verified * 1e3, 6) + " mm, above the bound " +
                           detail::fixed(bound * 1e3, 6) + " mm");
    }
  }
  return r;
}

}  // namespace slosh
