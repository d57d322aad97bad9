// Peaks of the planar linear model solved exactly piece by piece (planar_response.hpp): on
// sub-steps of a drive piece the horizontal acceleration is interpolated by a degree-7
// polynomial at Chebyshev nodes (error ~ (W H / 2)^8 / (2^7 8!) of the forcing for content at
// W rad/s, below 1e-9 for the sub-steps used), and every mode's response to a polynomial
// forcing is a polynomial particular solution plus the damped homogeneous one in closed form,
// so no step follows the fastest mode's period. The height |E| + R^2 w_l^2 / (4 g) is sampled
// at min(1 ms, fastest period / 64) by complex rotation (as linear_peaks.cpp) and every sampled
// local maximum within 5 % of the best sample is refined by safeguarded Newton steps on its
// exact derivatives. The liquid's spin (slow, seconds to minutes) is integrated by DOP853 on
// the same sub-steps from the interpolated turning rate. Applies when the effective gravity is
// constant (no vertical motion) and every mode is under-damped; else the caller integrates.

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <optional>

#include "response/planar_linear_exact.hpp"
#include "response/planar_scheme.hpp"
#include "sincos.hpp"

namespace slosh::detail {

namespace {

using Complex = std::complex<double>;
constexpr std::size_t kTerms{8};
using Coeffs = std::array<double, kTerms>;

/// Sub-steps per period of the first mode [-] (and per period of a law piece's harmonic).
constexpr double kFitStepsPerPeriod{8.0};
/// Candidates within this fraction of the best sample are refined (as find_max()).
constexpr double kRefineFraction{0.05};

/// Chebyshev nodes on [0, 1] and the inverse of their monomial Vandermonde matrix: the
/// interpolating polynomial's coefficients in u are inverse * values.
struct ChebyshevFit {
  std::array<double, kTerms> node{};
  std::array<std::array<double, kTerms>, kTerms> inverse{};
  ChebyshevFit() {
    std::array<std::array<double, 2 * kTerms>, kTerms> a{};
    for (std::size_t j = 0; j < kTerms; ++j) {
      node[j] = 0.5 * (1.0 - std::cos((2.0 * static_cast<double>(j) + 1.0) * std::numbers::pi / (2.0 * kTerms)));
      double p = 1.0;
      for (std::size_t k = 0; k < kTerms; ++k, p *= node[j]) a[j][k] = p;
      a[j][kTerms + j] = 1.0;
    }
    for (std::size_t c = 0; c < kTerms; ++c) {  // Gauss-Jordan with partial pivoting
      std::size_t pivot = c;
      for (std::size_t r = c + 1; r < kTerms; ++r) {
        if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
      }
      std::swap(a[c], a[pivot]);
      const double d = a[c][c];
      for (double& e : a[c]) e /= d;
      for (std::size_t r = 0; r < kTerms; ++r) {
        if (r == c) continue;
        const double f = a[r][c];
        for (std::size_t k = 0; k < 2 * kTerms; ++k) a[r][k] -= f * a[c][k];
      }
    }
    for (std::size_t r = 0; r < kTerms; ++r) {
      for (std::size_t k = 0; k < kTerms; ++k) inverse[r][k] = a[r][kTerms + k];
    }
  }
  [[nodiscard]] Coeffs fit(const Coeffs& values) const {
    Coeffs c{};
    for (std::size_t r = 0; r < kTerms; ++r) {
      double s = 0.0;
      for (std::size_t k = 0; k < kTerms; ++k) s += inverse[r][k] * values[k];
      c[r] = s;
    }
    return c;
  }
};

const ChebyshevFit& chebyshev() {
  static const ChebyshevFit fit;
  return fit;
}

double horner(const Coeffs& c, double u) {
  double r = c[kTerms - 1];
  for (std::size_t k = kTerms - 1; k > 0; --k) r = r * u + c[k - 1];
  return r;
}

/// p, p', p'' in u.
void horner_jet(const Coeffs& c, double u, double& p, double& d1, double& d2) {
  p = c[kTerms - 1];
  d1 = 0.0;
  d2 = 0.0;
  for (std::size_t k = kTerms - 1; k > 0; --k) {
    d2 = d2 * u + 2.0 * d1;
    d1 = d1 * u + p;
    p = p * u + c[k - 1];
  }
}

struct Mode {
  double w{}, w2{}, two_zw{}, gain{};
  Complex lambda;  // -sigma + i wd
};

/// One sub-step in closed form: E(u) = (px, py)(u) + sum_n Re((zx_n, zy_n) exp(lambda_n H u)),
/// amplitudes weighted by the modes' height gains; the liquid's spin w(u).
struct SubStep {
  double t0{}, H{};
  Coeffs px{}, py{}, spin{};
  std::array<Complex, kMaxModes> zx{}, zy{};
};

/// Height and its first two time derivatives.
struct Jet {
  double f{}, d1{}, d2{}, ex{}, ey{};
};

class ExactPlanarLinear {
 public:
  ExactPlanarLinear(const SloshingModel& model, const PlanarOptions& options, double vortex_gain)
      : options_(options), vortex_gain_(vortex_gain), fill_(model.fill_height) {
    double w_max = 0.0;
    for (int n = 0; n < model.modes(); ++n) {
      const double w = model.omega[static_cast<std::size_t>(n)];
      modes_.push_back({w, w * w, 2.0 * model.zeta * w, model.eta_gain[static_cast<std::size_t>(n)],
                        Complex(-model.zeta * w, w * std::sqrt(1.0 - model.zeta * model.zeta))});
      w_max = std::max(w_max, w);
    }
    w1_ = model.omega1();
    sample_step_ = std::min(kMaxPeakStep, 2.0 * std::numbers::pi / w_max / kSamplesPerPeriod);
  }

