// The one place NLopt is used.

#include <nlopt.hpp>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "slosh/core/solve/nlp_solver.hpp"

namespace slosh {

namespace {

struct Context {
  const NlpProblem* problem;
  const NlpOptions* options;
  nlopt::opt* opt{nullptr};
  int evaluations{0};
  bool abandoned{false};
  bool stopped{false};
};

/// True when the caller's stop flag is set: the run is ended at once (force_stop) and reported
/// as out of time.
bool stop_requested(Context* c) {
  if (c->options->stop == nullptr || !c->options->stop->load(std::memory_order_relaxed)) {
    return false;
  }
  if (!c->stopped) {
    c->stopped = true;
    c->opt->force_stop();
  }
  return true;
}

double objective_callback(unsigned n, const double* x, double* grad, void* data) {
  auto* c = static_cast<Context*>(data);
  ++c->evaluations;
  if (stop_requested(c)) {
    // Not evaluated: the run ends here.
    if (grad != nullptr) std::fill(grad, grad + n, 0.0);
    return 0.0;
  }
  // The value first: an abandon test may read it (multi_start's record of the last value).
  const double f = c->problem->objective(x, grad);
  if (c->options->abandon && !c->abandoned && c->options->abandon(x)) {
    c->abandoned = true;
    c->opt->force_stop();
  }
  return f;
}

struct EqualityData {
  const NlpProblem::LinearEquality* equality;
};

double equality_callback(unsigned n, const double* x, double* grad, void* data) {
  const auto* e = static_cast<EqualityData*>(data)->equality;
  double value = -e->b;
  for (unsigned i = 0; i < n; ++i) {
    value += e->a[i] * x[i];
    if (grad != nullptr) grad[i] = e->a[i];
  }
  return value;
}

void inequality_callback(unsigned m, double* result, unsigned n, const double* x, double* grad,
                         void* data) {
  auto* c = static_cast<Context*>(data);
  if (stop_requested(c)) {
    // Not evaluated: the run ends here.
    std::fill(result, result + m, 0.0);
    if (grad != nullptr) std::fill(grad, grad + static_cast<std::size_t>(m) * n, 0.0);
    return;
  }
  c->problem->inequalities(x, result, grad);
}

}  // namespace

NlpResult solve_with_nlopt(const NlpProblem& problem, const std::vector<double>& x0,
                           const NlpOptions& options) {
  const auto n = static_cast<unsigned>(problem.size());
  NlpResult out;
  out.x = x0;
  Context context{&problem, &options};
  std::vector<EqualityData> equality_data;
  equality_data.reserve(problem.equalities.size());
  try {
    nlopt::opt opt(nlopt::LD_SLSQP, n);
    context.opt = &opt;
    opt.set_lower_bounds(problem.lower);
    opt.set_upper_bounds(problem.upper);
    opt.set_min_objective(objective_callback, &context);
    for (const auto& e : problem.equalities) {
      equality_data.push_back({&e});
      opt.add_equality_constraint(equality_callback, &equality_data.back(),
                                  options.constraint_tolerance);
    }
    if (problem.inequality_count > 0) {
      opt.add_inequality_mconstraint(
          inequality_callback, &context,
          std::vector<double>(problem.inequality_count, options.constraint_tolerance));
    }
    opt.set_ftol_rel(options.tolerance);
    opt.set_xtol_rel(options.tolerance);
    opt.set_maxeval(options.max_iterations);
    if (options.time_limit > 0.0) opt.set_maxtime(options.time_limit);
    if (options.stop_value) opt.set_stopval(*options.stop_value);
    for (unsigned i = 0; i < n; ++i) {
      out.x[i] = std::clamp(out.x[i], problem.lower[i], problem.upper[i]);
    }
    const nlopt::result r = opt.optimize(out.x, out.objective);
    switch (r) {
      case nlopt::SUCCESS:
      case nlopt::FTOL_REACHED:
      case nlopt::XTOL_REACHED:
      case nlopt::STOPVAL_REACHED:
        out.status = SolveStatus::kOptimal;
        break;
      case nlopt::MAXEVAL_REACHED:
        // Not converged: the point is kept (the caller judges its feasibility), the status says
        // the solver did not finish.
        out.status = SolveStatus::kFailed;
        break;
      case nlopt::MAXTIME_REACHED:
        out.status = SolveStatus::kTimeLimit;
        break;
      default:
        out.status = SolveStatus::kFailed;
    }
    out.message = std::string("nlopt SLSQP: result code ") + std::to_string(static_cast<int>(r)) +
                  (r == nlopt::MAXEVAL_REACHED ? " (evaluation limit reached)" : "");
  } catch (const nlopt::forced_stop&) {
    if (context.stopped) {
      out.status = SolveStatus::kTimeLimit;
      out.message = "nlopt SLSQP: stopped (the caller no longer waits for it)";
    } else {
      out.status = SolveStatus::kFailed;
      out.message = "nlopt SLSQP: abandoned (an optimum another start found)";
    }
  } catch (const nlopt::roundoff_limited&) {
    out.status = SolveStatus::kAcceptable;
    out.message = "nlopt SLSQP: stopped by round-off";
  } catch (const std::exception& e) {
    out.status = SolveStatus::kFailed;
    out.message = std::string("nlopt SLSQP: ") + e.what();
  }
  out.evaluations = context.evaluations;
  out.abandoned = context.abandoned && !context.stopped;
  out.objective = problem.objective(out.x.data(), nullptr);
  out.max_violation = max_violation(problem, out.x);
  // SLSQP does not certify infeasibility: judge the returned point.
  if (out.max_violation > 10.0 * options.constraint_tolerance &&
      out.status != SolveStatus::kTimeLimit) {
    out.status = SolveStatus::kInfeasible;
  }
  return out;
}

}  // namespace slosh
