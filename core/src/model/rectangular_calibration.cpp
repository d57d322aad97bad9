#include "slosh/core/model/rectangular_calibration.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Dense>

#include "model/rectangular_direction_dual.hpp"
#include "slosh/core/constants.hpp"
#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/response/peak_finder.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "solve/least_squares.hpp"

namespace slosh {

namespace {

/// The fitted parameters, in this order: each direction's omega scale and zeta, then the gain;
/// the columns after them are the series offsets fitted, one per move that asks, in move order.
enum Column : std::size_t { kOmegaL, kZetaL, kOmegaW, kZetaW, kGain, kColumns };
using Values = std::array<double, kColumns>;
/// Every column's value: the parameters, then the fitted offsets.
using Columns = std::vector<double>;

constexpr std::array<const char*, kColumns> kNames{"the length's omega_scale", "the length's zeta",
                                                   "the width's omega_scale", "the width's zeta",
                                                   "height_gain"};

bool of_length(std::size_t column) {
  return column == kOmegaL || column == kZetaL;
}
bool of_width(std::size_t column) {
  return column == kOmegaW || column == kZetaW;
}

std::string sig3(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// The rest window a move's response is integrated over (as calibrate()'s horizon): the peaks'
// window and every series sample at the smallest offset allowed.
double horizon(const MeasuredMove& move) {
  double rest = 0.01;
  if (move.peaks) rest = std::max(rest, move.peaks->rest_window);
  if (move.series && !move.series->t.empty()) {
    const MeasuredSeries& s = *move.series;
    const double earliest_offset = s.offset - (s.fit_offset ? s.max_offset : 0.0);
    rest = std::max(rest, s.t.back() - earliest_offset - move.law.duration() + 0.01);
  }
  return rest;
}

/// A wave height with its gradient over the parameters and its rate in time.
struct Sample {
  double value{};
  Values gradient{};
  double rate{};  ///< [m/s]
};

/// One driven direction of a move as simulate models it, in dual numbers.
struct DirectionResponse {
  detail::RectangularDirectionDual response;
  std::size_t omega;  ///< its omega column (zeta's is the next)
};

/// `s` (height gain 1) as a Sample of the direction's columns, times `gain` and `sign`.
Sample direction_sample(const DirectionResponse& d, const detail::DirectionSample& s, double gain,
                        double sign) {
  Sample out;
  out.value = sign * gain * s.value;
  out.gradient[d.omega] = sign * gain * s.gradient[0];
  out.gradient[d.omega + 1] = sign * gain * s.gradient[1];
  out.gradient[kGain] = sign * s.value;
  out.rate = sign * gain * s.rate;
  return out;
}

Sample operator+(Sample a, const Sample& b) {
  a.value += b.value;
  for (std::size_t j = 0; j < kColumns; ++j) a.gradient[j] += b.gradient[j];
  a.rate += b.rate;
  return a;
}

Sample abs_of(Sample s) {
  if (s.value < 0.0) {
    s.value = -s.value;
    for (double& g : s.gradient) g = -g;
    s.rate = -s.rate;
  }
  return s;
}

/// The wall height simulate's peaks search (RectangularNonlinearDirection::wall for one
/// direction; highest_corner, |odd_L| + |odd_W| + |even_L + even_W|, for both;
/// RectangularLinearResponse's |eta| or |eta_L| + |eta_W| where the nonlinear model does not
/// hold, the second modes then being 0).
Sample wall_at(const std::vector<DirectionResponse>& dirs, double t, double gain) {
  Sample odd, even;
  for (const DirectionResponse& d : dirs) {
    odd = odd + abs_of(direction_sample(d, d.response.odd(t), gain, 1.0));
    even = even + direction_sample(d, d.response.even(t), gain, 1.0);
  }
  return odd + abs_of(even);
}

/// simulate's series value at t (RectangularSeries::eta_nonlinear, or eta_linear where the
/// nonlinear model does not hold, the second modes then being 0): the signed wall ahead,
/// odd + even, when one direction moves; the highest corner (wall_at) when both do.
Sample series_at(const std::vector<DirectionResponse>& dirs, double t, double gain) {
  if (dirs.size() == 1) {
    const DirectionResponse& d = dirs[0];
    return direction_sample(d, d.response.odd(t), gain, 1.0) +
           direction_sample(d, d.response.even(t), gain, 1.0);
  }
  return wall_at(dirs, t, gain);
}

/// The largest wall height over [a, b] located as simulate locates it (sampled at its step,
/// refined by golden section), with its gradient at that time (exact where the peak is a
/// smooth maximum: the time's own derivative multiplies a zero slope).
Sample peak_of(const std::vector<DirectionResponse>& dirs, double a, double b, double gain) {
  double step = kMaxPeakStep;
  for (const DirectionResponse& d : dirs) step = std::min(step, d.response.peak_step());
  const Peak p =
      find_max([&dirs, gain](double t) { return wall_at(dirs, t, gain).value; }, a, b, step);
  return wall_at(dirs, p.time, gain);
}

struct Evaluation {
  std::vector<double> r;
  std::vector<std::vector<double>> J;  // per residual, every column
  std::vector<std::size_t> move_end;
};

struct Problem {
  RectangularModel tank;  // the unscaled tank (omega_scale 1, gain 1)
  const std::vector<RectangularMeasuredMove>* moves{};
  NonlinearOptions nonlinear;
  /// Per move: whether simulate's nonlinear model holds for it (judged on the prior tank).
  std::vector<bool> nonlinear_holds;
  /// Per move: its offset column (kColumns on), or 0 when its series' offset is given.
  std::vector<std::size_t> offset_column;
  /// Per column (the parameters, then the offsets): start value and prior, bounds, fitted.
  Columns prior, lower, upper;
  std::vector<bool> free;

  [[nodiscard]] std::size_t columns() const { return prior.size(); }

  [[nodiscard]] Evaluation run(const Columns& v) const {
    Evaluation e;
    for (std::size_t i = 0; i < moves->size(); ++i) {
      const RectangularMeasuredMove& m = (*moves)[i];
      std::vector<DirectionResponse> dirs;
      const AxisComponents c = axis_components(m.orientation_deg);
      for (const auto& [component, base, omega] :
           {std::tuple{c.along_length, &tank.along_length, std::size_t{kOmegaL}},
            std::tuple{c.along_width, &tank.along_width, std::size_t{kOmegaW}}}) {
        if (component == 0.0) continue;
        dirs.push_back(
            {detail::RectangularDirectionDual(*base, m.move.law.scaled(component), horizon(m.move),
                                              nonlinear, nonlinear_holds[i]),
             omega});
        dirs.back().response.compute(v[omega], v[omega + 1]);
      }
      // col: the move's offset column, 0 for none (a peak does not depend on the offset).
      auto push = [&e, this](const Sample& s, double measured, std::size_t col) {
        e.r.push_back(s.value - measured);
        std::vector<double> row(columns(), 0.0);
        std::copy(s.gradient.begin(), s.gradient.end(), row.begin());
        if (col != 0) row[col] = -s.rate;
        e.J.push_back(std::move(row));
      };
      if (m.move.series) {
        const MeasuredSeries& s = *m.move.series;
        const std::size_t col = offset_column[i];
        const double offset = col != 0 ? v[col] : s.offset;
        for (std::size_t k = 0; k < s.t.size(); ++k) {
          // Before the move's start the tank is at rest: the wave and its rate are 0 there.
          push(series_at(dirs, std::max(s.t[k] - offset, 0.0), v[kGain]), s.eta[k], col);
        }
      }
      if (m.move.peaks) {
        const double T = m.move.law.duration();
        if (m.move.peaks->eta_motion)
          push(peak_of(dirs, 0.0, T, v[kGain]), *m.move.peaks->eta_motion, 0);
        if (m.move.peaks->eta_rest) {
          push(peak_of(dirs, T, T + m.move.peaks->rest_window, v[kGain]), *m.move.peaks->eta_rest,
               0);
        }
      }
      e.move_end.push_back(e.r.size());
    }
    return e;
  }

  [[nodiscard]] std::vector<std::size_t> free_columns() const {
    std::vector<std::size_t> c;
    for (std::size_t j = 0; j < columns(); ++j) {
      if (free[j]) c.push_back(j);
    }
    return c;
  }

  /// A column's name in the notes.
  [[nodiscard]] std::string name(std::size_t column) const {
    if (column < kColumns) return kNames[column];
    const auto move = static_cast<std::size_t>(
        std::find(offset_column.begin(), offset_column.end(), column) - offset_column.begin());
    return "the offset of move " + std::to_string(move + 1);
  }
};

Eigen::MatrixXd select(const Evaluation& e, const std::vector<std::size_t>& cols) {
  Eigen::MatrixXd J(static_cast<Eigen::Index>(e.r.size()), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t i = 0; i < e.r.size(); ++i) {
    for (std::size_t k = 0; k < cols.size(); ++k) {
      J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = e.J[i][cols[k]];
    }
  }
  return J;
}

Eigen::VectorXd widths(const Problem& pb, const std::vector<std::size_t>& cols) {
  Eigen::VectorXd w(static_cast<Eigen::Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k) {
    w[static_cast<Eigen::Index>(k)] = pb.upper[cols[k]] - pb.lower[cols[k]];
  }
  return w;
}

double residual_sigma(const Evaluation& e, std::size_t p) {
  if (e.r.size() <= p) return 0.0;
  double ssr = 0.0;
  for (double r : e.r) ssr += r * r;
  return std::sqrt(ssr / static_cast<double>(e.r.size() - p));
}

double rms(const std::vector<double>& r, std::size_t begin, std::size_t end) {
  if (end <= begin) return 0.0;
  double s = 0.0;
  for (std::size_t k = begin; k < end; ++k) s += r[k] * r[k];
  return std::sqrt(s / static_cast<double>(end - begin));
}

/// The least identifiable direction of the bound-scaled free parameters: its columns of at
/// least 0.3 in column order, and the largest.
struct WeakDirection {
  std::vector<std::size_t> columns;
  std::size_t largest{};
};

/// The least identifiable direction, when J^T J is singular in it (1e-12 relative) or its
/// standard deviation exceeds `fraction` of the bound box; `why` says which.
std::optional<WeakDirection> unidentifiable(const Problem& pb, const std::vector<std::size_t>& cols,
                                            const Eigen::MatrixXd& J, double sigma, double fraction,
                                            std::string* why) {
  if (cols.empty()) return std::nullopt;
  const Eigen::MatrixXd Js = J * widths(pb, cols).asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Js.transpose() * Js);
  const double lam = es.eigenvalues()[0];
  const bool singular = !(lam > 1e-12 * es.eigenvalues().maxCoeff());
  const double sd = singular ? HUGE_VAL : sigma / std::sqrt(lam);
  if (!singular && !(sd > fraction)) return std::nullopt;
  const Eigen::VectorXd u = es.eigenvectors().col(0);
  WeakDirection weak;
  Eigen::Index largest = 0;
  u.cwiseAbs().maxCoeff(&largest);
  weak.largest = cols[static_cast<std::size_t>(largest)];
  for (Eigen::Index k = 0; k < u.size(); ++k) {
    if (std::abs(u[k]) >= 0.3) weak.columns.push_back(cols[static_cast<std::size_t>(k)]);
  }
  *why = singular ? "J^T J is singular in that direction"
                  : "standard deviation " + sig3(100.0 * sd) + " % of its bound box";
  return weak;
}

std::string names_of(const Problem& pb, const std::vector<std::size_t>& columns) {
  std::string out;
  for (std::size_t k = 0; k < columns.size(); ++k) {
    out += (k == 0 ? "" : k + 1 == columns.size() ? " and " : ", ") + pb.name(columns[k]);
  }
  return out;
}

// Column j's result; `held`: held at its prior as not determined by the moves.
FittedParameter parameter(const Problem& pb, const Columns& v, std::size_t j,
                          const std::optional<double>& se, bool held) {
  FittedParameter f;
  f.prior = pb.prior[j];
  f.value = v[j];
  f.standard_error = se;
  f.state = pb.free[j] ? ParameterState::kFitted
                       : (held ? ParameterState::kUnidentifiable : ParameterState::kFixed);
  f.at_bound = pb.free[j] && (f.value <= pb.lower[j] || f.value >= pb.upper[j]);
  return f;
}

}  // namespace

namespace {

/// The fit's set-up: the unscaled tank, which directions the moves drive, every column's prior,
/// bounds and whether it is fitted (an undriven direction's are not).
Problem make_problem(const Format& format, const ModelOptions& base,
                     const std::vector<RectangularMeasuredMove>& moves,
                     const CalibrationSettings& settings, std::array<bool, 2>* driven) {
  ModelOptions unscaled = base;
  unscaled.omega_scale = 1.0;
  unscaled.height_gain = 1.0;
  unscaled.width_omega_scale.reset();
  unscaled.width_zeta.reset();
  Problem pb;
  pb.tank = rectangular_model_of(format, unscaled);
  pb.moves = &moves;
  pb.nonlinear = settings.nonlinear;
  *driven = {false, false};
  for (const RectangularMeasuredMove& m : moves) {
    const AxisComponents c = axis_components(m.orientation_deg);
    (*driven)[0] = (*driven)[0] || c.along_length != 0.0;
    (*driven)[1] = (*driven)[1] || c.along_width != 0.0;
    // simulate answers with its linear model outside the nonlinear model's range; the fit
    // follows it, judged once on the theory's tank (the fitted scales move the wave little).
    RectangularModel turned = pb.tank;
    turned.orientation_deg = m.orientation_deg;
    pb.nonlinear_holds.push_back(
        rectangular_nonlinear_peaks(turned, m.move.law, horizon(m.move), settings.nonlinear)
            .nonlinear);
  }
  const auto& p = settings.parameters;
  const std::array<const ParameterSetting*, kColumns> setting{&p[0], &p[1], &p[0], &p[1], &p[3]};
  const Values own{1.0, pb.tank.along_length.zeta, 1.0, pb.tank.along_width.zeta, 1.0};
  for (std::size_t j = 0; j < kColumns; ++j) {
    pb.prior.push_back(setting[j]->initial.value_or(own[j]));
    pb.lower.push_back(setting[j]->lower);
    pb.upper.push_back(setting[j]->upper);
    const bool measured = of_length(j) ? (*driven)[0] : of_width(j) ? (*driven)[1] : true;
    pb.free.push_back(setting[j]->fit && measured);
  }
  for (const RectangularMeasuredMove& m : moves) {
    const std::optional<MeasuredSeries>& s = m.move.series;
    if (!s || !s->fit_offset) {
      pb.offset_column.push_back(0);
      continue;
    }
    pb.offset_column.push_back(pb.prior.size());
    pb.prior.push_back(s->offset);
    pb.lower.push_back(s->offset - s->max_offset);
    pb.upper.push_back(s->offset + s->max_offset);
    pb.free.push_back(true);
  }
  return pb;
}

/// The sentences of the directions no move drives.
std::vector<std::string> unmeasured_notes(const std::array<bool, 2>& driven) {
  std::vector<std::string> notes;
  for (const auto& [measured, name, along] :
       {std::tuple{driven[0], "length", "(orientation 0 or 180 degrees)"},
        std::tuple{driven[1], "width", "(orientation 90 or -90 degrees)"}}) {
    if (!measured) {
      notes.push_back(std::string("the ") + name +
                      " is unmeasured: no move drives it, so its omega_scale and zeta keep their "
                      "priors; a move along it " +
                      along + " or a turned move would measure it");
    }
  }
  return notes;
}

/// The bounded least-squares fit of the free columns `cols` from `v`, into `v`.
detail::LeastSquaresOutcome fit(const Problem& pb, const std::vector<std::size_t>& cols, Columns& v,
                                const CalibrationSettings& settings) {
  const auto n = static_cast<Eigen::Index>(cols.size());
  detail::BoundedLeastSquares problem;
  problem.lower.resize(n);
  problem.upper.resize(n);
  Eigen::VectorXd x0(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const std::size_t j = cols[static_cast<std::size_t>(k)];
    problem.lower[k] = pb.lower[j];
    problem.upper[k] = pb.upper[j];
    x0[k] = v[j];
  }
  problem.evaluate = [&pb, &cols, &v](const Eigen::VectorXd& x, Eigen::VectorXd& r,
                                      Eigen::MatrixXd& jac) {
    Columns trial = v;
    for (std::size_t k = 0; k < cols.size(); ++k) trial[cols[k]] = x[static_cast<Eigen::Index>(k)];
    const Evaluation e = pb.run(trial);
    r = Eigen::Map<const Eigen::VectorXd>(e.r.data(), static_cast<Eigen::Index>(e.r.size()));
    jac = select(e, cols);
    return true;
  };
  detail::LeastSquaresOptions options;
  options.max_iterations = settings.max_iterations;
  options.stop = settings.stop;
  detail::LeastSquaresOutcome out = detail::solve_bounded_least_squares(problem, x0, options);
  for (std::size_t k = 0; k < cols.size(); ++k) v[cols[k]] = out.x[static_cast<Eigen::Index>(k)];
  return out;
}

/// sigma sqrt((J^T J)^-1_ii) of every free column (in the bound-scaled variables, as calibrate()).
std::vector<std::optional<double>> standard_errors(const Problem& pb,
                                                   const std::vector<std::size_t>& cols,
                                                   const Eigen::MatrixXd& J, double sigma) {
  std::vector<std::optional<double>> se(pb.columns());
  if (cols.empty() || !(sigma > 0.0)) return se;
  const Eigen::VectorXd w = widths(pb, cols);
  const Eigen::MatrixXd Js = J * w.asDiagonal();
  const auto n = static_cast<Eigen::Index>(cols.size());
  const Eigen::MatrixXd inv = (Js.transpose() * Js).ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    se[cols[k]] = sigma * std::sqrt(inv(i, i)) * w[i];
  }
  return se;
}

/// Every move's residual count, RMS before and after, and fitted offset.
std::vector<MoveFit> move_fits(const Problem& pb, const Columns& v,
                               const std::vector<std::optional<double>>& se,
                               const Evaluation& before, const Evaluation& after) {
  std::vector<MoveFit> out;
  std::size_t begin = 0;
  for (std::size_t i = 0; i < pb.moves->size(); ++i) {
    MoveFit m;
    m.name = (*pb.moves)[i].move.name;
    m.residuals = after.move_end[i] - begin;
    m.rms_before = rms(before.r, begin, before.move_end[i]);
    m.rms_after = rms(after.r, begin, after.move_end[i]);
    if (const std::size_t col = pb.offset_column[i]; col != 0) {
      m.offset = v[col];
      m.offset_standard_error = se[col];
    }
    out.push_back(std::move(m));
    begin = after.move_end[i];
  }
  return out;
}

CalibrationStatus status_of(detail::LeastSquaresStatus s) {
  switch (s) {
    case detail::LeastSquaresStatus::kConverged:
      return CalibrationStatus::kConverged;
    case detail::LeastSquaresStatus::kMaxIterations:
      return CalibrationStatus::kMaxIterations;
    case detail::LeastSquaresStatus::kStopped:
      return CalibrationStatus::kTimeLimit;
    case detail::LeastSquaresStatus::kFailed:
      break;
  }
  return CalibrationStatus::kFailed;
}

/// The variables of a fit with each pair of the directions' free columns (omega scales, zetas)
/// tied as one factor of their priors: per variable, its columns and their coefficients
/// (value = coefficient x variable).
using TiedVariables = std::vector<std::vector<std::pair<std::size_t, double>>>;

/// The tied fit's variables, or nothing when no pair of the directions' columns is free.
std::optional<TiedVariables> tied_variables(const Problem& pb,
                                            const std::vector<std::size_t>& cols) {
  const auto fitted = [&cols](std::size_t j) {
    return std::find(cols.begin(), cols.end(), j) != cols.end();
  };
  TiedVariables vars;
  bool tied = false;
  for (const auto& [l, w] : {std::pair{kOmegaL, kOmegaW}, std::pair{kZetaL, kZetaW}}) {
    if (fitted(l) && fitted(w) && pb.prior[l] > 0.0 && pb.prior[w] > 0.0) {
      vars.push_back({{l, pb.prior[l]}, {w, pb.prior[w]}});
      tied = true;
      continue;
    }
    if (fitted(l)) vars.push_back({{l, 1.0}});
    if (fitted(w)) vars.push_back({{w, 1.0}});
  }
  if (!tied) return std::nullopt;
  for (std::size_t j : cols) {
    if (!of_length(j) && !of_width(j)) vars.push_back({{j, 1.0}});
  }
  return vars;
}

/// A fit of the tied variables from the priors: its values, outcome, residual sigma and standard
/// errors (per column: a tied pair's are its factor's times each prior).
struct TiedFit {
  Columns v;
  detail::LeastSquaresOutcome ls;
  Evaluation after;
  double sigma{};
  std::vector<std::optional<double>> se;
  /// At least as many values as its parameters: it can stand as the answer (its errors are
  /// estimated when there are more).
  bool determined{false};
};

/// The Jacobian of the tied variables: each variable's columns of `e`, times their coefficients.
Eigen::MatrixXd tied_jacobian(const Evaluation& e, const TiedVariables& vars) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(e.r.size()),
                                            static_cast<Eigen::Index>(vars.size()));
  for (std::size_t i = 0; i < e.r.size(); ++i) {
    for (std::size_t k = 0; k < vars.size(); ++k) {
      for (const auto& [col, coef] : vars[k]) {
        J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) += coef * e.J[i][col];
      }
    }
  }
  return J;
}

