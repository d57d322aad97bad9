#include "slosh/core/model/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "model/calibration_response.hpp"
#include "solve/least_squares.hpp"
#include "text.hpp"

namespace slosh {

namespace {

constexpr std::size_t kP = kCalibrationParameters;
using Values = std::array<double, kP>;

SloshingModel base_model(const Format& format, ModelOptions base) {
  base.omega_scale = 1.0;
  base.height_gain = 1.0;
  return make_sloshing_model(format, base);
}

// The rest window a move's response is integrated over: the peaks' window and every series
// sample at the smallest offset allowed.
double horizon(const MeasuredMove& move) {
  double rest = 0.01;
  if (move.peaks) rest = std::max(rest, move.peaks->rest_window);
  if (move.series && !move.series->t.empty()) {
    const MeasuredSeries& s = move.series.value();
    const double earliest_offset = s.offset - (s.fit_offset ? s.max_offset : 0.0);
    rest = std::max(rest, s.t.back() - earliest_offset - move.law.duration() + 0.01);
  }
  return rest;
}

// Residuals and the full Jacobian (4 parameter columns + one per fitted offset).
struct Evaluation {
  std::vector<double> r;
  std::vector<std::vector<double>> J;
  std::vector<std::size_t> move_end;  // residual index after each move
};

Evaluation evaluate(const SloshingModel& model, const std::vector<MeasuredMove>& moves,
                    const Values& p, const std::vector<double>& offsets,
                    const NonlinearOptions& nonlinear) {
  std::size_t n_offsets = 0;
  for (const MeasuredMove& m : moves) n_offsets += m.series && m.series->fit_offset ? 1 : 0;
  Evaluation e;
  std::size_t offset_col = kP;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const MeasuredMove& move = moves[i];
    detail::CalibrationResponse response(model, move.law, horizon(move), nonlinear);
    response.compute({p[0], p[1], p[2]}, p[3]);
    // col: the offset column of the move, 0 for none (offset columns start at kP).
    auto push = [&](const detail::EtaSample& s, double measured, std::size_t col) {
      e.r.push_back(s.value - measured);
      std::vector<double> row(kP + n_offsets, 0.0);
      for (std::size_t j = 0; j < 3; ++j) row[j] = s.gradient[j];
      row[3] = s.value / p[3];
      if (col != 0) row[col] = -s.rate;
      e.J.push_back(std::move(row));
    };
    if (move.series) {
      const MeasuredSeries& s = move.series.value();
      const std::size_t col = s.fit_offset ? offset_col++ : 0;
      for (std::size_t k = 0; k < s.t.size(); ++k) {
        push(response.eta_at(s.t[k] - offsets[i]), s.eta[k], col);
      }
    }
    if (move.peaks) {
      const double T = move.law.duration();
      if (move.peaks->eta_motion) push(response.abs_peak(0.0, T), *move.peaks->eta_motion, 0);
      if (move.peaks->eta_rest) {
        push(response.abs_peak(T, T + move.peaks->rest_window), *move.peaks->eta_rest, 0);
      }
    }
    e.move_end.push_back(e.r.size());
  }
  return e;
}

double rms(const std::vector<double>& r, std::size_t begin, std::size_t end) {
  if (end <= begin) return 0.0;
  double s = 0.0;
  for (std::size_t k = begin; k < end; ++k) s += r[k] * r[k];
  return std::sqrt(s / static_cast<double>(end - begin));
}

}  // namespace

std::array<ParameterSetting, kCalibrationParameters> default_parameter_settings() {
  return {{{true, std::nullopt, 0.5, 2.0},
           {true, std::nullopt, 0.0, 0.3},
           {true, std::nullopt, 0.0, 2.0},
           {true, std::nullopt, 0.2, 5.0}}};
}

