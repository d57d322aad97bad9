// Peaks of the planar linear model solved exactly piece by piece (planar_response.hpp): on
// sub-steps of a drive piece the horizontal acceleration is interpolated by a degree-7
// polynomial at Chebyshev nodes (error ~ (W H / 2)^8 / (2^7 8!) of the forcing for content at
// W rad/s, below 1e-9 for the sub-steps used), and every mode's response to a polynomial
// forcing is a polynomial particular solution plus the damped homogeneous one in closed form,
// so no step follows the fastest mode's period (on an arc the sub-steps also take
// kFitStepsPerTurn per turn of the heading, with which the forcing turns). The height
// |E| + R^2 w_l^2 / (4 g) is sampled at min(1 ms, fastest period / 64, 1/64 of a turn of the
// heading) by complex rotation (as linear_peaks.cpp) and every sampled
// local maximum within 5 % of the best sample is refined by safeguarded Newton steps on its
// exact derivatives. The liquid's spin is the SpinTrack's (planar_spin.hpp), on the same
// sub-steps. Applies when the effective gravity is constant (no vertical motion) and every mode
// is under-damped; else the caller integrates.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "plain_complex.hpp"
#include "response/planar_linear_exact.hpp"
#include "response/planar_scheme.hpp"
#include "response/planar_spin.hpp"
#include "sincos.hpp"

// One clone for AVX (4 doubles a vector; no FMA and no reassociation, so the same numbers as the
// baseline SSE2 clone bit for bit), chosen at load time where the CPU has it.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SLOSH_PLANAR_LINEAR_CLONES __attribute__((target_clones("avx", "default")))
#else
#define SLOSH_PLANAR_LINEAR_CLONES
#endif