TiedFit fit_tied(const Problem& pb, const TiedVariables& vars, const Columns& start,
                 const CalibrationSettings& settings) {
  const auto n = static_cast<Eigen::Index>(vars.size());
  detail::BoundedLeastSquares problem;
  problem.lower.resize(n);
  problem.upper.resize(n);
  Eigen::VectorXd x0(n), w(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    problem.lower[k] = -HUGE_VAL;
    problem.upper[k] = HUGE_VAL;
    for (const auto& [col, coef] : vars[static_cast<std::size_t>(k)]) {
      problem.lower[k] = std::max(problem.lower[k], pb.lower[col] / coef);
      problem.upper[k] = std::min(problem.upper[k], pb.upper[col] / coef);
    }
    const auto& [col, coef] = vars[static_cast<std::size_t>(k)].front();
    x0[k] = std::clamp(start[col] / coef, problem.lower[k], problem.upper[k]);
    w[k] = problem.upper[k] - problem.lower[k];
  }
  const auto values = [&pb, &vars, &start](const Eigen::VectorXd& x) {
    Columns v = start;
    for (std::size_t k = 0; k < vars.size(); ++k) {
      for (const auto& [col, coef] : vars[k]) v[col] = coef * x[static_cast<Eigen::Index>(k)];
    }
    return v;
  };
  problem.evaluate = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd& jac) {
    const Evaluation e = pb.run(values(x));
    r = Eigen::Map<const Eigen::VectorXd>(e.r.data(), static_cast<Eigen::Index>(e.r.size()));
    jac = tied_jacobian(e, vars);
    return true;
  };
  detail::LeastSquaresOptions options;
  options.max_iterations = settings.max_iterations;
  options.stop = settings.stop;
  TiedFit t;
  t.ls = detail::solve_bounded_least_squares(problem, x0, options);
  t.v = values(t.ls.x);
  t.after = pb.run(t.v);
  t.sigma = residual_sigma(t.after, vars.size());
  t.se.assign(pb.columns(), std::nullopt);
  // Fewer values than parameters: the tie is not determined (why_tied does not report it); as
  // many: determined, with nothing left to estimate its errors from.
  t.determined = t.after.r.size() >= vars.size();
  if (t.after.r.size() <= vars.size()) return t;
  const Eigen::MatrixXd Js = tied_jacobian(t.after, vars) * w.asDiagonal();
  const Eigen::MatrixXd inv = (Js.transpose() * Js).ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  for (std::size_t k = 0; k < vars.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    for (const auto& [col, coef] : vars[k])
      t.se[col] = coef * t.sigma * std::sqrt(inv(i, i)) * w[i];
  }
  return t;
}

