// The one place Ipopt is used.

#include <coin/IpIpoptApplication.hpp>
#include <coin/IpTNLP.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

#include "slosh/core/solve/nlp_solver.hpp"

namespace slosh {

namespace {

using Ipopt::Index;
using Ipopt::Number;

// Constraints: the linear equalities first (rows 0..e-1), then the inequalities g(x) <= 0.
// The Jacobian is stored dense.
class Adapter : public Ipopt::TNLP {
 public:
  using Clock = std::chrono::steady_clock;

  Adapter(const NlpProblem& problem, const std::vector<double>& x0,
          std::optional<Clock::time_point> deadline, const std::atomic<bool>* stop)
      : deadline_(deadline),
        stop_(stop),
        problem_(problem),
        x0_(x0),
        n_(problem.size()),
        e_(static_cast<int>(problem.equalities.size())),
        m_(e_ + problem.inequality_count) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = n_;
    m = m_;
    nnz_jac_g = n_ * m_;
    nnz_h_lag = 0;  // limited-memory quasi-Newton
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l,
                       Number* g_u) override {
    for (Index i = 0; i < n; ++i) {
      x_l[i] = problem_.lower[i];
      x_u[i] = problem_.upper[i];
    }
    for (Index j = 0; j < m; ++j) {
      if (j < e_) {
        g_l[j] = g_u[j] = problem_.equalities[j].b;
      } else {
        g_l[j] = -2e19;  // Ipopt's "minus infinity"
        g_u[j] = 0.0;
      }
    }
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool, Number*, Number*, Index, bool,
                          Number*) override {
    if (init_x) {
      for (Index i = 0; i < n; ++i) x[i] = x0_[i];
    }
    return true;
  }

  bool eval_f(Index, const Number* x, bool, Number& obj_value) override {
    ++evaluations_;
    obj_value = problem_.objective(x, nullptr);
    return std::isfinite(obj_value);
  }

  bool eval_grad_f(Index, const Number* x, bool, Number* grad_f) override {
    problem_.objective(x, grad_f);
    return true;
  }

  bool eval_g(Index n, const Number* x, bool, Index, Number* g) override {
    for (Index j = 0; j < e_; ++j) {
      double ax = 0.0;
      for (Index i = 0; i < n; ++i) ax += problem_.equalities[j].a[i] * x[i];
      g[j] = ax;
    }
    if (problem_.inequality_count > 0) problem_.inequalities(x, g + e_, nullptr);
    return true;
  }

  bool eval_jac_g(Index n, const Number* x, bool, Index m, Index, Index* i_row, Index* j_col,
                  Number* values) override {
    if (values == nullptr) {
      for (Index j = 0; j < m; ++j) {
        for (Index i = 0; i < n; ++i) {
          i_row[j * n + i] = j;
          j_col[j * n + i] = i;
        }
      }
      return true;
    }
    for (Index j = 0; j < e_; ++j) {
      for (Index i = 0; i < n; ++i) values[j * n + i] = problem_.equalities[j].a[i];
    }
    if (problem_.inequality_count > 0) {
      std::vector<double> g(problem_.inequality_count);
      problem_.inequalities(x, g.data(), values + static_cast<std::ptrdiff_t>(e_) * n);
    }
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*,
                         const Number*, Index, const Number*, const Number*, Number obj_value,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x_final_.assign(x, x + n);
    objective_ = obj_value;
  }

  // Called once per iteration: the wall-clock budget (Ipopt's own max_cpu_time counts CPU time)
  // and the caller's stop flag.
  bool intermediate_callback(Ipopt::AlgorithmMode, Index, Number, Number, Number, Number, Number,
                             Number, Number, Number, Index, const Ipopt::IpoptData*,
                             Ipopt::IpoptCalculatedQuantities*) override {
    if ((deadline_ && Clock::now() >= *deadline_) ||
        (stop_ != nullptr && stop_->load(std::memory_order_relaxed))) {
      out_of_time_ = true;
      return false;
    }
    return true;
  }