void calibration_residuals(const Format& format, const ModelOptions& base,
                           const std::vector<MeasuredMove>& moves,
                           const std::array<double, kCalibrationParameters>& p,
                           const std::vector<double>& offsets, const NonlinearOptions& nonlinear,
                           std::vector<double>* residuals,
                           std::vector<std::vector<double>>* jacobian) {
  Evaluation e = evaluate(base_model(format, base), moves, p, offsets, nonlinear);
  *residuals = std::move(e.r);
  if (jacobian != nullptr) *jacobian = std::move(e.J);
}

namespace {

// The fit's working state: which columns are free, their bounds, the current values.
struct Problem {
  SloshingModel model;
  const std::vector<MeasuredMove>* moves{};
  NonlinearOptions nonlinear;
  Values prior{};
  Values value{};
  std::vector<double> offsets;           // per move (initial values for non-fitted)
  std::vector<double> offset_init;       // per move
  std::vector<std::size_t> offset_move;  // move of each offset column
  std::vector<bool> free;                // per column (4 + offsets)
  std::vector<double> lower, upper;      // per column
  std::function<bool()> stop;

  [[nodiscard]] std::vector<std::size_t> free_columns() const {
    std::vector<std::size_t> c;
    for (std::size_t j = 0; j < free.size(); ++j)
      if (free[j]) c.push_back(j);
    return c;
  }
  void set(const std::vector<std::size_t>& cols, const Eigen::VectorXd& x) {
    for (std::size_t k = 0; k < cols.size(); ++k) {
      const std::size_t j = cols[k];
      const double v = x[static_cast<Eigen::Index>(k)];
      if (j < kP) {
        value[j] = v;
      } else {
        offsets[offset_move[j - kP]] = v;
      }
    }
  }
  [[nodiscard]] double column_value(std::size_t j) const {
    return j < kP ? value[j] : offsets[offset_move[j - kP]];
  }
  [[nodiscard]] Evaluation run() const {
    return evaluate(model, *moves, value, offsets, nonlinear);
  }
};

Eigen::MatrixXd select(const Evaluation& e, const std::vector<std::size_t>& cols) {
  Eigen::MatrixXd J(static_cast<Eigen::Index>(e.r.size()), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t i = 0; i < e.r.size(); ++i)
    for (std::size_t k = 0; k < cols.size(); ++k)
      J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = e.J[i][cols[k]];
  return J;
}

Eigen::VectorXd residual_vector(const Evaluation& e) {
  return Eigen::Map<const Eigen::VectorXd>(e.r.data(), static_cast<Eigen::Index>(e.r.size()));
}

detail::LeastSquaresOutcome fit(Problem& pb, int max_iterations) {
  const std::vector<std::size_t> cols = pb.free_columns();
  const auto n = static_cast<Eigen::Index>(cols.size());
  detail::BoundedLeastSquares ls;
  ls.lower.resize(n);
  ls.upper.resize(n);
  Eigen::VectorXd x0(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const std::size_t j = cols[static_cast<std::size_t>(k)];
    ls.lower[k] = pb.lower[j];
    ls.upper[k] = pb.upper[j];
    x0[k] = pb.column_value(j);
  }
  ls.evaluate = [&pb, &cols](const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd& J) {
    Problem trial = pb;
    trial.set(cols, x);
    const Evaluation e = trial.run();
    r = residual_vector(e);
    J = select(e, cols);
    return true;
  };
  detail::LeastSquaresOptions options;
  options.max_iterations = max_iterations;
  options.stop = pb.stop;
  detail::LeastSquaresOutcome out = detail::solve_bounded_least_squares(ls, x0, options);
  pb.set(cols, out.x);
  return out;
}

std::string column_name(const Problem& pb, std::size_t j) {
  if (j < kP) return std::string(name_of(static_cast<CalibrationParameter>(j)));
  return "offset of move " + std::to_string(pb.offset_move[j - kP] + 1);
}

}  // namespace