  PlanarPeaks run(const PlanarDrive& drive, double rest_time);

 private:
  struct State {
    std::array<double, kMaxModes> x{}, y{}, vx{}, vy{};
    double phi{}, spin{};
  };

  void sub_step(const PlanarDrive& drive, std::size_t piece, bool rest, double t0, double H,
                SubStep& out);
  void sample(const SubStep& s, std::size_t m, std::vector<double>& t,
              std::vector<double>& f) const;
  [[nodiscard]] Jet jet(double t) const;
  [[nodiscard]] double height_now() const;
  [[nodiscard]] double free_bound() const;
  [[nodiscard]] PlanarPeak window_peak(const std::vector<double>& t,
                                       const std::vector<double>& f) const;
  [[nodiscard]] PlanarPeak refine(double lo, double hi, double t, double f) const;

  PlanarOptions options_;
  double vortex_gain_{}, fill_{}, w1_{}, sample_step_{};
  bool spin_{};
  std::vector<Mode> modes_;
  State state_;
  std::vector<SubStep> steps_;
};

void ExactPlanarLinear::sub_step(const PlanarDrive& drive, std::size_t piece, bool rest, double t0,
                                 double H, SubStep& out) {
  out.t0 = t0;
  out.H = H;
  Coeffs qx{}, qy{}, th{};
  if (!rest) {
    const ChebyshevFit& fit = chebyshev();
    Coeffs ax{}, ay{}, td{};
    for (std::size_t j = 0; j < kTerms; ++j) {
      const PlanarExcitation e = drive.excitation(piece, t0 + fit.node[j] * H);
      ax[j] = -e.ax;
      ay[j] = -e.ay;
      td[j] = e.theta_dot;
    }
    qx = fit.fit(ax);
    qy = fit.fit(ay);
    if (spin_) th = fit.fit(td);
  }
  out.px.fill(0.0);
  out.py.fill(0.0);
  const double inv_h = 1.0 / H, inv_h2 = inv_h * inv_h;
  for (std::size_t n = 0; n < modes_.size(); ++n) {
    const Mode& md = modes_[n];
    const double a1 = md.two_zw * inv_h;
    auto particular = [&](const Coeffs& q) {
      Coeffs r{};
      for (std::size_t k = kTerms; k-- > 0;) {
        double v = q[k];
        if (k + 1 < kTerms) v -= static_cast<double>(k + 1) * a1 * r[k + 1];
        if (k + 2 < kTerms) v -= static_cast<double>((k + 2) * (k + 1)) * inv_h2 * r[k + 2];
        r[k] = v / md.w2;
      }
      return r;
    };
    const Coeffs rx = particular(qx), ry = particular(qy);
    const double sigma = -md.lambda.real(), wd = md.lambda.imag();
    auto homogeneous = [&](const Coeffs& r, double x0, double v0) {
      const double c1 = x0 - r[0];
      const double c2 = (v0 - r[1] * inv_h + sigma * c1) / wd;
      return Complex(c1, -c2);
    };
    const Complex zx = homogeneous(rx, state_.x[n], state_.vx[n]);
    const Complex zy = homogeneous(ry, state_.y[n], state_.vy[n]);
    const Complex e = std::exp(md.lambda * H);
    double rx1 = 0.0, ry1 = 0.0, drx1 = 0.0, dry1 = 0.0;
    for (std::size_t k = 0; k < kTerms; ++k) {
      out.px[k] += md.gain * rx[k];
      out.py[k] += md.gain * ry[k];
      rx1 += rx[k];
      ry1 += ry[k];
      drx1 += static_cast<double>(k) * rx[k];
      dry1 += static_cast<double>(k) * ry[k];
    }
    out.zx[n] = md.gain * zx;
    out.zy[n] = md.gain * zy;
    state_.x[n] = rx1 + (zx * e).real();
    state_.y[n] = ry1 + (zy * e).real();
    state_.vx[n] = drx1 * inv_h + (md.lambda * zx * e).real();
    state_.vy[n] = dry1 * inv_h + (md.lambda * zy * e).real();
  }
  out.spin.fill(0.0);
  if (spin_) {
    const double nu = options_.kinematic_viscosity, fill = fill_;
    auto rhs = [nu, fill](double, double v, double a) {
      return ekman_rate(nu, fill, a, v) * (a - v);
    };
    auto acc = [&](std::size_t i) { return horner(th, kDopC[i]); };
    DopStep<double> step;
    const double f0 = rhs(state_.phi, state_.spin, th[0]);
    dop853_step(rhs, acc, state_.phi, state_.spin, f0, H, true, step, true);
    std::copy(step.v_poly.begin(), step.v_poly.end(), out.spin.begin());
    state_.phi = step.x1;
    state_.spin = step.v1;
  }
}

void ExactPlanarLinear::sample(const SubStep& s, std::size_t m, std::vector<double>& t,
                               std::vector<double>& f) const {
  const double dt = s.H / static_cast<double>(m);
  std::array<Complex, kMaxModes> rot{}, step{};
  for (std::size_t n = 0; n < modes_.size(); ++n) {
    rot[n] = 1.0;
    step[n] = std::exp(modes_[n].lambda * dt);
  }
  for (std::size_t j = 0; j < m; ++j) {
    const double u = static_cast<double>(j) / static_cast<double>(m);
    double ex = horner(s.px, u), ey = horner(s.py, u);
    for (std::size_t n = 0; n < modes_.size(); ++n) {
      const Complex zx = s.zx[n] * rot[n], zy = s.zy[n] * rot[n];
      ex += zx.real();
      ey += zy.real();
      rot[n] *= step[n];
    }
    double h = std::sqrt(ex * ex + ey * ey);
    if (spin_) {
      const double w = horner(s.spin, u);
      h += vortex_gain_ * w * w;
    }
    t.push_back(s.t0 + static_cast<double>(j) * dt);
    f.push_back(h);
  }
}

Jet ExactPlanarLinear::jet(double t) const {
  const auto it = std::upper_bound(steps_.begin(), steps_.end(), t,
                                   [](double v, const SubStep& s) { return v < s.t0; });
  const SubStep& s = *(it == steps_.begin() ? it : it - 1);
  const double tau = t - s.t0, u = tau / s.H, ih = 1.0 / s.H;
  double ex = 0, ex1 = 0, ex2 = 0, ey = 0, ey1 = 0, ey2 = 0;
  horner_jet(s.px, u, ex, ex1, ex2);
  horner_jet(s.py, u, ey, ey1, ey2);
  ex1 *= ih;
  ey1 *= ih;
  ex2 *= ih * ih;
  ey2 *= ih * ih;
  for (std::size_t n = 0; n < modes_.size(); ++n) {
    const Complex l = modes_[n].lambda;
    const SinCos sc = fast_sincos(l.imag() * tau);
    const Complex e = std::exp(l.real() * tau) * Complex(sc.cos, sc.sin);
    const Complex zx = s.zx[n] * e, zy = s.zy[n] * e;
    ex += zx.real();
    ey += zy.real();
    ex1 += (l * zx).real();
    ey1 += (l * zy).real();
    ex2 += (l * l * zx).real();
    ey2 += (l * l * zy).real();
  }
  Jet j;
  j.ex = ex;
  j.ey = ey;
  const double r = std::sqrt(ex * ex + ey * ey);
  if (r > 0.0) {
    const double dot = ex * ex1 + ey * ey1;
    j.f = r;
    j.d1 = dot / r;
    j.d2 = (ex1 * ex1 + ey1 * ey1 + ex * ex2 + ey * ey2) / r - dot * dot / (r * r * r);
  }
  if (spin_) {
    double w = 0, w1 = 0, w2 = 0;
    horner_jet(s.spin, u, w, w1, w2);
    j.f += vortex_gain_ * w * w;
    j.d1 += 2.0 * vortex_gain_ * w * w1 * ih;
    j.d2 += 2.0 * vortex_gain_ * (w1 * w1 + w * w2) * ih * ih;
  }
  return j;
}

double ExactPlanarLinear::height_now() const {
  double ex = 0.0, ey = 0.0;
  for (std::size_t n = 0; n < modes_.size(); ++n) {
    ex += modes_[n].gain * state_.x[n];
    ey += modes_[n].gain * state_.y[n];
  }
  return std::sqrt(ex * ex + ey * ey) + vortex_gain_ * state_.spin * state_.spin;
}

/// |r_n| <= sqrt(|r_n|^2 + |r_n'|^2 / w_n^2) for all later times in free motion; the spin only
/// decays once the container stops turning.
double ExactPlanarLinear::free_bound() const {
  double b = 0.0;
  for (std::size_t n = 0; n < modes_.size(); ++n) {
    const double r2 = state_.x[n] * state_.x[n] + state_.y[n] * state_.y[n];
    const double v2 = state_.vx[n] * state_.vx[n] + state_.vy[n] * state_.vy[n];
    b += std::abs(modes_[n].gain) * std::sqrt(r2 + v2 / modes_[n].w2);
  }
  return b + vortex_gain_ * state_.spin * state_.spin;
}

/// The root of f' in [lo, hi] from t by Newton's method kept inside the bracket (bisection when
/// a step leaves it or f'' >= 0).
PlanarPeak ExactPlanarLinear::refine(double lo, double hi, double t, double f) const {
  PlanarPeak best{f, t, 0.0};
  for (int it = 0; it < 60 && hi - lo > 1e-14; ++it) {
    const Jet j = jet(t);
    if (j.f > best.value) best = {j.f, t, std::atan2(j.ey, j.ex)};
    if (j.d1 == 0.0) break;
    if (j.d1 > 0.0) {
      lo = t;
    } else {
      hi = t;
    }
    const double next = t - j.d1 / j.d2;
    const double mid = 0.5 * (lo + hi);
    const double step = j.d2 < 0.0 && next > lo && next < hi ? next : mid;
    if (std::abs(step - t) < 1e-14) break;
    t = step;
  }
  const Jet j = jet(best.time);
  best.direction = std::atan2(j.ey, j.ex);
  return best;
}

PlanarPeak ExactPlanarLinear::window_peak(const std::vector<double>& t,
                                          const std::vector<double>& f) const {
  PlanarPeak best{-1.0, 0.0, 0.0};
  if (t.empty()) return {0.0, 0.0, 0.0};
  const double top = *std::max_element(f.begin(), f.end());
  const double threshold = top - kRefineFraction * std::abs(top);
  const std::size_t n = t.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (f[i] < threshold) continue;
    const bool left = i == 0 || f[i] >= f[i - 1];
    const bool right = i + 1 == n || f[i] >= f[i + 1];
    if (!left || !right) continue;
    PlanarPeak p{f[i], t[i], 0.0};
    if (i > 0 && i + 1 < n) p = refine(t[i - 1], t[i + 1], t[i], f[i]);
    if (p.value > best.value) {
      best = p;
      const Jet j = jet(best.time);
      best.direction = std::atan2(j.ey, j.ex);
    }
  }
  return best;
}

PlanarPeaks ExactPlanarLinear::run(const PlanarDrive& drive, double rest_time) {
  spin_ = drive.turns() && vortex_gain_ > 0.0;
  const double T = drive.duration();
  const std::vector<DrivePiece>& pieces = drive.pieces();
  const double h_max =
      std::min(options_.max_step, 2.0 * std::numbers::pi / w1_ / kFitStepsPerPeriod);
  PlanarPeaks peaks;
  std::vector<double> ts, fs;
  ts.reserve(static_cast<std::size_t>((T + rest_time) / sample_step_) + pieces.size() + 8);
  fs.reserve(ts.capacity());
  double best_rest = 0.0;
  for (std::size_t k = 0; k <= pieces.size(); ++k) {
    const bool rest = k == pieces.size();
    if (rest) {  // the motion window ends with its end point
      ts.push_back(T);
      fs.push_back(height_now());
      peaks.motion = window_peak(ts, fs);
      ts.clear();
      fs.clear();
    }
    const DrivePiece p = rest ? DrivePiece{T, T + rest_time} : pieces[k];
    const double L = p.t_end - p.t_begin;
    if (!(L > 0.0)) continue;
    const std::size_t n =
        step_count(L, piece_max_step(h_max, p.harmonic_omega, kFitStepsPerPeriod), 1);
    const double H = L / static_cast<double>(n);
    const std::size_t m = step_count(H, sample_step_, 1);
    bool done = false;
    for (std::size_t j = 0; j < n && !done; ++j) {
      steps_.emplace_back();
      sub_step(drive, k, rest, p.t_begin + H * static_cast<double>(j), H, steps_.back());
      const std::size_t first = fs.size();
      sample(steps_.back(), m, ts, fs);
      if (rest) {
        for (std::size_t i = first; i < fs.size(); ++i) best_rest = std::max(best_rest, fs[i]);
        done = free_bound() <= best_rest;
      }
    }
    if (rest && !done) {
      ts.push_back(T + rest_time);
      fs.push_back(height_now());
    }
  }
  peaks.rest = window_peak(ts, fs);
  return peaks;
}

}  // namespace

std::optional<PlanarPeaks> exact_planar_linear_peaks(const SloshingModel& model,
                                                     const PlanarDrive& drive, double rest_time,
                                                     const PlanarOptions& options) {
  if (drive.vertical() || !(model.zeta < 1.0)) return std::nullopt;
  ExactPlanarLinear solver(model, options, vortex_gain(model, options));
  return solver.run(drive, rest_time);
}

}  // namespace slosh::detail