/// The likelihood-ratio test of the free fit against the tied one (Gaussian residuals: n ln of
/// the ratio of their squares' sums is chi-square with as many degrees as the tie removed): the
/// p-value of the free fit's lower residuals arising by chance.
double split_p_value(const Evaluation& tied, const Evaluation& free, std::size_t removed) {
  double ssr_tied = 0.0, ssr_free = 0.0;
  for (double r : tied.r) ssr_tied += r * r;
  for (double r : free.r) ssr_free += r * r;
  if (!(ssr_free > 0.0)) return ssr_tied > 0.0 ? 0.0 : 1.0;
  const double lr = static_cast<double>(free.r.size()) * std::log(ssr_tied / ssr_free);
  if (!(lr > 0.0)) return 1.0;
  // chi-square survival for 1 and 2 degrees of freedom
  return removed == 1 ? std::erfc(std::sqrt(0.5 * lr)) : std::exp(-0.5 * lr);
}

/// The significance below which the free fit's split of the directions is kept [-].
constexpr double kSplitSignificance{0.05};

}  // namespace

namespace {

/// The fit with the directions apart: its values, outcome, residuals, Jacobian of the columns
/// still free, sigma and the columns held at their priors.
struct FreeFit {
  Columns v;
  detail::LeastSquaresOutcome ls;
  Evaluation after;
  Eigen::MatrixXd J;
  double sigma{};
  std::vector<std::size_t> cols;
  std::vector<bool> held;
};

/// Fits the free columns from `start`, holding at its prior each column the moves do not
/// determine, or (both directions in one weak combination) refusing into `refused`, every value
/// then its prior and no column free.
FreeFit fit_apart(Problem& pb, const Columns& start, const Evaluation& before,
                  const CalibrationSettings& settings, RectangularCalibrationResult& out) {
  FreeFit f{start,
            {},
            before,
            {},
            residual_sigma(before, 0),
            pb.free_columns(),
            std::vector<bool>(pb.columns(), false)};
  f.ls.status = detail::LeastSquaresStatus::kConverged;  // nothing to fit: the priors stand
  while (!f.cols.empty()) {
    f.ls = fit(pb, f.cols, f.v, settings);
    out.iterations += f.ls.iterations;
    f.after = pb.run(f.v);
    f.J = select(f.after, f.cols);
    f.sigma = residual_sigma(f.after, f.cols.size());
    if (f.ls.status == detail::LeastSquaresStatus::kStopped) break;
    std::string why;
    const auto weak =
        unidentifiable(pb, f.cols, f.J, f.sigma, settings.identifiable_fraction, &why);
    if (!weak) break;
    const std::vector<std::size_t>& shared = weak->columns;
    if (std::any_of(shared.begin(), shared.end(), of_length) &&
        std::any_of(shared.begin(), shared.end(), of_width)) {
      // The moves drive both directions but do not tell them apart: no values to report.
      out.refused = names_of(pb, shared) + " cannot be separated by these moves (" + why +
                    "): add a move along the length (orientation 0 or 180 degrees) and one "
                    "along the width (90 or -90 degrees), or a measured series of a turned "
                    "move, whose two frequencies tell the directions apart";
      f.v = pb.prior;
      pb.free.assign(pb.columns(), false);
      f.after = before;
      f.cols.clear();
      f.sigma = residual_sigma(f.after, 0);
      break;
    }
    const std::size_t hold = weak->largest;
    out.notes.push_back(names_of(pb, shared) +
                        (shared.size() > 1 ? " cannot be separated" : " is not determined") +
                        " by these moves (" + why + "): " + pb.name(hold) +
                        " is held at its prior " + sig3(pb.prior[hold]) +
                        "; add moves that excite it (faster or larger moves, a measured series)");
    pb.free[hold] = false;
    f.held[hold] = true;
    f.v[hold] = pb.prior[hold];
    f.cols = pb.free_columns();
  }
  return f;
}

/// "omega scales and zetas": the pairs a tie joins.
std::string tied_pairs(const TiedVariables& vars) {
  bool omega = false, zeta = false;
  for (const auto& var : vars) {
    if (var.size() < 2) continue;
    omega = omega || var.front().first == kOmegaL;
    zeta = zeta || var.front().first == kZetaL;
  }
  return omega && zeta ? "omega scales and zetas" : omega ? "omega scales" : "zetas";
}

/// Why the tied fit is reported instead of the fit apart, or empty when the fit apart stands.
std::string why_tied(const Problem& pb, const FreeFit& f, const TiedFit& tied, std::size_t removed,
                     const std::string& refused) {
  if (tied.ls.status != detail::LeastSquaresStatus::kConverged || !tied.determined) return {};
  if (!refused.empty()) return refused.substr(0, refused.find(": add a move"));
  std::vector<std::size_t> held;
  for (std::size_t j = 0; j < f.held.size(); ++j) {
    if (f.held[j]) held.push_back(j);
  }
  if (std::any_of(held.begin(), held.end(),
                  [](std::size_t j) { return of_length(j) || of_width(j); })) {
    // Apart, the moves left a direction's column undetermined (held at its prior): tied, they
    // determine it.
    return "fitted apart, " + names_of(pb, held) + (held.size() > 1 ? " are" : " is") +
           " not determined by these moves";
  }
  if (!held.empty()) return {};
  const double p = split_p_value(tied.after, f.after, removed);
  if (p < kSplitSignificance) return {};
  if (f.ls.status != detail::LeastSquaresStatus::kConverged) {
    return "fitted apart from every start, the search did not converge (" +
           std::string(name_of(status_of(f.ls.status))) + ") and its best point is no better " +
           "than the tie (likelihood-ratio p = " + sig3(p) + ")";
  }
  double ssr_tied = 0.0, ssr_free = 0.0;
  for (double r : tied.after.r) ssr_tied += r * r;
  for (double r : f.after.r) ssr_free += r * r;
  return "fitted apart, they lower the residuals' sum of squares by only " +
         sig3(100.0 * (1.0 - ssr_free / ssr_tied)) + " % (likelihood-ratio p = " + sig3(p) +
         " >= " + sig3(kSplitSignificance) + "), a split the noise explains";
}

/// The starts of the fit apart: the tied fit's point and the priors, and the tied point with the
/// two frequency scales split by +-kSplitStarts either way, since two nearly equal frequencies make
/// the least-squares surface of their split many-valleyed (either direction can take the higher
/// frequency, and a start in the wrong valley converges there).
std::vector<Columns> apart_starts(const Problem& pb, const std::optional<TiedFit>& tied) {
  constexpr std::array<double, 2> kSplitStarts{0.04, 0.1};
  // Tanks whose two directions' own first frequencies are this far apart (relative to their
  // middle) have one valley per direction's frequency: the tie's point alone starts them.
  constexpr double kDistinctFrequencies{0.1};
  std::vector<Columns> starts;
  if (tied) starts.push_back(tied->v);  // converged or not, the tie's best point
  const double f_l = pb.tank.along_length.omega1(), f_w = pb.tank.along_width.omega1();
  if (tied && std::abs(f_l - f_w) > kDistinctFrequencies * 0.5 * (f_l + f_w)) return starts;
  starts.push_back(pb.prior);
  if (!tied || !pb.free[kOmegaL] || !pb.free[kOmegaW]) return starts;
  // (Centred on the priors as well, and split by 2, 5, 10 and 20 %, the starts found no other
  // valley over 20 random truths of an 80 x 81 mm tank, at two to four times the cost.)
  for (const Columns& centre : {tied->v}) {
    for (double split : kSplitStarts) {
      for (double sign : {1.0, -1.0}) {
        Columns v = centre;
        v[kOmegaL] =
            std::clamp(v[kOmegaL] * (1.0 + sign * split), pb.lower[kOmegaL], pb.upper[kOmegaL]);
        v[kOmegaW] =
            std::clamp(v[kOmegaW] * (1.0 - sign * split), pb.lower[kOmegaW], pb.upper[kOmegaW]);
        starts.push_back(std::move(v));
      }
    }
  }
  return starts;
}

double ssr_of(const Evaluation& e) {
  double ssr = 0.0;
  for (double r : e.r) ssr += r * r;
  return ssr;
}

/// The fit apart from every start of apart_starts: the one of least residuals (a start in the
/// right valley can run out of iterations where another converges in a wrong one), continued
/// once from its point when it did not converge; with its problem (the columns it held), notes
/// and refusal.
FreeFit best_apart(Problem& pb, const std::optional<TiedFit>& tied, const Evaluation& before,
                   const CalibrationSettings& settings, RectangularCalibrationResult& out) {
  std::optional<FreeFit> best;
  Problem best_pb = pb;
  RectangularCalibrationResult best_out = out;
  bool stopped = false;
  for (const Columns& start : apart_starts(pb, tied)) {
    if (stopped) break;
    Problem trial_pb = pb;
    RectangularCalibrationResult trial_out = out;
    trial_out.iterations = 0;
    FreeFit f = fit_apart(trial_pb, start, before, settings, trial_out);
    out.iterations += trial_out.iterations;
    stopped = stopped || f.ls.status == detail::LeastSquaresStatus::kStopped;
    // Refused, or a column held at its prior, ranks after a fit of every column.
    const auto rank = [](const FreeFit& x, const RectangularCalibrationResult& o) {
      const bool held = std::find(x.held.begin(), x.held.end(), true) != x.held.end();
      return std::pair{!o.refused.empty() ? 2 : held ? 1 : 0, ssr_of(x.after)};
    };
    if (!best || rank(f, trial_out) < rank(*best, best_out)) {
      best = std::move(f);
      best_pb = std::move(trial_pb);
      best_out = std::move(trial_out);
    }
  }
  int iterations = out.iterations;
  // A search the budget cut is the budget's answer, whichever start gave its best point.
  if (stopped) best->ls.status = detail::LeastSquaresStatus::kStopped;
  if (best->ls.status == detail::LeastSquaresStatus::kMaxIterations && best_out.refused.empty()) {
    Problem again_pb = best_pb;
    RectangularCalibrationResult again_out = best_out;
    again_out.iterations = 0;
    FreeFit again = fit_apart(again_pb, best->v, before, settings, again_out);
    iterations += again_out.iterations;
    if (again_out.refused.empty() && ssr_of(again.after) <= ssr_of(best->after)) {
      best = std::move(again);
      best_pb = std::move(again_pb);
      best_out = std::move(again_out);
    }
  }
  out = std::move(best_out);
  out.iterations = iterations;
  pb = std::move(best_pb);
  return std::move(*best);
}

/// The note of a tied answer: why (`why`, why_tied's), what was tied, and which moves would
/// measure each direction on its own when the moves have none along either axis.
std::string tie_note(const std::vector<RectangularMeasuredMove>& moves, const std::string& why,
                     const std::string& pairs) {
  bool along_length = false, along_width = false;
  for (const RectangularMeasuredMove& m : moves) {
    const AxisComponents c = axis_components(m.orientation_deg);
    along_length = along_length || c.along_width == 0.0;
    along_width = along_width || c.along_length == 0.0;
  }
  const bool noise = why.starts_with("fitted apart, they lower");
  std::string note = std::string(noise ? "the two directions agree within the noise"
                                       : "the moves do not tell the directions apart") +
                     " (" + why + "): fitted with their " + pairs +
                     " tied, each pair one factor of its priors";
  if (!(along_length && along_width)) {
    note +=
        "; a move along the length (orientation 0 or 180 degrees) and one along the width (90 "
        "or -90 degrees) would measure each direction on its own";
  }
  return note;
}

}  // namespace

