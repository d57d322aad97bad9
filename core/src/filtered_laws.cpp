#include "slosh/core/filtered_laws.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

namespace slosh {

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

std::string to_string(ShaperType type) {
  switch (type) {
    case ShaperType::kZV:
      return "zv";
    case ShaperType::kZVD:
      return "zvd";
    case ShaperType::kZVDD:
      return "zvdd";
    case ShaperType::kEI:
      return "ei";
  }
  return "zv";
}

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
    chain.durations = Durations{t3, std::max(0.0, t2 - t3), t3, std::max(0.0, t1 - t2 - t3),
                                t3, std::max(0.0, t2 - t3), t3};
  }
  return chain;
}

}  // namespace slosh
