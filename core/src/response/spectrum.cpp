#include "slosh/core/response/spectrum.hpp"

#include <algorithm>
#include <cmath>

#include "response/sincos.hpp"
#include "solve/dual.hpp"

namespace slosh {

namespace {

template <typename T>
using Complex = std::complex<T>;

// phi1(z) = (1 - e^{-z})/z and phi2(z) = (1 - (1+z) e^{-z})/z^2, z = j w L.
template <typename T>
void phi12(T wl, Complex<T>* phi1, Complex<T>* phi2) {
  const Complex<T> z(T(0), wl);
  if (std::abs(wl) < T(0.5)) {
    // phi1 = sum (-z)^n/(n+1)!, phi2 = sum (-z)^n (n+1)/(n+2)!.
    Complex<T> term(1);  // (-z)^n / n!
    Complex<T> s1(0), s2(0);
    for (int n = 0; n < 30; ++n) {
      s1 += term / T(n + 1);
      s2 += term * T(n + 1) / (T(n + 1) * T(n + 2));
      term *= -z / T(n + 1);
    }
    *phi1 = s1;
    *phi2 = s2;
    return;
  }
  const Complex<T> e = std::exp(-z);
  *phi1 = (T(1) - e) / z;
  *phi2 = (T(1) - (T(1) + z) * e) / (z * z);
}

template <typename T>
Complex<T> expj(T phase) {
  return {std::cos(phase), -std::sin(phase)};  // exp(-j phase)
}

template <>
Complex<double> expj(double phase) {
  const detail::SinCos sc = detail::fast_sincos(phase);
  return {sc.cos, -sc.sin};
}

}  // namespace

template <typename T>
std::complex<T> seven_segment_spectrum(const std::array<T, kSegments>& d, T stroke, T omega) {
  if (omega == T(0)) return {};
  const auto lv = plateau_levels(d, stroke);
  std::array<T, kSegments + 1> t{};
  for (std::size_t i = 0; i < kSegments; ++i) t[i + 1] = t[i] + d[i];
  const std::array<T, kSegments> J{lv.A / d[0],  T(0), -lv.A / d[2], T(0),
                                   -lv.B / d[4], T(0), lv.B / d[6]};
  // The jerk-jump form divides by omega^2: its round-off grows as (omega T)^-2 times the jerk,
  // so below omega T = 8 the per-segment form is used (both agree to ~1e-15 there).
  if (std::abs(omega) * t[kSegments] >= T(8)) {
    Complex<T> sum = J[0] * (Complex<T>(1) - expj(omega * t[1]));  // t_0 = 0
    for (std::size_t k = 2; k < kSegments; k += 2) {
      sum += J[k] * (expj(omega * t[k]) - expj(omega * t[k + 1]));
    }
    return -sum / (omega * omega);
  }
  const std::array<T, kSegments> a0{T(0), lv.A, lv.A, T(0), T(0), -lv.B, -lv.B};
  Complex<T> sum(0);
  for (std::size_t k = 0; k < kSegments; ++k) {
    if (d[k] == T(0)) continue;
    Complex<T> p1, p2;
    phi12(omega * d[k], &p1, &p2);
    sum += expj(omega * t[k]) * (a0[k] * d[k] * p1 + J[k] * d[k] * d[k] * p2);
  }
  return sum;
}

template std::complex<double> seven_segment_spectrum(const std::array<double, kSegments>&, double,
                                                     double);
template std::complex<long double> seven_segment_spectrum(const std::array<long double, kSegments>&,
                                                          long double, long double);

void seven_segment_magnitudes(const Durations& d, double stroke, double omega0, double step,
                              std::size_t count, std::vector<double>* out) {
  constexpr std::size_t kRefresh{32};
  constexpr double kRotationMinOmegaT{0.5};
  out->resize(count);
  if (count == 0) return;
  double total = 0.0;
  for (double di : d) total += di;
  const double first = std::min(omega0, omega0 + step * static_cast<double>(count - 1));
  // The rotation's error is bounded by the jerk-jump terms' scale sum |w_i| / omega^2 (about
  // 1e-14 of it), which grows against |X| ~ stroke omega as (omega T)^-3 at low frequency: at
  // omega T = 0.5 still below 1e-10 of |X|, far under what a band check resolves.
  if (!(first > 0.0 && first * total >= kRotationMinOmegaT)) {
    for (std::size_t k = 0; k < count; ++k) {
      (*out)[k] =
          std::abs(seven_segment_spectrum(d, stroke, omega0 + step * static_cast<double>(k)));
    }
    return;
  }
  // The jerk-jump form of seven_segment_spectrum: X = -(1/omega^2) sum_i w_i E_i, E_i =
  // exp(-j omega t_i), over the 7 switch times after t_0 = 0 (w_0 = J_0 at E_0 = 1).
  const auto lv = plateau_levels(d, stroke);
  const std::array<double, kSegments> J{lv.A / d[0],  0.0, -lv.A / d[2], 0.0,
                                        -lv.B / d[4], 0.0, lv.B / d[6]};
  std::array<double, kSegments + 1> t{};
  for (std::size_t i = 0; i < kSegments; ++i) t[i + 1] = t[i] + d[i];
  // w_i: J_0 at t_0, -J_0 at t_1, J_k at t_k and -J_k at t_{k+1} for k = 2, 4, 6.
  std::array<double, kSegments + 1> w{J[0], -J[0], J[2], -J[2], J[4], -J[4], J[6], -J[6]};
  // E_i = exp(-j omega t_i) and its rotation R_i per grid step, as real and imaginary parts
  // (std::complex's product checks for NaN on every multiply, which also keeps the loop from
  // vectorising); E_0 = 1 is folded into the sum.
  constexpr std::size_t kTerms{kSegments};
  std::array<double, kTerms> er{}, ei{}, rr{}, ri{}, wt{};
  for (std::size_t i = 0; i < kTerms; ++i) {
    const std::complex<double> r = expj(step * t[i + 1]);
    rr[i] = r.real();
    ri[i] = r.imag();
    wt[i] = w[i + 1];
  }
  for (std::size_t k = 0; k < count; ++k) {
    const double omega = omega0 + step * static_cast<double>(k);
    if (k % kRefresh == 0) {
      for (std::size_t i = 0; i < kTerms; ++i) {
        const std::complex<double> e = expj(omega * t[i + 1]);
        er[i] = e.real();
        ei[i] = e.imag();
      }
    } else {
      for (std::size_t i = 0; i < kTerms; ++i) {
        const double re = er[i] * rr[i] - ei[i] * ri[i];
        const double im = er[i] * ri[i] + ei[i] * rr[i];
        er[i] = re;
        ei[i] = im;
      }
    }
    double sum_re = w[0];
    double sum_im = 0.0;
    for (std::size_t i = 0; i < kTerms; ++i) {
      sum_re += wt[i] * er[i];
      sum_im += wt[i] * ei[i];
    }
    (*out)[k] = std::sqrt(sum_re * sum_re + sum_im * sum_im) / (omega * omega);
  }
}

std::complex<double> acceleration_spectrum(const SevenSegmentLaw& law, double omega) {
  return seven_segment_spectrum(law.durations(), law.stroke(), omega);
}

namespace {

// The jerks of the four ramps with their derivatives, and the switch times, of one set of
// durations: what every frequency of a gradient evaluation shares.
struct JerkForm {
  std::array<Dual7, 4> J;
  std::array<double, kSegments + 1> t{};
};

JerkForm jerk_form(const Durations& d, double stroke) {
  std::array<Dual7, kSegments> dd;
  for (std::size_t i = 0; i < kSegments; ++i) dd[i] = Dual7::variable(d[i], i);
  const auto lv = plateau_levels(dd, Dual7(stroke));
  JerkForm f{{lv.A / dd[0], -lv.A / dd[2], -lv.B / dd[4], lv.B / dd[6]}, {}};
  for (std::size_t i = 0; i < kSegments; ++i) f.t[i + 1] = f.t[i] + d[i];
  return f;
}

SpectrumGradient gradient_at(const JerkForm& f, double omega) {
  SpectrumGradient out{};
  if (omega == 0.0) return out;
  // X = -(1/omega^2) sum_k w_k E_k with E_k = exp(-j omega t_k), w_{2r} = J_r, w_{2r+1} = -J_r.
  std::array<std::complex<double>, kSegments + 1> E;
  E[0] = 1.0;
  for (std::size_t i = 1; i <= kSegments; ++i) E[i] = expj(omega * f.t[i]);
  std::array<std::complex<double>, 4> diff;
  std::complex<double> X(0.0);
  for (std::size_t r = 0; r < 4; ++r) {
    diff[r] = E[2 * r] - E[2 * r + 1];
    X += f.J[r].v * diff[r];
  }
  // dX/d dT_i = sum_r dJ_r/d dT_i diff_r + sum_{k > i} w_k dE_k/d dT_i, dE_k/d dT_i = -j omega E_k
  // for t_k that includes dT_i (k > i): the second sum is a suffix sum over k.
  const double scale = -1.0 / (omega * omega);
  std::complex<double> suffix(0.0);
  for (std::size_t i = kSegments; i-- > 0;) {
    const std::size_t k = i + 1;
    const double w = (k % 2 == 0 ? 1.0 : -1.0) * f.J[k / 2].v;
    suffix += w * std::complex<double>(omega * E[k].imag(), -omega * E[k].real());
    std::complex<double> g = suffix;
    for (std::size_t r = 0; r < 4; ++r) g += f.J[r].d[i] * diff[r];
    out.dX[i] = g * scale;
  }
  out.X = X * scale;
  return out;
}

SpectrumPowerGradient power_of(const SpectrumGradient& sg) {
  SpectrumPowerGradient out{};
  out.X = sg.X;
  out.power = std::norm(sg.X);
  for (std::size_t i = 0; i < kSegments; ++i) {
    out.gradient[i] = 2.0 * (sg.X.real() * sg.dX[i].real() + sg.X.imag() * sg.dX[i].imag());
  }
  return out;
}

}  // namespace

SpectrumGradient spectrum_gradient(const Durations& d, double stroke, double omega) {
  if (omega == 0.0) return {};
  return gradient_at(jerk_form(d, stroke), omega);
}

void spectrum_power_gradients(const Durations& d, double stroke, const std::vector<double>& omegas,
                              std::vector<SpectrumPowerGradient>* out) {
  const JerkForm f = jerk_form(d, stroke);
  out->resize(omegas.size());
  for (std::size_t k = 0; k < omegas.size(); ++k) (*out)[k] = power_of(gradient_at(f, omegas[k]));
}

SpectrumPowerGradient spectrum_power_gradient(const Durations& d, double stroke, double omega) {
  return power_of(spectrum_gradient(d, stroke, omega));
}

namespace {

// psi_n(j theta) = int_0^1 u^n exp(-j theta u) du for n = 0..3.
std::array<std::complex<double>, 4> psi(double theta) {
  std::array<std::complex<double>, 4> out{};
  const std::complex<double> z(0.0, theta);
  if (std::abs(theta) < 2.0) {
    // sum_m (-z)^m / (m! (n + m + 1)): upward recursion would lose digits here.
    std::complex<double> term(1.0);
    for (int m = 0; m < 40; ++m) {
      for (int n = 0; n < 4; ++n) out[static_cast<std::size_t>(n)] += term / double(n + m + 1);
      term *= -z / double(m + 1);
      if (std::abs(term) < 1e-18) break;
    }
    return out;
  }
  const std::complex<double> e = expj(theta);  // exp(-z)
  out[0] = (1.0 - e) / z;
  for (std::size_t n = 1; n < 4; ++n) out[n] = (double(n) * out[n - 1] - e) / z;
  return out;
}

}  // namespace

std::complex<double> acceleration_spectrum(const MotionLaw& law, double omega) {
  // Sampled laws (IIR) have ~1000 pieces of one length: psi and the phase step are shared, and
  // exp(-j w t_begin) advances by one product per piece (recomputed every 64 against drift).
  constexpr int kPhaseRefresh = 64;
  std::complex<double> sum(0.0);
  double last_length = -1.0;
  std::array<std::complex<double>, 4> q{};
  std::complex<double> step(1.0), phase(1.0);
  double next_begin = -1.0;
  int since_refresh = kPhaseRefresh;
  for (const LawPiece& p : law.pieces()) {
    const double L = p.duration();
    if (L <= 0.0) continue;
    // Sample grids k T_s give lengths equal up to a few ulps: reusing psi and the phase step
    // then errs by ~omega dL / (omega L) ~ 1e-12 relative at most, far below what is reported.
    if (std::abs(L - last_length) > 1e-12 * L) {
      q = psi(omega * L);
      step = expj(omega * L);
      last_length = L;
    }
    if (p.t_begin != next_begin || since_refresh >= kPhaseRefresh) {
      phase = expj(omega * p.t_begin);
      since_refresh = 0;
    }
    std::complex<double> piece(0.0);
    double Ln = L;
    for (std::size_t n = 0; n < 4; ++n, Ln *= L) piece += p.poly[n] * Ln * q[n];
    if (p.harmonic_omega != 0.0 && (p.harmonic_cos != 0.0 || p.harmonic_sin != 0.0)) {
      // hc cos + hs sin = (hc - j hs)/2 exp(j W tau) + (hc + j hs)/2 exp(-j W tau).
      const double W = p.harmonic_omega;
      const std::complex<double> plus(0.5 * p.harmonic_cos, -0.5 * p.harmonic_sin);
      const std::complex<double> minus(0.5 * p.harmonic_cos, 0.5 * p.harmonic_sin);
      piece += L * (plus * psi((omega - W) * L)[0] + minus * psi((omega + W) * L)[0]);
    }
    sum += phase * piece;
    phase *= step;
    next_begin = p.t_end;
    ++since_refresh;
  }
  return sum;
}

}  // namespace slosh