namespace {

Eigen::VectorXd widths(const Problem& pb, const std::vector<std::size_t>& cols) {
  Eigen::VectorXd w(static_cast<Eigen::Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k)
    w[static_cast<Eigen::Index>(k)] = pb.upper[cols[k]] - pb.lower[cols[k]];
  return w;
}

// The least identifiable direction of the bound-scaled parameters: when J^T J is singular in it
// (1e-12 relative) or its standard deviation exceeds `fraction` of the box, the column to hold
// (the direction's largest component) and the sentence that says so.
std::optional<std::size_t> unidentifiable(const Problem& pb, const std::vector<std::size_t>& cols,
                                          const Eigen::MatrixXd& J, double sigma, double fraction,
                                          std::string* sentence) {
  if (cols.empty()) return std::nullopt;
  const Eigen::MatrixXd Js = J * widths(pb, cols).asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Js.transpose() * Js);
  const double lam = es.eigenvalues()[0];
  const double lmax = es.eigenvalues().maxCoeff();
  const bool singular = !(lam > 1e-12 * lmax);
  const double sd = singular ? HUGE_VAL : sigma / std::sqrt(lam);
  if (!singular && !(sd > fraction)) return std::nullopt;
  const Eigen::VectorXd u = es.eigenvectors().col(0);
  Eigen::Index worst = 0;
  u.cwiseAbs().maxCoeff(&worst);
  std::string names;
  std::size_t count = 0;
  for (Eigen::Index k = 0; k < u.size(); ++k) {
    if (std::abs(u[k]) < 0.3) continue;
    names += (count++ == 0 ? "" : " and ") + column_name(pb, cols[static_cast<std::size_t>(k)]);
  }
  const std::size_t held = cols[static_cast<std::size_t>(worst)];
  *sentence =
      (count > 1 ? names + " cannot be separated by these moves"
                 : names + " is not determined by these moves") +
      (singular ? " (J^T J is singular in that direction)"
                : " (standard deviation " + detail::sig3(100.0 * sd) + " % of its bound box)") +
      ": " + column_name(pb, held) + " is held at its prior " +
      detail::sig3(held < kP ? pb.prior[held] : pb.offset_init[pb.offset_move[held - kP]]) +
      "; add moves that excite it (faster or larger moves, a measured series)";
  return held;
}

Problem make_problem(const Format& format, const ModelOptions& base,
                     const std::vector<MeasuredMove>& moves, const CalibrationSettings& settings) {
  Problem pb;
  pb.model = base_model(format, base);
  pb.moves = &moves;
  pb.nonlinear = settings.nonlinear;
  pb.stop = settings.stop;
  const Values own{1.0, pb.model.zeta, base.alpha, 1.0};
  for (std::size_t j = 0; j < kP; ++j) {
    const ParameterSetting& s = settings.parameters[j];
    pb.prior[j] = s.initial.value_or(own[j]);
    pb.free.push_back(s.fit);
    pb.lower.push_back(s.lower);
    pb.upper.push_back(s.upper);
  }
  pb.value = pb.prior;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const auto& s = moves[i].series;
    pb.offsets.push_back(s ? s->offset : 0.0);
    if (s && s->fit_offset) {
      pb.offset_move.push_back(i);
      pb.free.push_back(true);
      pb.lower.push_back(s->offset - s->max_offset);
      pb.upper.push_back(s->offset + s->max_offset);
    }
  }
  pb.offset_init = pb.offsets;
  return pb;
}

double residual_sigma(const Evaluation& e, std::size_t p) {
  const std::size_t m = e.r.size();
  if (m <= p) return 0.0;
  double ssr = 0.0;
  for (double r : e.r) ssr += r * r;
  return std::sqrt(ssr / static_cast<double>(m - p));
}

