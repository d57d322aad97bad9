#include "slosh/core/law/filtered_laws.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

namespace slosh {

MotionLaw make_base_law(BaseLaw base, double stroke, double duration) {
  switch (base) {
    case BaseLaw::kSevenSegmentUniform:
      return SevenSegmentLaw(uniform_durations(duration), stroke).law();
    case BaseLaw::kPoly5:
      return make_poly5_law(stroke, duration);
    case BaseLaw::kModifiedTrapezoid:
      return make_modified_trapezoid_law(stroke, duration);
  }
  return make_poly5_law(stroke, duration);
}

namespace {

/// Breakpoints closer than this are one [s].
constexpr double kBreakpointTolerance{1e-12};

// The piece `p` re-expressed in tau' = tau - delta (its local time shifted to start delta later),
// scaled by `factor`.
LawPiece shifted(const LawPiece& p, double delta, double factor) {
  LawPiece q;
  const auto& c = p.poly;
  // c(tau' + delta) = sum_m tau'^m sum_{n >= m} binom(n, m) c_n delta^(n - m)
  q.poly[0] = c[0] + delta * (c[1] + delta * (c[2] + delta * c[3]));
  q.poly[1] = c[1] + delta * (2.0 * c[2] + delta * 3.0 * c[3]);
  q.poly[2] = c[2] + delta * 3.0 * c[3];
  q.poly[3] = c[3];
  for (double& v : q.poly) v *= factor;
  if (p.harmonic_omega != 0.0) {
    const double w = p.harmonic_omega;
    const double cw = std::cos(w * delta);
    const double sw = std::sin(w * delta);
    q.harmonic_omega = w;
    q.harmonic_cos = factor * (p.harmonic_cos * cw + p.harmonic_sin * sw);
    q.harmonic_sin = factor * (p.harmonic_sin * cw - p.harmonic_cos * sw);
  }
  return q;
}

void add_into(LawPiece& sum, const LawPiece& term) {
  for (std::size_t i = 0; i < sum.poly.size(); ++i) sum.poly[i] += term.poly[i];
  if (term.harmonic_omega == 0.0) return;
  if (sum.harmonic_omega != 0.0 &&
      std::abs(sum.harmonic_omega - term.harmonic_omega) > 1e-12 * std::abs(sum.harmonic_omega)) {
    throw std::invalid_argument(
        "convolve: overlapping pieces carry harmonics of different frequencies");
  }
  sum.harmonic_omega = term.harmonic_omega;
  sum.harmonic_cos += term.harmonic_cos;
  sum.harmonic_sin += term.harmonic_sin;
}

std::vector<double> merged(std::vector<double> times) {
  std::sort(times.begin(), times.end());
  std::vector<double> out;
  for (double t : times) {
    if (out.empty() || t - out.back() > kBreakpointTolerance) out.push_back(t);
  }
  return out;
}

}  // namespace

double damped_period(double omega, double zeta) {
  return 2.0 * std::numbers::pi / (omega * std::sqrt(1.0 - zeta * zeta));
}

namespace {

constexpr double kTwoPi{2.0 * std::numbers::pi};

/// sigma = -zeta + i sqrt(1 - zeta^2): the mode's pole divided by omega.
std::complex<double> unit_pole(double zeta) {
  return {-zeta, std::sqrt(1.0 - zeta * zeta)};
}

/// Impulses of amplitudes a_j / sum(a) at t_j = j spacing [s].
InputShaper impulse_train(ShaperType type, const std::vector<double>& a, double spacing) {
  double sum = 0.0;
  for (double v : a) sum += v;
  InputShaper s;
  s.type = type;
  for (std::size_t j = 0; j < a.size(); ++j) {
    s.impulses.push_back({spacing * static_cast<double>(j), a[j] / sum});
  }
  return s;
}

/// The ZV family's damping compensation: a_j K^j.
std::vector<double> compensated(std::vector<double> a, double K) {
  double power = 1.0;
  for (double& v : a) {
    v *= power;
    power *= K;
  }
  return a;
}

// ---- The two- and three-hump EI shapers --------------------------------------------------------
// Designed in units of the undamped period (omega = 2 pi): times t [periods], frequencies as
// ratios r = w / omega. Sources: Singhose, Derezinski & Singer, "Extra-insensitive input shapers
// for controlling flexible spacecraft", JGCD 19(2) 1996, and Singhose, Porter, Tuttle & Singer,
// "Vibration reduction using multi-hump input shapers", JDSMC 119(2) 1997. The undamped closed
// forms are taken as Klipper's klippy/extras/shaper_defs.py (github Klipper3d/klipper) wrote them
// in its earlier get_2hump_ei_shaper / get_3hump_ei_shaper, with the ZV family's compensation K^j
// for damping (our fallback below); Klipper now uses Singhose's damped fits, cubics in zeta for
// V = 5 %, which the tests use as an independent check of the damped design solved here.

/// A hump design: amplitudes, times (t_0 = 0) [periods], ratios of the zeros and of the humps
/// off the design frequency, each ascending. ei2 has a zero at r = 1, ei3 a hump.
struct HumpDesign {
  std::vector<double> amplitudes, times, zeros, humps;
  bool hump_at_design{false};
};

/// Z(r) = sum_j A_j exp(2 pi r sigma (t_N - t_j)) and dZ/dr: shaper_residual = |Z|.
struct ResidualSum {
  std::complex<double> value, slope;
};

ResidualSum residual_sum(const HumpDesign& d, double r, std::complex<double> sigma) {
  ResidualSum z;
  const double tN = d.times.back();
  for (std::size_t j = 0; j < d.amplitudes.size(); ++j) {
    const std::complex<double> k = kTwoPi * sigma * (tN - d.times[j]);
    const std::complex<double> term = d.amplitudes[j] * std::exp(r * k);
    z.value += term;
    z.slope += k * term;
  }
  return z;
}

/// The unknowns [A_0 .. A_{n-1}, t_1 .. t_{n-1}, zeros, humps] of a design and back.
std::vector<double> unknowns(const HumpDesign& d) {
  std::vector<double> x = d.amplitudes;
  x.insert(x.end(), d.times.begin() + 1, d.times.end());
  x.insert(x.end(), d.zeros.begin(), d.zeros.end());
  x.insert(x.end(), d.humps.begin(), d.humps.end());
  return x;
}

HumpDesign with_unknowns(HumpDesign d, const std::vector<double>& x) {
  const std::size_t n = d.amplitudes.size();
  auto at = x.begin();
  std::copy(at, at + static_cast<long>(n), d.amplitudes.begin());
  std::copy(at + static_cast<long>(n), at + static_cast<long>(2 * n - 1), d.times.begin() + 1);
  at += static_cast<long>(2 * n - 1);
  std::copy(at, at + static_cast<long>(d.zeros.size()), d.zeros.begin());
  at += static_cast<long>(d.zeros.size());
  std::copy(at, at + static_cast<long>(d.humps.size()), d.humps.begin());
  return d;
}

/// The design conditions, scaled by V: unit sum; at each zero Re Z = Im Z = 0; at each hump
/// |Z| = V and d|Z|^2/dr = 0; at r = 1 a zero (ei2) or a hump (ei3). As many as unknowns.
std::vector<double> hump_conditions(const HumpDesign& d, double V, double zeta) {
  const std::complex<double> sigma = unit_pole(zeta);
  std::vector<double> f{-1.0};
  for (double a : d.amplitudes) f[0] += a;
  auto zero = [&](double r) {
    const std::complex<double> z = residual_sum(d, r, sigma).value / V;
    f.push_back(z.real());
    f.push_back(z.imag());
  };
  auto hump = [&](double r) {
    const ResidualSum z = residual_sum(d, r, sigma);
    f.push_back(std::norm(z.value) / (V * V) - 1.0);
    f.push_back(std::real(std::conj(z.value) * z.slope) / (kTwoPi * V * V));
  };
  d.hump_at_design ? hump(1.0) : zero(1.0);
  for (double r : d.zeros) zero(r);
  for (double r : d.humps) hump(r);
  return f;
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

/// Solves M y = b for y in b (M row-major m x m, partial pivoting); false when M is singular.
bool solve_linear(std::vector<double> M, std::vector<double>& b) {
  const std::size_t m = b.size();
  for (std::size_t c = 0; c < m; ++c) {
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < m; ++r) {
      if (std::abs(M[r * m + c]) > std::abs(M[pivot * m + c])) pivot = r;
    }
    if (!(std::abs(M[pivot * m + c]) > 0.0)) return false;
    for (std::size_t k = 0; k < m; ++k) std::swap(M[c * m + k], M[pivot * m + k]);
    std::swap(b[c], b[pivot]);
    for (std::size_t r = c + 1; r < m; ++r) {
      const double factor = M[r * m + c] / M[c * m + c];
      for (std::size_t k = c; k < m; ++k) M[r * m + k] -= factor * M[c * m + k];
      b[r] -= factor * b[c];
    }
  }
  for (std::size_t c = m; c-- > 0;) {
    for (std::size_t k = c + 1; k < m; ++k) b[c] -= M[c * m + k] * b[k];
    b[c] /= M[c * m + c];
  }
  return true;
}

/// Newton's method on the design conditions at (V, zeta) from `d`, with a central-difference
/// Jacobian (step 1e-7 on unknowns of order 0.1 to 3); nullopt unless every condition is within
/// 1e-12 (hump heights within 1e-12 V) after at most 30 steps.
std::optional<HumpDesign> solve_conditions(const HumpDesign& d, double V, double zeta) {
  constexpr int kMaxSteps{30};
  constexpr double kTolerance{1e-12};
  constexpr double kDifferenceStep{1e-7};
  std::vector<double> x = unknowns(d);
  const std::size_t m = x.size();
  auto conditions = [&](const std::vector<double>& y) {
    return hump_conditions(with_unknowns(d, y), V, zeta);
  };
  std::vector<double> f = conditions(x);
  const double start = max_abs(f);
  for (int step = 0; step < kMaxSteps; ++step) {
    const double size = max_abs(f);
    if (size <= kTolerance) return with_unknowns(d, x);
    if (!(size <= 1e3 * std::max(start, 1.0))) return std::nullopt;  // diverging or NaN
    std::vector<double> J(m * m);
    for (std::size_t c = 0; c < m; ++c) {
      std::vector<double> up = x, down = x;
      up[c] += kDifferenceStep;
      down[c] -= kDifferenceStep;
      const std::vector<double> fu = conditions(up), fd = conditions(down);
      for (std::size_t r = 0; r < m; ++r) J[r * m + c] = (fu[r] - fd[r]) / (2.0 * kDifferenceStep);
    }
    std::vector<double> dx(m);
    for (std::size_t r = 0; r < m; ++r) dx[r] = -f[r];
    if (!solve_linear(std::move(J), dx)) return std::nullopt;
    for (std::size_t c = 0; c < m; ++c) x[c] += dx[c];
    f = conditions(x);
  }
  if (max_abs(f) <= kTolerance) return with_unknowns(d, x);
  return std::nullopt;
}

/// The frequencies of a design in the order the undamped shaper has them: ei2 z h 1 h z, ei3
/// z h z 1 z h z.
std::vector<double> ordered_ratios(const HumpDesign& d) {
  if (!d.hump_at_design) return {d.zeros[0], d.humps[0], 1.0, d.humps[1], d.zeros[1]};
  return {d.zeros[0], d.humps[0], d.zeros[1], 1.0, d.zeros[2], d.humps[1], d.zeros[3]};
}

/// A shaper of the same shape as the undamped one: positive amplitudes, increasing times,
/// positive frequencies in the undamped order.
bool same_shape(const HumpDesign& d) {
  for (double a : d.amplitudes) {
    if (!(a > 0.0)) return false;
  }
  for (std::size_t j = 1; j < d.times.size(); ++j) {
    if (!(d.times[j] > d.times[j - 1])) return false;
  }
  const std::vector<double> r = ordered_ratios(d);
  if (!(r.front() > 0.0)) return false;
  for (std::size_t j = 1; j < r.size(); ++j) {
    if (!(r[j] > r[j - 1])) return false;
  }
  return true;
}

/// The undamped two-hump EI: t_j = j / 2, [a, 1/2 - a, 1/2 - a, a]; its residual
/// |g(c)| = |c (8a c^2 + 1 - 8a)| with c = cos(pi r / 2) vanishes at c = 0 and
/// c^2 = (8a - 1) / (8a) and peaks at c^2 = (8a - 1) / (24a).
HumpDesign undamped_ei2(double V) {
  double a = 0.125;  // V = 0: zvdd, the humps merged into a triple zero at omega
  if (V > 0.0) {
    const double X = std::cbrt(V * V * (std::sqrt(1.0 - V * V) + 1.0));
    a = (3.0 * X * X + 2.0 * X + 3.0 * V * V) / (16.0 * X);
  }
  const double c_zero = std::sqrt((8.0 * a - 1.0) / (8.0 * a));
  const double r_zero = 2.0 / std::numbers::pi * std::acos(c_zero);
  const double r_hump = 2.0 / std::numbers::pi * std::acos(c_zero / std::sqrt(3.0));
  return {{a, 0.5 - a, 0.5 - a, a},
          {0.0, 0.5, 1.0, 1.5},
          {r_zero, 2.0 - r_zero},
          {r_hump, 2.0 - r_hump},
          false};
}

/// The undamped three-hump EI: t_j = j / 2, [a1, a2, a3, a2, a1]; its residual
/// |g(c)| = |4 a1 c^2 + 2 a2 c + a3 - 2 a1| with c = cos(pi r) is V at c = -1 and at the vertex
/// c = -a2 / (4 a1), and vanishes at the two roots of g.
HumpDesign undamped_ei3(double V) {
  const double a1 = (1.0 + 3.0 * V + 2.0 * std::sqrt(2.0 * V * (V + 1.0))) / 16.0;
  const double a2 = (1.0 - V) / 4.0;
  const double a3 = 1.0 - 2.0 * a1 - 2.0 * a2;
  const double root = std::sqrt(std::max(0.0, a2 * a2 - 4.0 * a1 * (a3 - 2.0 * a1)));
  const double r1 = std::acos((-a2 + root) / (4.0 * a1)) / std::numbers::pi;
  const double r2 = std::acos((-a2 - root) / (4.0 * a1)) / std::numbers::pi;
  const double r_hump = std::acos(-a2 / (4.0 * a1)) / std::numbers::pi;
  return {{a1, a2, a3, a2, a1},
          {0.0, 0.5, 1.0, 1.5, 2.0},
          {r1, r2, 2.0 - r2, 2.0 - r1},
          {r_hump, 2.0 - r_hump},
          true};
}

/// The design continued in zeta from the undamped one (steps of at most 0.02, halved on a failure
/// down to 1e-4); nullopt when it fails or the residual between the outer zeros exceeds V.
std::optional<HumpDesign> damped_hump_design(HumpDesign d, double V, double zeta) {
  constexpr double kMaxZetaStep{0.02};
  constexpr double kMinZetaStep{1e-4};
  constexpr int kMaxAttempts{200};
  double reached = 0.0;
  double step = kMaxZetaStep;
  for (int attempt = 0; reached < zeta; ++attempt) {
    if (attempt == kMaxAttempts || step < kMinZetaStep) return std::nullopt;
    const double next = std::min(zeta, reached + step);
    std::optional<HumpDesign> solved = solve_conditions(d, V, next);
    if (solved && same_shape(*solved)) {
      d = std::move(*solved);
      reached = next;
      step = std::min(2.0 * step, kMaxZetaStep);
    } else {
      step /= 2.0;
    }
  }
  InputShaper s;
  for (std::size_t j = 0; j < d.amplitudes.size(); ++j) {
    s.impulses.push_back({d.times[j], d.amplitudes[j]});
  }
  const double worst =
      max_residual_over(s, kTwoPi * d.zeros.front(), kTwoPi * d.zeros.back(), zeta);
  if (!(worst <= V * (1.0 + 1e-9))) return std::nullopt;
  return d;
}

InputShaper multi_hump_shaper(ShaperType type, double omega, double zeta, double V) {
  const HumpDesign undamped = type == ShaperType::kEI2 ? undamped_ei2(V) : undamped_ei3(V);
  // Without damping the closed form is the design; with V = 0 its compensated form is exact (the
  // humps merge into a multiple zero at omega, as for zvdd).
  const bool closed_form_exact = zeta == 0.0 || V == 0.0;
  const std::optional<HumpDesign> d =
      closed_form_exact ? std::nullopt : damped_hump_design(undamped, V, zeta);
  if (!d) {
    const double K = std::exp(-zeta * std::numbers::pi / std::sqrt(1.0 - zeta * zeta));
    InputShaper s =
        impulse_train(type, compensated(undamped.amplitudes, K), damped_period(omega, zeta) / 2.0);
    s.exact_design = closed_form_exact;
    return s;
  }
  InputShaper s = impulse_train(type, d->amplitudes, 0.0);
  for (std::size_t j = 0; j < s.impulses.size(); ++j) {
    s.impulses[j].time = d->times[j] * kTwoPi / omega;
  }
  return s;
}

}  // namespace

InputShaper make_shaper(ShaperType type, double omega, double zeta, double residual) {
  if (!(omega > 0.0) || !std::isfinite(omega)) {
    throw std::invalid_argument("make_shaper: omega must be > 0");
  }
  if (!(zeta >= 0.0 && zeta < 1.0))
    throw std::invalid_argument("make_shaper: zeta must be in [0, 1)");
  if (!(residual >= 0.0 && residual < 1.0)) {
    throw std::invalid_argument("make_shaper: the EI residual must be in [0, 1)");
  }
  const double K = std::exp(-zeta * std::numbers::pi / std::sqrt(1.0 - zeta * zeta));
  const double half = damped_period(omega, zeta) / 2.0;
  switch (type) {
    case ShaperType::kZV:
      return impulse_train(type, {1.0, K}, half);
    case ShaperType::kZVD:
      return impulse_train(type, {1.0, 2.0 * K, K * K}, half);
    case ShaperType::kZVDD:
      return impulse_train(type, {1.0, 3.0 * K, 3.0 * K * K, K * K * K}, half);
    case ShaperType::kEI: {
      const double V = residual;
      const double p = (1.0 + V / K) / ((1.0 + K) * (1.0 + K));
      const double q = 2.0 * p - V / (K * K);
      return impulse_train(type, {p, q * K, p * K * K}, half);
    }
    case ShaperType::kMZV: {
      // 135 degrees apart: the undamped vectors a, b e^{i 3 pi / 4}, a e^{i 3 pi / 2} close; the
      // compensation K^(3/4) per impulse keeps them closed with damping (Klipper's get_mzv_shaper,
      // klippy/extras/shaper_defs.py, github Klipper3d/klipper: n = 3 impulses over 3/4 T_d).
      const double a = 1.0 - 1.0 / std::numbers::sqrt2;
      return impulse_train(type, compensated({a, std::numbers::sqrt2 - 1.0, a}, std::pow(K, 0.75)),
                           0.75 * half);
    }
    case ShaperType::kEI2:
    case ShaperType::kEI3:
      return multi_hump_shaper(type, omega, zeta, residual);
  }
  throw std::invalid_argument("make_shaper: unknown shaper type");
}

double shaper_residual(const InputShaper& shaper, double omega, double zeta) {
  const double t_end = shaper.delay();
  const std::complex<double> rate(-zeta * omega, omega * std::sqrt(1.0 - zeta * zeta));
  std::complex<double> z(0.0);
  for (const Impulse& i : shaper.impulses) z += i.amplitude * std::exp(rate * (t_end - i.time));
  return std::abs(z);
}

double max_residual_over(const InputShaper& shaper, double omega_lo, double omega_hi, double zeta) {
  constexpr double kSlopeSamplesPerPeriod{256.0};
  constexpr double kMaxSamples{1e7};
  if (shaper.impulses.empty()) throw std::invalid_argument("max_residual_over: no impulses");
  if (!(zeta >= 0.0 && zeta < 1.0)) {
    throw std::invalid_argument("max_residual_over: zeta must be in [0, 1)");
  }
  if (!(omega_lo >= 0.0 && omega_lo <= omega_hi && std::isfinite(omega_hi))) {
    throw std::invalid_argument("max_residual_over: needs 0 <= omega_lo <= omega_hi, finite");
  }
  const double tN = shaper.delay();
  const std::complex<double> sigma = unit_pole(zeta);
  // d|Z|^2/dw = 2 Re(conj(Z) Z'), Z(w) = sum_j A_j exp(w sigma (t_N - t_j)).
  auto slope = [&](double w) {
    std::complex<double> z, dz;
    for (const Impulse& i : shaper.impulses) {
      const std::complex<double> k = sigma * (tN - i.time);
      const std::complex<double> term = i.amplitude * std::exp(w * k);
      z += term;
      dz += k * term;
    }
    return std::real(std::conj(z) * dz);
  };
  auto residual = [&](double w) { return shaper_residual(shaper, w, zeta); };
  double best = std::max(residual(omega_lo), residual(omega_hi));
  if (!(tN > 0.0) || omega_hi == omega_lo) return best;
  const double samples = std::ceil((omega_hi - omega_lo) * tN * kSlopeSamplesPerPeriod / kTwoPi);
  if (samples > kMaxSamples) {
    throw std::invalid_argument("max_residual_over: the range spans more than 1e7 samples");
  }
  const auto n = std::max(1L, static_cast<long>(samples));
  double w0 = omega_lo, d0 = slope(omega_lo);
  for (long k = 1; k <= n; ++k) {
    const double w1 =
        k == n ? omega_hi
               : omega_lo + (omega_hi - omega_lo) * static_cast<double>(k) / static_cast<double>(n);
    const double d1 = slope(w1);
    if (d0 > 0.0 && d1 <= 0.0) {  // a maximum in [w0, w1]: bisect the slope to the last bit
      double a = w0, b = w1;
      for (double mid = 0.5 * (a + b); mid > a && mid < b; mid = 0.5 * (a + b)) {
        (slope(mid) > 0.0 ? a : b) = mid;
      }
      best = std::max({best, residual(a), residual(b)});
    }
    w0 = w1;
    d0 = d1;
  }
  return best;
}

MotionLaw convolve(const MotionLaw& base, const InputShaper& shaper) {
  struct Term {
    double begin, end;
    const LawPiece* piece;
    double factor;
  };
  std::vector<Term> terms;
  std::vector<double> times;
  for (const Impulse& i : shaper.impulses) {
    for (const LawPiece& p : base.pieces()) {
      if (p.duration() <= 0.0) continue;
      terms.push_back({p.t_begin + i.time, p.t_end + i.time, &p, i.amplitude});
      times.push_back(terms.back().begin);
      times.push_back(terms.back().end);
    }
  }
  times.push_back(0.0);
  const std::vector<double> cuts = merged(std::move(times));
  std::vector<LawPiece> pieces;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    LawPiece sum;
    sum.t_begin = cuts[k];
    sum.t_end = cuts[k + 1];
    const double mid = 0.5 * (cuts[k] + cuts[k + 1]);
    for (const Term& t : terms) {
      if (t.begin < mid && mid < t.end)
        add_into(sum, shifted(*t.piece, cuts[k] - t.begin, t.factor));
    }
    pieces.push_back(sum);
  }
  return MotionLaw(base.name() + "+" + to_string(shaper.type), std::move(pieces));
}