namespace slosh::detail {

namespace {

constexpr std::size_t kTerms{kFitTerms};
using Coeffs = FitPoly;

/// A mode whose omega H is below this is stepped by its Taylor series in u instead of the
/// polynomial particular solution plus the homogeneous one: the particular solution's
/// coefficients r_k carry q_{k+j} (k+j)! / (omega H)^(2j) and cancel against the homogeneous
/// amplitude when omega H is small (a sub-step of 1e-16 s at a path join, a trajectory sampled
/// at 20 kHz), while the series' terms fall like (omega H)^j / j! there.
constexpr double kSeriesLimit{1.0};
/// Terms of the solution polynomial of a sub-step: the Taylor series at omega H <= 1 drops
/// terms below 1 / 24! ~ 2e-24 of the state.
constexpr std::size_t kSolTerms{24};
/// A mode stepped by its series at omega H at or above this is sampled in the closed form
/// (polynomial plus phasor) all the same: the samples only locate the candidates that the
/// series' exact derivatives refine (jet()), and there the closed form's cancellation costs at
/// most ~7! / (omega H)^6 ~ 3e5 ulp, while the series' 24-term polynomial would cost three
/// times the sampling's multiply-adds.
constexpr double kSampleClosedLimit{0.5};
using SolPoly = std::array<double, kSolTerms>;

/// Candidates within this fraction of the best sample are refined (as find_max()).
constexpr double kRefineFraction{0.05};
/// A candidate this far below the best refined peak is not refined [-] (window_peak()).
constexpr double kRefineGain{0.01};

/// p, p', p'' in u of the first `terms` coefficients.
template <std::size_t N>
void horner_jet(const std::array<double, N>& c, double u, double& p, double& d1, double& d2,
                std::size_t terms = N) {
  p = c[terms - 1];
  d1 = 0.0;
  d2 = 0.0;
  for (std::size_t k = terms - 1; k > 0; --k) {
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
template <std::size_t M>
struct SubStep {
  double t0{}, H{};
  bool forced{};              ///< px, py are not zero (the rest window's modes are all homogeneous)
  std::size_t terms{kTerms};  ///< coefficients of px, py in use
  SolPoly px{}, py{};
  Coeffs spin{};
  std::array<Complex, M> zx{}, zy{};
  /// The sampling's own form when a mode is stepped by its series at omega H >=
  /// kSampleClosedLimit (else the sampling uses the form above): every mode as the polynomial
  /// sx, sy of kTerms coefficients plus its phasor.
  bool sample_apart{};
  Coeffs sx{}, sy{};
  std::array<Complex, M> szx{}, szy{};
};

/// Height and its first two time derivatives.
struct Jet {
  double f{}, d1{}, d2{}, ex{}, ey{};
};

template <std::size_t M>
class ExactPlanarLinear {
 public:
  ExactPlanarLinear(const SloshingModel& model, const PlanarOptions& options, double vortex_gain)
      : model_(&model), options_(options), vortex_gain_(vortex_gain) {
    double w_max = 0.0;
    for (std::size_t n = 0; n < M; ++n) {
      const double w = model.omega[n];
      modes_[n] = {w, w * w, 2.0 * model.zeta * w, model.eta_gain[n],
                   Complex{-model.zeta * w, w * std::sqrt(1.0 - model.zeta * model.zeta)}};
      w_max = std::max(w_max, w);
    }
    sample_step_ = std::min(kMaxPeakStep, 2.0 * std::numbers::pi / w_max / kSamplesPerPeriod);
  }

  PlanarPeaks run(const PlanarDrive& drive, double rest_time);

 private:
  struct State {
    std::array<double, M> x{}, y{}, vx{}, vy{};
    double spin{};  // the liquid's spin rate at the current time [rad/s]
  };

  void sub_step(const PlanarDrive& drive, std::size_t piece, bool rest, double t0, double H,
                SubStep<M>& out);
  void series_step(const Mode& md, std::size_t n, const Coeffs& qx, const Coeffs& qy, double H,
                   SubStep<M>& out);
  /// Mode n's response on each axis to the forcing polynomials qx, qy over a sub-step of
  /// 1 / inv_h seconds from the current state: the particular polynomial r(u) plus
  /// Re(z exp(lambda H u)).
  struct ClosedForm {
    Coeffs r{};
    Complex z;
  };
  [[nodiscard]] std::array<ClosedForm, 2> closed_forms(const Mode& md, std::size_t n,
                                                       const Coeffs& qx, const Coeffs& qy,
                                                       double inv_h) const;
  void sample(const SubStep<M>& s, std::size_t m, std::vector<double>& t,
              std::vector<double>& f) const;
  [[nodiscard]] Jet jet(double t) const;
  [[nodiscard]] double height_now() const;
  [[nodiscard]] double free_bound(double horizon) const;
  [[nodiscard]] PlanarPeak window_peak(const std::vector<double>& t,
                                       const std::vector<double>& f) const;
  [[nodiscard]] PlanarPeak refine(double lo, double hi, double t, double f) const;

  const SloshingModel* model_;
  PlanarOptions options_;
  double vortex_gain_{}, sample_step_{};
  bool spin_{};
  std::array<Mode, M> modes_{};
  SpinTrack spin_track_;
  State state_;
  std::vector<SubStep<M>> steps_;
};

// Both axes in one loop: two independent recurrences (each a chain of divisions) overlap.
template <std::size_t M>
std::array<typename ExactPlanarLinear<M>::ClosedForm, 2> ExactPlanarLinear<M>::closed_forms(
    const Mode& md, std::size_t n, const Coeffs& qx, const Coeffs& qy, double inv_h) const {
  const double a1 = md.two_zw * inv_h, inv_h2 = inv_h * inv_h;
  std::array<ClosedForm, 2> c;
  Coeffs& rx = c[0].r;
  Coeffs& ry = c[1].r;
  for (std::size_t k = kTerms; k-- > 0;) {
    double vx = qx[k], vy = qy[k];
    if (k + 1 < kTerms) {
      vx -= static_cast<double>(k + 1) * a1 * rx[k + 1];
      vy -= static_cast<double>(k + 1) * a1 * ry[k + 1];
    }
    if (k + 2 < kTerms) {
      vx -= static_cast<double>((k + 2) * (k + 1)) * inv_h2 * rx[k + 2];
      vy -= static_cast<double>((k + 2) * (k + 1)) * inv_h2 * ry[k + 2];
    }
    rx[k] = vx / md.w2;
    ry[k] = vy / md.w2;
  }
  const double sigma = -md.lambda.real(), wd = md.lambda.imag();
  auto phasor = [&](const Coeffs& r, double x0, double v0) {
    const double c1 = x0 - r[0];
    const double c2 = (v0 - r[1] * inv_h + sigma * c1) / wd;
    return Complex{c1, -c2};
  };
  c[0].z = phasor(rx, state_.x[n], state_.vx[n]);
  c[1].z = phasor(ry, state_.y[n], state_.vy[n]);
  return c;
}

template <std::size_t M>
void ExactPlanarLinear<M>::sub_step(const PlanarDrive& drive, std::size_t piece, bool rest,
                                    double t0, double H, SubStep<M>& out) {
  out.t0 = t0;
  out.H = H;
  out.forced = !rest;
  Coeffs qx{}, qy{};
  if (!rest) {
    const ChebyshevFit& fit = chebyshev();
    Coeffs ax{}, ay{};
    for (std::size_t j = 0; j < kTerms; ++j) {
      const PlanarExcitation e = drive.excitation(piece, t0 + fit.node[j] * H);
      ax[j] = -e.ax;
      ay[j] = -e.ay;
    }
    qx = fit.fit(ax);
    qy = fit.fit(ay);
  }
  out.px.fill(0.0);
  out.py.fill(0.0);
  out.terms = kTerms;
  out.sample_apart = false;
  out.sx.fill(0.0);
  out.sy.fill(0.0);
  bool series_only = false;  // a series mode too fast-stepped for the closed form
  const double inv_h = 1.0 / H;
  for (std::size_t n = 0; n < M; ++n) {
    const Mode& md = modes_[n];
    const double wh = md.w * H;
    if (wh < kSeriesLimit) {
      if (wh >= kSampleClosedLimit) {
        const auto [cx, cy] = closed_forms(md, n, qx, qy, inv_h);
        for (std::size_t k = 0; k < kTerms; ++k) {
          out.sx[k] += md.gain * cx.r[k];
          out.sy[k] += md.gain * cy.r[k];
        }
        out.szx[n] = md.gain * cx.z;
        out.szy[n] = md.gain * cy.z;
        out.sample_apart = true;
      } else {
        series_only = true;
      }
      series_step(md, n, qx, qy, H, out);
      continue;
    }
    const auto [cx, cy] = closed_forms(md, n, qx, qy, inv_h);
    const Coeffs& rx = cx.r;
    const Coeffs& ry = cy.r;
    const Complex zx = cx.z, zy = cy.z;
    const Complex e = exp_of(md.lambda, H);
    double rx1 = 0.0, ry1 = 0.0, drx1 = 0.0, dry1 = 0.0;
    for (std::size_t k = 0; k < kTerms; ++k) {
      out.px[k] += md.gain * rx[k];
      out.py[k] += md.gain * ry[k];
      out.sx[k] += md.gain * rx[k];
      out.sy[k] += md.gain * ry[k];
      rx1 += rx[k];
      ry1 += ry[k];
      drx1 += static_cast<double>(k) * rx[k];
      dry1 += static_cast<double>(k) * ry[k];
    }
    out.zx[n] = md.gain * zx;
    out.zy[n] = md.gain * zy;
    out.szx[n] = out.zx[n];
    out.szy[n] = out.zy[n];
    state_.x[n] = rx1 + (zx * e).real();
    state_.y[n] = ry1 + (zy * e).real();
    state_.vx[n] = drx1 * inv_h + (md.lambda * zx * e).real();
    state_.vy[n] = dry1 * inv_h + (md.lambda * zy * e).real();
  }
  if (series_only) out.sample_apart = false;
  out.spin.fill(0.0);
  if (spin_) {
    out.spin = spin_track_.pieces()[steps_.size() - 1].w;  // the same sub-steps, in order
    state_.spin = horner(out.spin, 1.0);
  }
}

/// Mode n over the sub-step as its Taylor series in u: with s(u) = x(t0 + u H),
/// s'' + 2 zeta omega H s' + (omega H)^2 s = H^2 q(u), s(0) = x0, s'(0) = v0 H, so
/// (j + 2)(j + 1) s_{j+2} = H^2 q_j - 2 zeta omega H (j + 1) s_{j+1} - (omega H)^2 s_j.
/// Every term is a sum of small parts (no cancellation) for any H >= 0; at omega H < 1 the
/// terms beyond kSolTerms are below 1 / kSolTerms! of the state. The mode's amplitude is all in
/// the polynomial (z = 0).
template <std::size_t M>
void ExactPlanarLinear<M>::series_step(const Mode& md, std::size_t n, const Coeffs& qx,
                                       const Coeffs& qy, double H, SubStep<M>& out) {
  const double b = md.two_zw * H, g = md.w2 * H * H, h2 = H * H;
  // Both axes in one loop: two independent recurrences (each a chain of divisions) overlap.
  SolPoly sx{}, sy{};
  sx[0] = state_.x[n];
  sx[1] = state_.vx[n] * H;
  sy[0] = state_.y[n];
  sy[1] = state_.vy[n] * H;
  for (std::size_t j = 0; j + 2 < kSolTerms; ++j) {
    const double fx = j < kTerms ? h2 * qx[j] : 0.0, fy = j < kTerms ? h2 * qy[j] : 0.0;
    const double bj = static_cast<double>(j + 1), den = static_cast<double>((j + 2) * (j + 1));
    sx[j + 2] = (fx - b * bj * sx[j + 1] - g * sx[j]) / den;
    sy[j + 2] = (fy - b * bj * sy[j + 1] - g * sy[j]) / den;
  }
  double x1 = 0.0, y1 = 0.0, dx1 = 0.0, dy1 = 0.0, scale = 0.0;
  for (std::size_t k = 0; k < kSolTerms; ++k) {
    out.px[k] += md.gain * sx[k];
    out.py[k] += md.gain * sy[k];
    x1 += sx[k];
    y1 += sy[k];
    dx1 += static_cast<double>(k) * sx[k];
    dy1 += static_cast<double>(k) * sy[k];
    scale += std::abs(sx[k]) + std::abs(sy[k]);
  }
  // Terms below round-off of the whole are not evaluated when sampling.
  std::size_t terms = kSolTerms;
  while (terms > kTerms && std::abs(sx[terms - 1]) + std::abs(sy[terms - 1]) <= 1e-18 * scale) {
    --terms;
  }
  out.terms = std::max(out.terms, terms);
  out.forced = true;
  out.zx[n] = {};
  out.zy[n] = {};
  state_.x[n] = x1;
  state_.y[n] = y1;
  state_.vx[n] = dx1 / H;
  state_.vy[n] = dy1 / H;
}

/// Samples evaluated together: the polynomials' Horner recurrences and the modes' phasors of
/// kBlock samples are independent, so the loops over a block run at the vector units'
/// throughput instead of waiting on one sample's chain of dependent operations.
constexpr std::size_t kBlock{8};
using Block = std::array<double, kBlock>;

/// c(u_b) for every u_b of the block, by Horner's rule on the first `terms` coefficients.
template <std::size_t N>
void horner_block(const std::array<double, N>& c, std::size_t terms, const Block& u, Block& r) {
  r.fill(c[terms - 1]);
  for (std::size_t k = terms - 1; k > 0; --k) {
    const double ck = c[k - 1];
    for (std::size_t b = 0; b < kBlock; ++b) r[b] = r[b] * u[b] + ck;
  }
}

template <std::size_t M>
void ExactPlanarLinear<M>::sample(const SubStep<M>& s, std::size_t m, std::vector<double>& t,
                                  std::vector<double>& f) const {
  const double dt = s.H / static_cast<double>(m);
  // Each mode's phasor at the block's samples is its value at the block's start times
  // exp(lambda dt b): those powers are the same for every block, so the samples of a block are
  // independent products (no chain from sample to sample within the block).
  std::array<Complex, M> start{}, advance{};
  std::array<Block, M> pow_re{}, pow_im{};
  for (std::size_t n = 0; n < M; ++n) {
    const Complex step = exp_of(modes_[n].lambda, dt);
    Complex p{1.0, 0.0};
    for (std::size_t b = 0; b < kBlock; ++b) {
      pow_re[n][b] = p.re;
      pow_im[n][b] = p.im;
      p = p * step;
    }
    advance[n] = p;
    start[n] = {1.0, 0.0};
  }
  const std::size_t first = f.size();
  t.resize(first + m);
  f.resize(first + m);
  double* tp = t.data() + first;
  double* fp = f.data() + first;
  const double du = 1.0 / static_cast<double>(m);
  const std::array<Complex, M>& zx = s.sample_apart ? s.szx : s.zx;
  const std::array<Complex, M>& zy = s.sample_apart ? s.szy : s.zy;
  Block u{}, ex{}, ey{}, w{};
  for (std::size_t j0 = 0; j0 < m; j0 += kBlock) {
    // A last, partial block is evaluated whole (its extra samples are not stored).
    const std::size_t count = std::min(kBlock, m - j0);
    for (std::size_t b = 0; b < kBlock; ++b) u[b] = static_cast<double>(j0 + b) * du;
    if (s.sample_apart) {
      horner_block(s.sx, kTerms, u, ex);
      horner_block(s.sy, kTerms, u, ey);
    } else if (s.forced) {
      horner_block(s.px, s.terms, u, ex);
      horner_block(s.py, s.terms, u, ey);
    } else {
      ex.fill(0.0);
      ey.fill(0.0);
    }
    for (std::size_t n = 0; n < M; ++n) {
      const Complex ax = zx[n] * start[n], ay = zy[n] * start[n];
      for (std::size_t b = 0; b < kBlock; ++b) {
        ex[b] += ax.re * pow_re[n][b] - ax.im * pow_im[n][b];
        ey[b] += ay.re * pow_re[n][b] - ay.im * pow_im[n][b];
      }
      start[n] = start[n] * advance[n];
    }
    for (std::size_t b = 0; b < kBlock; ++b) ex[b] = std::sqrt(ex[b] * ex[b] + ey[b] * ey[b]);
    if (spin_) {
      horner_block(s.spin, kFitTerms, u, w);
      for (std::size_t b = 0; b < kBlock; ++b) ex[b] += vortex_gain_ * w[b] * w[b];
    }
    for (std::size_t b = 0; b < count; ++b) {
      tp[j0 + b] = s.t0 + static_cast<double>(j0 + b) * dt;
      fp[j0 + b] = ex[b];
    }
  }
}

template <std::size_t M>
Jet ExactPlanarLinear<M>::jet(double t) const {
  const auto it = std::upper_bound(steps_.begin(), steps_.end(), t,
                                   [](double v, const SubStep<M>& s) { return v < s.t0; });
  const SubStep<M>& s = *(it == steps_.begin() ? it : it - 1);
  const double tau = t - s.t0, u = tau / s.H, ih = 1.0 / s.H;
  double ex = 0, ex1 = 0, ex2 = 0, ey = 0, ey1 = 0, ey2 = 0;
  horner_jet(s.px, u, ex, ex1, ex2, s.terms);
  horner_jet(s.py, u, ey, ey1, ey2, s.terms);
  ex1 *= ih;
  ey1 *= ih;
  ex2 *= ih * ih;
  ey2 *= ih * ih;
  for (std::size_t n = 0; n < M; ++n) {
    const Complex l = modes_[n].lambda;
    const Complex e = exp_of(l, tau);
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

template <std::size_t M>
double ExactPlanarLinear<M>::height_now() const {
  double ex = 0.0, ey = 0.0;
  for (std::size_t n = 0; n < M; ++n) {
    ex += modes_[n].gain * state_.x[n];
    ey += modes_[n].gain * state_.y[n];
  }
  return std::sqrt(ex * ex + ey * ey) + vortex_gain_ * state_.spin * state_.spin;
}

/// Each mode's reach up to the horizon (oscillator_reach_over); the spin only decays once the
/// container stops turning.
template <std::size_t M>
double ExactPlanarLinear<M>::free_bound(double horizon) const {
  double b = 0.0;
  for (std::size_t n = 0; n < M; ++n) {
    const double qx = state_.x[n], qy = state_.y[n], vx = state_.vx[n], vy = state_.vy[n];
    const double e = 0.5 * ((vx * vx + vy * vy) / modes_[n].w2 + qx * qx + qy * qy);
    const double l = qx * vy - qy * vx;
    b += std::abs(modes_[n].gain) *
         std::sqrt(
             oscillator_reach_over(e, l * l / modes_[n].w2, 0.0, 0.5 * modes_[n].two_zw, horizon));
  }
  return b + vortex_gain_ * state_.spin * state_.spin;
}

/// The root of f' in [lo, hi] from t by Newton's method kept inside the bracket (bisection when
/// a step leaves it or f'' >= 0).
template <std::size_t M>
PlanarPeak ExactPlanarLinear<M>::refine(double lo, double hi, double t, double f) const {
  PlanarPeak best{f, t, 0.0};
  bool refined = false;
  for (int it = 0; it < 60 && hi - lo > 1e-14; ++it) {
    const Jet j = jet(t);
    if (j.f > best.value) {
      best = {j.f, t, std::atan2(j.ey, j.ex)};
      refined = true;
    }
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
  // An improved best carries its direction already (from the jet at its very time).
  if (!refined) {
    const Jet j = jet(best.time);
    best.direction = std::atan2(j.ey, j.ex);
  }
  return best;
}

template <std::size_t M>
PlanarPeak ExactPlanarLinear<M>::window_peak(const std::vector<double>& t,
                                             const std::vector<double>& f) const {
  if (t.empty()) return {0.0, 0.0, 0.0};
  double top = f.front();  // a plain loop (it vectorises; max_element's branches do not)
  for (double v : f) top = std::max(top, v);
  const double threshold = top - kRefineFraction * std::abs(top);
  const std::size_t n = t.size();
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < n; ++i) {
    if (f[i] < threshold) continue;
    const bool left = i == 0 || f[i] >= f[i - 1];
    const bool right = i + 1 == n || f[i] >= f[i + 1];
    if (left && right) candidates.push_back(i);
  }
  // Highest samples first; a candidate whose sample is more than kRefineGain below the best
  // refined peak cannot exceed it (between samples at most 1/64 of the fastest period apart
  // the height rises above its best sample by less than (4 pi / 64)^2 / 8 = 0.5 %).
  std::sort(candidates.begin(), candidates.end(),
            [&f](std::size_t a, std::size_t b) { return f[a] > f[b]; });
  PlanarPeak best{-1.0, 0.0, 0.0};
  bool directed = false;  // best.direction is that of the jet at best.time (refine()'s)
  for (std::size_t i : candidates) {
    if (f[i] < best.value * (1.0 - kRefineGain)) break;
    PlanarPeak p{f[i], t[i], 0.0};
    const bool interior = i > 0 && i + 1 < n;
    if (interior) p = refine(t[i - 1], t[i + 1], t[i], f[i]);
    if (p.value > best.value) {
      best = p;
      directed = interior;
    }
  }
  if (!directed) {
    const Jet j = jet(best.time);
    best.direction = std::atan2(j.ey, j.ex);
  }
  return best;
}

template <std::size_t M>
PlanarPeaks ExactPlanarLinear<M>::run(const PlanarDrive& drive, double rest_time) {
  spin_ = drive.turns() && vortex_gain_ > 0.0;
  if (spin_) spin_track_ = SpinTrack(drive, rest_time, *model_, options_);
  const double T = drive.duration();
  const std::vector<DrivePiece>& pieces = drive.pieces();
  const double h_fit = fit_step(*model_, options_);
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
    const std::size_t n = fit_steps(L, h_fit, p);
    const double H = L / static_cast<double>(n);
    const std::size_t m =
        step_count(H, piece_max_step(sample_step_, p.heading_rate, kSamplesPerPeriod), 1);
    bool done = false;
    for (std::size_t j = 0; j < n && !done; ++j) {
      steps_.emplace_back();
      sub_step(drive, k, rest, p.t_begin + H * static_cast<double>(j), H, steps_.back());
      const std::size_t first = fs.size();
      sample(steps_.back(), m, ts, fs);
      if (rest) {
        for (std::size_t i = first; i < fs.size(); ++i) best_rest = std::max(best_rest, fs[i]);
        const double t_end = p.t_begin + H * static_cast<double>(j + 1);
        done = free_bound(T + rest_time - t_end) * (1.0 + kPlanarStopMargin) <= best_rest;
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

// flatten: the solution and the sampling are inlined, so the AVX clone's block loops are AVX.
SLOSH_PLANAR_LINEAR_CLONES [[gnu::flatten]] std::optional<PlanarPeaks> exact_planar_linear_peaks(
    const SloshingModel& model, const PlanarDrive& drive, double rest_time,
    const PlanarOptions& options) {
  if (drive.vertical() || !(model.zeta < 1.0)) return std::nullopt;
  const double gain = vortex_gain(model, options);
  switch (model.modes()) {
    case 1:
      return ExactPlanarLinear<1>(model, options, gain).run(drive, rest_time);
    case 2:
      return ExactPlanarLinear<2>(model, options, gain).run(drive, rest_time);
    case 3:
      return ExactPlanarLinear<3>(model, options, gain).run(drive, rest_time);
    case 4:
      return ExactPlanarLinear<4>(model, options, gain).run(drive, rest_time);
    case 5:
      return ExactPlanarLinear<5>(model, options, gain).run(drive, rest_time);
    default:
      return std::nullopt;
  }
}

}  // namespace slosh::detail