void report(const Problem& pb, const Evaluation& before, const Evaluation& after,
            const std::vector<std::size_t>& cols, const Eigen::VectorXd& se,
            CalibrationResult* out) {
  for (std::size_t j = 0; j < kP; ++j) {
    FittedParameter& f = out->parameters[j];
    f.prior = pb.prior[j];
    f.value = pb.value[j];
    f.at_bound = pb.free[j] && (f.value <= pb.lower[j] || f.value >= pb.upper[j]);
  }
  std::size_t begin = 0;
  for (std::size_t i = 0; i < pb.moves->size(); ++i) {
    MoveFit m;
    m.name = (*pb.moves)[i].name;
    m.residuals = after.move_end[i] - begin;
    m.rms_before = rms(before.r, begin, before.move_end[i]);
    m.rms_after = rms(after.r, begin, after.move_end[i]);
    const auto& s = (*pb.moves)[i].series;
    if (s && s->fit_offset) m.offset = pb.offsets[i];
    out->moves.push_back(std::move(m));
    begin = after.move_end[i];
  }
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const std::size_t j = cols[k];
    const double v = se[static_cast<Eigen::Index>(k)];
    if (j < kP) {
      out->parameters[j].standard_error = v;
    } else {
      out->moves[pb.offset_move[j - kP]].offset_standard_error = v;
    }
  }
}

}  // namespace

CalibrationResult calibrate(const Format& format, const ModelOptions& base,
                            const std::vector<MeasuredMove>& moves,
                            const CalibrationSettings& settings) {
  CalibrationResult out;
  Problem pb = make_problem(format, base, moves, settings);
  for (std::size_t j = 0; j < kP; ++j)
    out.parameters[j].state = pb.free[j] ? ParameterState::kFitted : ParameterState::kFixed;
  const Evaluation before = pb.run();
  detail::LeastSquaresOutcome ls;
  std::vector<std::size_t> cols;
  Eigen::MatrixXd J;
  double sigma = 0.0;
  Evaluation after;
  for (;;) {
    ls = fit(pb, settings.max_iterations);
    out.iterations += ls.iterations;
    cols = pb.free_columns();
    after = pb.run();
    J = select(after, cols);
    sigma = residual_sigma(after, cols.size());
    if (ls.status == detail::LeastSquaresStatus::kStopped) break;
    std::string sentence;
    const auto held = unidentifiable(pb, cols, J, sigma, settings.identifiable_fraction, &sentence);
    if (!held) break;
    out.identifiability.push_back(sentence);
    pb.free[*held] = false;
    if (*held < kP) {
      pb.value[*held] = pb.prior[*held];
      out.parameters[*held].state = ParameterState::kUnidentifiable;
    } else {
      const std::size_t move = pb.offset_move[*held - kP];
      pb.offsets[move] = pb.offset_init[move];
    }
  }
  if (!cols.empty() && after.r.size() <= cols.size()) {
    out.identifiability.push_back(
        std::to_string(after.r.size()) + " measured values for " + std::to_string(cols.size()) +
        " fitted values: no degree of freedom is left, so the fit interpolates and standard "
        "errors cannot be estimated; measure more moves or fit fewer parameters");
  }
  Eigen::VectorXd se = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(cols.size()));
  if (!cols.empty() && sigma > 0.0) {
    const Eigen::VectorXd w = widths(pb, cols);
    const Eigen::MatrixXd Js = J * w.asDiagonal();
    const Eigen::MatrixXd inv =
        (Js.transpose() * Js)
            .ldlt()
            .solve(Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(cols.size()),
                                             static_cast<Eigen::Index>(cols.size())));
    se = sigma * inv.diagonal().cwiseSqrt().cwiseProduct(w);
  }
  report(pb, before, after, cols, se, &out);
  out.sigma = sigma;
  switch (ls.status) {
    case detail::LeastSquaresStatus::kConverged:
      out.status = CalibrationStatus::kConverged;
      break;
    case detail::LeastSquaresStatus::kMaxIterations:
      out.status = CalibrationStatus::kMaxIterations;
      break;
    case detail::LeastSquaresStatus::kStopped:
      out.status = CalibrationStatus::kTimeLimit;
      break;
    case detail::LeastSquaresStatus::kFailed:
      out.status = CalibrationStatus::kFailed;
      break;
  }
  out.model = base;
  out.model.omega_scale = pb.value[0];
  out.model.damping = DampingCorrelation::kExplicit;
  out.model.explicit_zeta = pb.value[1];
  out.model.alpha = pb.value[2];
  out.model.height_gain = pb.value[3];
  return out;
}

}  // namespace slosh