RectangularCalibrationResult calibrate_rectangular(
    const Format& format, const ModelOptions& base,
    const std::vector<RectangularMeasuredMove>& moves, const CalibrationSettings& settings) {
  RectangularCalibrationResult out;
  std::array<bool, 2> driven{};
  Problem pb = make_problem(format, base, moves, settings, &driven);
  out.notes = unmeasured_notes(driven);
  const Evaluation before = pb.run(pb.prior);
  const std::vector<bool> free_before = pb.free;
  // The directions tied first (each pair of their columns one factor of its priors): the fit
  // the moves always determine when both directions are driven, and the start of the fit apart,
  // which from the priors could wander off where the two frequencies nearly coincide (an
  // 80 x 81 mm tank at 30 degrees ended at a width's scale of 0.66 and sigma 20 times the noise).
  const std::optional<TiedVariables> vars = tied_variables(pb, pb.free_columns());
  std::optional<TiedFit> tied;
  if (vars) {
    tied = fit_tied(pb, *vars, pb.prior, settings);
    out.iterations += tied->ls.iterations;
  }
  const std::size_t removed =
      vars ? static_cast<std::size_t>(std::count(free_before.begin(), free_before.end(), true)) -
                 vars->size()
           : 0;
  FreeFit f = best_apart(pb, tied, before, settings, out);
  std::vector<std::optional<double>> se = standard_errors(pb, f.cols, f.J, f.sigma);
  if (const std::string why = tied ? why_tied(pb, f, *tied, removed, out.refused) : std::string();
      !why.empty()) {
    out.notes = unmeasured_notes(driven);  // the fit apart's notes are not the answer's
    out.notes.push_back(tie_note(moves, why, tied_pairs(*vars)));
    out.refused.clear();
    pb.free = free_before;
    f.held.assign(f.held.size(), false);
    f.v = tied->v;
    f.ls = tied->ls;
    f.after = tied->after;
    f.sigma = tied->sigma;
    se = tied->se;
  }
  auto param = [&](std::size_t j) { return parameter(pb, f.v, j, se[j], f.held[j]); };
  out.length = {driven[0], param(kOmegaL), param(kZetaL)};
  out.width = {driven[1], param(kOmegaW), param(kZetaW)};
  out.height_gain = param(kGain);
  out.moves = move_fits(pb, f.v, se, before, f.after);
  out.sigma = f.sigma;
  out.status = out.refused.empty() ? status_of(f.ls.status) : CalibrationStatus::kFailed;
  return out;
}

void rectangular_calibration_residuals(const Format& format, const ModelOptions& base,
                                       const std::vector<RectangularMeasuredMove>& moves,
                                       const RectangularCalibrationValues& p,
                                       const std::vector<double>& offsets,
                                       const NonlinearOptions& nonlinear,
                                       std::vector<double>* residuals,
                                       std::vector<std::vector<double>>* jacobian) {
  CalibrationSettings settings;
  settings.nonlinear = nonlinear;
  std::array<bool, 2> driven{};
  const Problem pb = make_problem(format, base, moves, settings, &driven);
  Columns v(p.begin(), p.end());
  v.resize(pb.columns());
  for (std::size_t i = 0; i < moves.size(); ++i) {
    if (pb.offset_column[i] != 0) v[pb.offset_column[i]] = offsets[i];
  }
  Evaluation e = pb.run(v);
  *residuals = std::move(e.r);
  if (jacobian != nullptr) *jacobian = std::move(e.J);
}

}  // namespace slosh
