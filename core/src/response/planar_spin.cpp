#include "response/planar_spin.hpp"

#include <cmath>
#include <numbers>

#include "response/nonlinear_scheme.hpp"
#include "response/planar_scheme.hpp"

namespace slosh::detail {

ChebyshevFit::ChebyshevFit() {
  std::array<std::array<double, 2 * kFitTerms>, kFitTerms> a{};
  for (std::size_t j = 0; j < kFitTerms; ++j) {
    node[j] = 0.5 * (1.0 - std::cos((2.0 * static_cast<double>(j) + 1.0) * std::numbers::pi /
                                    (2.0 * kFitTerms)));
    double p = 1.0;
    for (std::size_t k = 0; k < kFitTerms; ++k, p *= node[j]) a[j][k] = p;
    a[j][kFitTerms + j] = 1.0;
  }
  for (std::size_t c = 0; c < kFitTerms; ++c) {  // Gauss-Jordan with partial pivoting
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < kFitTerms; ++r) {
      if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
    }
    std::swap(a[c], a[pivot]);
    const double d = a[c][c];
    for (double& e : a[c]) e /= d;
    for (std::size_t r = 0; r < kFitTerms; ++r) {
      if (r == c) continue;
      const double f = a[r][c];
      for (std::size_t k = 0; k < 2 * kFitTerms; ++k) a[r][k] -= f * a[c][k];
    }
  }
  for (std::size_t r = 0; r < kFitTerms; ++r) {
    for (std::size_t k = 0; k < kFitTerms; ++k) inverse[r][k] = a[r][kFitTerms + k];
  }
}

const ChebyshevFit& chebyshev() {
  static const ChebyshevFit fit;
  return fit;
}

double fit_step(const SloshingModel& model, const PlanarOptions& options) {
  return std::min(options.max_step, 2.0 * std::numbers::pi / model.omega1() / kFitStepsPerPeriod);
}

std::size_t fit_steps(double L, double h_fit, const DrivePiece& p) {
  const double h = piece_max_step(h_fit, p.heading_rate, kFitStepsPerTurn);
  return step_count(L, piece_max_step(h, p.harmonic_omega, kFitStepsPerPeriod), 1);
}

namespace {

/// The liquid's spin a time tau after w0 once the container has stopped turning: then
/// Omega = |w| and w' = -c sqrt(|w|) w, c = sqrt(nu) / h, so |w|^(-1/2) grows linearly:
/// w(tau) = w0 / (1 + c sqrt(|w0|) tau / 2)^2 (closed form; no step needed in the rest window).
double spin_down(double w0, double c, double tau) {
  const double d = 1.0 + 0.5 * c * std::sqrt(std::abs(w0)) * tau;
  return w0 / (d * d);
}

}  // namespace

SpinTrack::SpinTrack(const PlanarDrive& drive, double rest_time, const SloshingModel& model,
                     const PlanarOptions& options) {
  const double nu = options.kinematic_viscosity, fill = model.fill_height;
  const double h_fit = fit_step(model, options);
  const ChebyshevFit& cheb = chebyshev();
  auto rhs = [nu, fill](double, double v, double a) {
    return ekman_rate(nu, fill, a, v) * (a - v);
  };
  const std::vector<DrivePiece>& pieces = drive.pieces();
  const double T = drive.duration();
  const double spin_down_rate = std::sqrt(nu) / fill;
  double phi = 0.0, spin = 0.0;
  for (std::size_t k = 0; k <= pieces.size(); ++k) {
    const bool rest = k == pieces.size();
    const DrivePiece p = rest ? DrivePiece{T, T + rest_time} : pieces[k];
    const double L = p.t_end - p.t_begin;
    if (!(L > 0.0)) continue;
    const std::size_t n = fit_steps(L, h_fit, p);
    const double H = L / static_cast<double>(n);
    for (std::size_t j = 0; j < n; ++j) {
      const double t0 = p.t_begin + H * static_cast<double>(j);
      if (rest) {
        FitPoly values{};
        for (std::size_t i = 0; i < kFitTerms; ++i) {
          values[i] = spin_down(spin, spin_down_rate, cheb.node[i] * H);
        }
        pieces_.push_back({t0, H, cheb.fit(values)});
        spin = spin_down(spin, spin_down_rate, H);
        continue;
      }
      FitPoly values{};
      for (std::size_t i = 0; i < kFitTerms; ++i) {
        values[i] = drive.turning_rate(k, t0 + cheb.node[i] * H);
      }
      const FitPoly rate = cheb.fit(values);
      auto acc = [&rate](std::size_t i) { return horner(rate, kDopC[i]); };
      DopStep<double> step;
      dop853_step(rhs, acc, phi, spin, rhs(phi, spin, rate[0]), H, true, step, true);
      Piece piece{t0, H, {}};
      std::copy(step.v_poly.begin(), step.v_poly.end(), piece.w.begin());
      pieces_.push_back(piece);
      phi = step.x1;
      spin = step.v1;
    }
  }
}

double SpinTrack::at(double t) const {
  if (pieces_.empty() || t <= 0.0) return 0.0;
  const auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t,
                                   [](double v, const Piece& p) { return v < p.t0; });
  const Piece& p = *(it - 1);
  return horner(p.w, std::min((t - p.t0) / p.H, 1.0));
}

FitPoly SpinTrack::over(double t0, double h) const {
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t0,
                             [](double v, const Piece& p) { return v < p.t0; });
  const Piece& p = *(it - 1);
  const double a = (t0 - p.t0) / p.H, b = h / p.H;
  if (it == pieces_.end() || t0 + h <= it->t0) {
    // Inside one sub-step: w(a + b theta) re-expanded in theta (Horner on polynomials).
    FitPoly r{};
    r[0] = p.w[kFitTerms - 1];
    for (std::size_t k = kFitTerms - 1; k > 0; --k) {
      // r <- r (a + b theta) + w[k - 1]; r has degree kFitTerms - 1 - k here.
      const std::size_t deg = kFitTerms - 1 - k;
      for (std::size_t d = deg + 1; d > 0; --d) r[d] = r[d] * a + r[d - 1] * b;
      r[0] = r[0] * a + p.w[k - 1];
    }
    return r;
  }
  // Across sub-steps of the same drive piece, where the spin is smooth: interpolate it.
  const ChebyshevFit& cheb = chebyshev();
  FitPoly values{};
  for (std::size_t i = 0; i < kFitTerms; ++i) values[i] = at(t0 + cheb.node[i] * h);
  return cheb.fit(values);
}

}  // namespace slosh::detail