FirChain make_fir_chain(double stroke, double t1, double t2, double t3) {
  if (!(t1 > 0.0 && t2 > 0.0 && t3 > 0.0)) {
    throw std::invalid_argument("make_fir_chain: every filter duration must be > 0");
  }
  const std::array<double, 3> T{t1, t2, t3};
  // Jerk steps of +-stroke / (T1 T2 T3) at every subset sum.
  struct Step {
    double time;
    double sign;
  };
  std::vector<Step> steps;
  std::vector<double> times;
  for (int mask = 0; mask < 8; ++mask) {
    double time = 0.0;
    double sign = 1.0;
    for (int i = 0; i < 3; ++i) {
      if (mask & (1 << i)) {
        time += T[static_cast<std::size_t>(i)];
        sign = -sign;
      }
    }
    steps.push_back({time, sign});
    times.push_back(time);
  }
  const std::vector<double> cuts = merged(std::move(times));
  const double unit = stroke / (t1 * t2 * t3);
  std::vector<LawPiece> pieces;
  double a = 0.0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    double jerk = 0.0;
    for (const Step& s : steps) {
      if (s.time <= cuts[k] + kBreakpointTolerance) jerk += s.sign * unit;
    }
    LawPiece p;
    p.t_begin = cuts[k];
    p.t_end = cuts[k + 1];
    p.poly = {a, jerk, 0.0, 0.0};
    a += jerk * p.duration();
    pieces.push_back(p);
  }
  FirChain chain{t1, t2, t3, MotionLaw("fir_chain", std::move(pieces)), std::nullopt};
  if (t1 >= t2 + t3 - kBreakpointTolerance && t2 >= t3 - kBreakpointTolerance) {
    // The chain lasts t1 + t2 + t3; a plateau or cruise shorter than 1 ns is exactly 0.
    chain.durations =
        clean_durations(Durations{t3, std::max(0.0, t2 - t3), t3, std::max(0.0, t1 - t2 - t3), t3,
                                  std::max(0.0, t2 - t3), t3},
                        t1 + t2 + t3);
  }
  return chain;
}

}  // namespace slosh

