#include "slosh/core/law/filtered_laws.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

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
  std::vector<double> a;
  switch (type) {
    case ShaperType::kZV:
      a = {1.0, K};
      break;
    case ShaperType::kZVD:
      a = {1.0, 2.0 * K, K * K};
      break;
    case ShaperType::kZVDD:
      a = {1.0, 3.0 * K, 3.0 * K * K, K * K * K};
      break;
    case ShaperType::kEI: {
      const double V = residual;
      const double p = (1.0 + V / K) / ((1.0 + K) * (1.0 + K));
      const double q = 2.0 * p - V / (K * K);
      a = {p, q * K, p * K * K};
      break;
    }
  }
  double sum = 0.0;
  for (double v : a) sum += v;
  InputShaper s;
  s.type = type;
  for (std::size_t j = 0; j < a.size(); ++j) {
    s.impulses.push_back({half * static_cast<double>(j), a[j] / sum});
  }
  return s;
}

double shaper_residual(const InputShaper& shaper, double omega, double zeta) {
  const double t_end = shaper.delay();
  const std::complex<double> rate(-zeta * omega, omega * std::sqrt(1.0 - zeta * zeta));
  std::complex<double> z(0.0);
  for (const Impulse& i : shaper.impulses) z += i.amplitude * std::exp(rate * (t_end - i.time));
  return std::abs(z);
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