  std::vector<double> x_final_;
  double objective_{};
  int evaluations_{0};
  bool out_of_time_{false};
  std::optional<Clock::time_point> deadline_;
  const std::atomic<bool>* stop_;

 private:
  const NlpProblem& problem_;
  std::vector<double> x0_;
  int n_, e_, m_;
};

SolveStatus translate(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded:
      return SolveStatus::kOptimal;
    case Ipopt::Solved_To_Acceptable_Level:
    case Ipopt::Feasible_Point_Found:
      return SolveStatus::kAcceptable;
    case Ipopt::Infeasible_Problem_Detected:
      return SolveStatus::kInfeasible;
    case Ipopt::Maximum_CpuTime_Exceeded:
    case Ipopt::User_Requested_Stop:  // only intermediate_callback stops: budget or stop flag
      return SolveStatus::kTimeLimit;
    default:
      return SolveStatus::kFailed;
  }
}

// Debian's Ipopt factorises with sequential MUMPS, whose Fortran state is process-global and not
// thread-safe: two solves at once corrupt it and abort the process. Every Ipopt solve in the
// process holds this lock from the application's creation to its destruction.
std::timed_mutex ipopt_mutex;

}  // namespace

NlpResult solve_with_ipopt(const NlpProblem& problem, const std::vector<double>& x0,
                           const NlpOptions& options) {
  NlpResult out;
  out.x = x0;
  std::optional<Adapter::Clock::time_point> deadline;
  if (options.time_limit > 0.0) {
    deadline = Adapter::Clock::now() + std::chrono::duration_cast<Adapter::Clock::duration>(
                                           std::chrono::duration<double>(options.time_limit));
  }
  // Waiting for another Ipopt solve counts against this one's budget.
  std::unique_lock<std::timed_mutex> lock(ipopt_mutex, std::defer_lock);
  if (deadline ? !lock.try_lock_until(*deadline) : (lock.lock(), false)) {
    out.status = SolveStatus::kTimeLimit;
    out.objective = problem.objective(out.x.data(), nullptr);
    out.max_violation = max_violation(problem, out.x);
    out.message = "ipopt: the time budget ran out waiting for another Ipopt solve";
    return out;
  }
  Ipopt::SmartPtr<Adapter> adapter = new Adapter(problem, x0, deadline, options.stop);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");  // no banner
  app->Options()->SetStringValue("hessian_approximation", "limited-memory");
  app->Options()->SetNumericValue("tol", options.tolerance);
  app->Options()->SetNumericValue("constr_viol_tol", options.constraint_tolerance);
  app->Options()->SetIntegerValue("max_iter", options.max_iterations);
  const Ipopt::ApplicationReturnStatus init = app->Initialize();
  if (init != Ipopt::Solve_Succeeded) {
    out.message = "ipopt: initialisation failed";
    return out;
  }
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(adapter);
  out.status = translate(status);
  out.message = status == Ipopt::Solve_Succeeded ? std::string("ipopt: converged")
                : status == Ipopt::Solved_To_Acceptable_Level
                    ? std::string("ipopt: solved to its acceptable tolerance only")
                : status == Ipopt::Feasible_Point_Found
                    ? std::string("ipopt: stopped at a feasible point")
                    : "ipopt: return status " + std::to_string(static_cast<int>(status));
  if (!adapter->x_final_.empty()) out.x = adapter->x_final_;
  out.evaluations = adapter->evaluations_;
  out.objective = problem.objective(out.x.data(), nullptr);
  out.max_violation = max_violation(problem, out.x);
  // A converged point within Ipopt's own relaxation of the bounds is a solution (the multi-start
  // judges it by the same tolerance): only beyond it is the point infeasible.
  if (out.usable() &&
      out.max_violation > std::max(kIpoptRelaxedViolation, 10.0 * options.constraint_tolerance)) {
    out.status = SolveStatus::kInfeasible;
  }
  return out;
}

}  // namespace slosh