namespace slosh {

IirFilter make_iir_filter(IirOrder order, double omega, double zeta, double tau,
                          double sample_period) {
  if (!(omega > 0.0) || !(zeta >= 0.0 && zeta < 1.0) || !(tau > 0.0) || !(sample_period > 0.0)) {
    throw std::invalid_argument(
        "make_iir_filter: omega, tau and the sample period must be > 0, zeta in [0, 1)");
  }
  // Long double: the coefficients are O(1e2) terms that cancel down to a DC gain of 1 over
  // (1 - e^(-tau Ts))^3 ~ 1e-5; in double that leaves ~1e-9 of the stroke.
  using R = long double;
  const R w = omega;
  const R Ts = sample_period;
  const R zeta_l = zeta;
  const R tau_l = tau;
  const R e1 = std::exp(-tau_l * Ts);
  const R e2 = e1 * e1;
  IirFilter f;
  f.order = order;
  f.tau = tau;
  f.sample_period = sample_period;
  if (order == IirOrder::kSecond) {
    const R Q = (tau_l / w) * (tau_l / w) / Ts;
    const R A = R(2) * (zeta_l * w * tau_l - w * w) / (tau_l * tau_l * tau_l);
    const R B = (w / tau_l) * (w / tau_l);
    const R C = -A;
    const R D = (tau_l * tau_l - R(2) * zeta_l * w * tau_l + w * w) / (tau_l * tau_l);
    f.a = {-R(2) * e1, e2};
    f.b = {Q * (A + C), Q * ((-R(2) * A - C + D * Ts) * e1 - A + B * Ts - R(2) * C),
           Q * (A * e2 + (R(2) * A - R(2) * B * Ts + R(2) * C - R(2) * D * Ts) * e1 + C),
           Q * ((-A + B * Ts) * e2 + (-C + D * Ts) * e1)};
  } else {
    const R e3 = e2 * e1;
    // The paper prints Q = tau^3 / (omega^2 T_s) * 1 / T_s; the extra 1/T_s makes the DC gain
    // 1/T_s instead of 1 (checked against the
    // continuous filter in tests): Q = tau^3 / (omega^2 T_s).
    const R Q = tau_l * tau_l * tau_l / (w * w * Ts);
    const R A = (R(2) * zeta_l * w * tau_l - R(3) * w * w) / (tau_l * tau_l * tau_l * tau_l);
    const R B = w * w / (tau_l * tau_l * tau_l);
    const R C = -A;
    const R D = -R(2) * (zeta_l * w * tau_l - w * w) / (tau_l * tau_l * tau_l);
    const R Db = D * Ts * e1;
    const R E = (tau_l * tau_l - R(2) * zeta_l * w * tau_l + w * w) / (tau_l * tau_l);
    const R Eb = E * Ts * Ts / R(2) * e1;
    f.a = {-R(3) * e1, R(3) * e2, -e3};
    f.b = {Q * (A + C), Q * ((-R(3) * A - R(2) * C) * e1 - A - R(2) * C + Db + Eb + B * Ts),
           Q * ((R(3) * A + C) * e2 + (R(3) * A - R(3) * B * Ts + R(4) * C - Db + Eb) * e1 + C -
                R(2) * Db - R(2) * Eb),
           Q * (-A * e3 + (-R(3) * A + R(3) * B * Ts - R(2) * C) * e2 +
                (-R(2) * C + R(2) * Db - R(2) * Eb) * e1 + Db + Eb),
           Q * ((A - B * Ts) * e3 + C * e2 + (-Db + Eb) * e1)};
  }
  return f;
}

std::vector<double> apply_iir(const IirFilter& f, const std::vector<double>& u,
                              std::size_t output_length) {
  if (u.empty()) return std::vector<double>(output_length, 0.0);
  auto input = [&](long k) {
    if (k < 0) return u.front();
    if (k >= static_cast<long>(u.size())) return u.back();
    return u[static_cast<std::size_t>(k)];
  };
  // Before 0 the filter rests at the input's initial value (DC gain 1).
  std::vector<long double> y(output_length);
  auto output = [&](long k) {
    return k < 0 ? static_cast<long double>(u.front()) : y[static_cast<std::size_t>(k)];
  };
  for (std::size_t n = 0; n < output_length; ++n) {
    const long k = static_cast<long>(n);
    long double v = 0.0;
    for (std::size_t i = 0; i < f.a.size(); ++i) v -= f.a[i] * output(k - 1 - static_cast<long>(i));
    for (std::size_t i = 0; i < f.b.size(); ++i) v += f.b[i] * input(k + 1 - static_cast<long>(i));
    y[n] = v;
  }
  return {y.begin(), y.end()};
}

}  // namespace slosh

namespace slosh {

namespace {

/// One filter pass: the output samples up to one past the last above the tail tolerance.
std::vector<double> filtered_samples(const MotionLaw& base, const IirFilter& f) {
  const double Ts = f.sample_period;
  const auto n = static_cast<std::size_t>(std::ceil(base.duration() / Ts - 1e-9)) + 1;
  std::vector<double> u(n);
  for (std::size_t k = 0; k < n; ++k) u[k] = base.at(static_cast<double>(k) * Ts).acceleration;
  u.back() = 0.0;  // at rest from the end of the base law on
  // The tail decays as t^2 e^(-tau t) at worst: 60 / tau is far below any tolerance.
  const auto tail = static_cast<std::size_t>(std::ceil(60.0 / (f.tau * Ts)));
  std::vector<double> y = apply_iir(f, u, n + tail);
  double peak = 0.0;
  for (double v : y) peak = std::max(peak, std::abs(v));
  std::size_t last = 0;
  for (std::size_t k = 0; k < y.size(); ++k) {
    if (std::abs(y[k]) > kIirTailTolerance * peak) last = k;
  }
  y.resize(last + 2);
  y.back() = 0.0;
  return y;
}

}  // namespace

namespace {

/// The delay compensation's best pass: the filtered samples of the longest filtered law that fits
/// in T, with the base duration and delay it came from.
struct CompensatedPass {
  std::vector<double> samples;  ///< empty when no pass fits
  double base_duration{};
  double delay{};
  double first_delay{};  ///< the delay measured on the base law of duration T
  int iterations{};
};

/// Delay compensation (paper sec. 4): base duration T - Delta T until the filtered law ends in
/// (T - T_s, T]; keeps the longest pass that fits when the sample grid makes it oscillate.
CompensatedPass compensate_delay(const std::function<MotionLaw(double)>& base,
                                 const IirFilter& filter, double T) {
  const double Ts = filter.sample_period;
  auto duration_of = [Ts](const std::vector<double>& y) {
    return static_cast<double>(y.size() - 1) * Ts;
  };
  CompensatedPass best;
  double base_duration = T;
  for (int pass = 0; pass < kIirMaxIterations; ++pass) {
    std::vector<double> y = filtered_samples(base(base_duration), filter);
    ++best.iterations;
    const double Tf = duration_of(y);
    const double delay = Tf - base_duration;
    if (pass == 0) best.first_delay = delay;
    if (Tf <= T + 1e-9 * T && (best.samples.empty() || Tf > duration_of(best.samples))) {
      best.base_duration = base_duration;
      best.delay = delay;
      best.samples = std::move(y);
      if (duration_of(best.samples) > T - Ts + 1e-9 * T) break;
    }
    base_duration = T - delay;
    if (!(base_duration >= kMinBaseDuration)) break;
  }
  return best;
}

/// Exact rest-to-rest: scales the knot accelerations `a` by (c0 + c1 t/T) so that the
/// hat-function integrals give v(T) = 0 and s(T) = stroke (w_v = int Lambda_k, w_s = int (T - t)
/// Lambda_k); returns the largest correction relative to the peak acceleration [-].
double correct_rest_to_rest(const std::vector<double>& t, std::vector<double>& a, double stroke,
                            double T) {
  const std::size_t m = t.size();
  double V0 = 0.0, V1 = 0.0, P0 = 0.0, P1 = 0.0, peak = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    double wv = 0.0, wt = 0.0;
    if (k > 0) {
      const double h = t[k] - t[k - 1];
      wv += 0.5 * h;
      wt += h * (0.5 * t[k] - h / 6.0);
    }
    if (k + 1 < m) {
      const double h = t[k + 1] - t[k];
      wv += 0.5 * h;
      wt += h * (0.5 * t[k] + h / 6.0);
    }
    const double ws = T * wv - wt;
    V0 += wv * a[k];
    V1 += wv * a[k] * t[k] / T;
    P0 += ws * a[k];
    P1 += ws * a[k] * t[k] / T;
    peak = std::max(peak, std::abs(a[k]));
  }
  const double det = V0 * P1 - V1 * P0;
  const double c0 = -V1 * stroke / det;
  const double c1 = V0 * stroke / det;
  double correction = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const double corrected = a[k] * (c0 + c1 * t[k] / T);
    correction = std::max(correction, std::abs(corrected - a[k]));
    a[k] = corrected;
  }
  return peak > 0.0 ? correction / peak : 0.0;
}

}  // namespace

IirLaw make_iir_law(const std::function<MotionLaw(double)>& base, const IirFilter& filter,
                    double stroke, double T) {
  const double Ts = filter.sample_period;
  IirLaw out;
  CompensatedPass best = compensate_delay(base, filter, T);
  out.iterations = best.iterations;
  out.delay = best.first_delay;
  if (best.samples.empty()) return out;  // the delay leaves no time for the base law

  out.fits = true;
  out.base_duration = best.base_duration;
  out.delay = best.delay;
  out.filtered_duration =
      std::min(static_cast<double>(best.samples.size() - 1) * Ts, T);  // T within round-off
  // Knots: the sample times, then T when the last sample falls short of it.
  std::vector<double> t, a;
  for (std::size_t k = 0; k < best.samples.size(); ++k) {
    t.push_back(static_cast<double>(k) * Ts);
    a.push_back(best.samples[k]);
  }
  if (t.back() < T - 1e-12 * T) {
    t.push_back(T);
    a.push_back(0.0);
  } else {
    t.back() = T;
  }
  out.correction = correct_rest_to_rest(t, a, stroke, T);
  out.law = piecewise_linear_law("iir", t, a);
  return out;
}

}  // namespace slosh
