#include "support/reference_optimum.hpp"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace slosh::test {

namespace {

// Forward-mode dual number over the 7 durations.
struct D {
  double v{};
  std::array<double, 7> g{};
  D() = default;
  D(double value) : v(value) {}  // NOLINT: constants promote
  static D var(double value, std::size_t i) {
    D d(value);
    d.g[i] = 1.0;
    return d;
  }
};
D operator+(const D& a, const D& b) {
  D r(a.v + b.v);
  for (std::size_t i = 0; i < 7; ++i) r.g[i] = a.g[i] + b.g[i];
  return r;
}
D operator-(const D& a, const D& b) {
  D r(a.v - b.v);
  for (std::size_t i = 0; i < 7; ++i) r.g[i] = a.g[i] - b.g[i];
  return r;
}
D operator*(const D& a, const D& b) {
  D r(a.v * b.v);
  for (std::size_t i = 0; i < 7; ++i) r.g[i] = a.g[i] * b.v + a.v * b.g[i];
  return r;
}
D operator/(const D& a, const D& b) {
  D r(a.v / b.v);
  for (std::size_t i = 0; i < 7; ++i) r.g[i] = (a.g[i] * b.v - a.v * b.g[i]) / (b.v * b.v);
  return r;
}
D sin(const D& a) {
  D r(std::sin(a.v));
  const double c = std::cos(a.v);
  for (std::size_t i = 0; i < 7; ++i) r.g[i] = c * a.g[i];
  return r;
}
D cos(const D& a) {
  D r(std::cos(a.v));
  const double s = -std::sin(a.v);
  for (std::size_t i = 0; i < 7; ++i) r.g[i] = s * a.g[i];
  return r;
}

double value_of(const D& d) {
  return d.v;
}
double value_of(double d) {
  return d;
}

template <typename S>
struct Levels {
  S A, B;
};

// Moment of a unit trapezoid (up ramp r1, plateau p, down ramp r3) starting at 0.
template <typename S>
S unit_moment(const S& r1, const S& p, const S& r3) {
  return r1 * r1 / S(3.0) + p * (r1 + p / S(2.0)) + (r1 + p) * r3 / S(2.0) + r3 * r3 / S(6.0);
}

// A d3 = B d4 (zero final velocity); s = -int a t dt = B M_neg - A M_pos.
template <typename S>
Levels<S> levels(const std::array<S, 7>& d, const S& stroke) {
  const S d3 = d[0] / S(2.0) + d[1] + d[2] / S(2.0);
  const S d4 = d[4] / S(2.0) + d[5] + d[6] / S(2.0);
  const S m_pos = unit_moment(d[0], d[1], d[2]);
  const S t4 = d[0] + d[1] + d[2] + d[3];
  const S m_neg = t4 * d4 + unit_moment(d[4], d[5], d[6]);
  const S A = stroke / (d3 / d4 * m_neg - m_pos);
  return {A, A * d3 / d4};
}

// Re and Im of X(omega) = int a e^{-j w t} dt; per segment a = q + m (t - ta):
// int f cos = [f sin/w + m cos/w^2], int f sin = [-f cos/w + m sin/w^2].
template <typename S>
std::array<S, 2> spectrum(const std::array<S, 7>& d, const S& stroke, double w) {
  using std::cos;
  using std::sin;
  const Levels<S> lv = levels(d, stroke);
  const S zero(0.0);
  const std::array<S, 7> start_level{zero, lv.A, lv.A, zero, zero, zero - lv.B, zero - lv.B};
  const std::array<S, 7> end_level{lv.A, lv.A, zero, zero, zero - lv.B, zero - lv.B, zero};
  S t(0.0), re(0.0), im(0.0);
  const S W(w), W2(w * w);
  for (std::size_t k = 0; k < 7; ++k) {
    const S tb = t + d[k];
    if (value_of(d[k]) > 0.0) {
      const S m = (end_level[k] - start_level[k]) / d[k];
      const S fa = start_level[k], fb = end_level[k];
      const S sa = sin(W * t), ca = cos(W * t), sb = sin(W * tb), cb = cos(W * tb);
      re = re + (fb * sb / W + m * cb / W2) - (fa * sa / W + m * ca / W2);
      im = im - ((zero - fb * cb / W + m * sb / W2) - (zero - fa * ca / W + m * sa / W2));
    }
    t = tb;
  }
  return {re, im};
}

std::array<D, 7> duals(const double* x) {
  std::array<D, 7> d;
  for (std::size_t i = 0; i < 7; ++i) d[i] = D::var(x[i], i);
  return d;
}

SevenDurations uniform(double T) {
  SevenDurations d;
  d.fill(T / 7.0);
  return d;
}

// Seeded starts: the uniform law and Dirichlet(1) points over the room above the bounds.
std::vector<SevenDurations> make_starts(const SpectralProblem& p, int count, std::uint64_t seed) {
  std::vector<SevenDurations> out{uniform(p.T)};
  const SevenDurations lower{p.min_ramp, 0, p.min_ramp, 0, p.min_ramp, 0, p.min_ramp};
  double room = p.T;
  for (double l : lower) room -= l;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(1e-12, 1.0);
  while (static_cast<int>(out.size()) < count) {
    SevenDurations w;
    double total = 0.0;
    for (double& wi : w) {
      wi = -std::log(u(rng));
      total += wi;
    }
    SevenDurations d;
    for (std::size_t i = 0; i < 7; ++i) d[i] = lower[i] + room * w[i] / total;
    out.push_back(d);
  }
  return out;
}

struct Data {
  const SpectralProblem* p;
  std::vector<double> omegas;
  std::vector<double> weights;
  double scale{};  // 1 / (tol X_ref)^2 or 1 / X_ref^2
  double jerk_ref{};
  bool epigraph{false};
};

double jerk_objective(unsigned n, const double* x, double* grad, void* data) {
  const auto* c = static_cast<Data*>(data);
  const auto d = duals(x);
  const Levels<D> lv = levels(d, D(c->p->stroke));
  const D j = lv.A * lv.A / d[0] + lv.A * lv.A / d[2] + lv.B * lv.B / d[4] + lv.B * lv.B / d[6];
  if (grad != nullptr) {
    for (unsigned i = 0; i < n; ++i) grad[i] = i < 7 ? j.g[i] / c->jerk_ref : 0.0;
  }
  return j.v / c->jerk_ref;
}

double power_objective(unsigned n, const double* x, double* grad, void* data) {
  const auto* c = static_cast<Data*>(data);
  const auto d = duals(x);
  D total(0.0);
  for (std::size_t k = 0; k < c->omegas.size(); ++k) {
    const auto X = spectrum(d, D(c->p->stroke), c->omegas[k]);
    total = total + D(c->weights[k] * c->scale) * (X[0] * X[0] + X[1] * X[1]);
  }
  if (grad != nullptr) {
    for (unsigned i = 0; i < n; ++i) grad[i] = total.g[i];
  }
  return total.v;
}

double epigraph_objective(unsigned n, const double* x, double* grad, void*) {
  if (grad != nullptr) {
    for (unsigned i = 0; i < n; ++i) grad[i] = i == 7 ? 1.0 : 0.0;
  }
  return x[7];
}

// |X(w_k)|^2 scale - (1 or z) <= 0.
void band_constraints(unsigned m, double* result, unsigned n, const double* x, double* grad,
                      void* data) {
  const auto* c = static_cast<Data*>(data);
  const auto d = duals(x);
  for (unsigned k = 0; k < m; ++k) {
    const auto X = spectrum(d, D(c->p->stroke), c->omegas[k]);
    const D power = (X[0] * X[0] + X[1] * X[1]) * D(c->scale);
    result[k] = power.v - (c->epigraph ? x[7] : 1.0);
    if (grad != nullptr) {
      for (unsigned i = 0; i < n; ++i) {
        grad[k * n + i] = i < 7 ? power.g[i] : -1.0;
      }
    }
  }
}

double sum_constraint(unsigned n, const double* x, double* grad, void* data) {
  const double T = *static_cast<double*>(data);
  double s = -T;
  for (unsigned i = 0; i < 7; ++i) {
    s += x[i];
    if (grad != nullptr) grad[i] = 1.0;
  }
  for (unsigned i = 7; i < n && grad != nullptr; ++i) grad[i] = 0.0;
  return s;
}

enum class Kind { kJerk, kExcess, kNotch };

ReferenceOptimum run(const SpectralProblem& p, Kind kind, int count, int grid_points,
                     std::uint64_t seed) {
  Data data{&p, {}, {}, 0.0, 0.0, kind == Kind::kExcess};
  const double x_ref = reference_x_ref(p);
  const double w1 = p.omega1;
  if (kind == Kind::kNotch) {
    data.omegas = {(1.0 - p.p_notch) * w1, w1, (1.0 + p.p_notch) * w1};
    data.weights = {1.0, 1.0, 1.0};
    data.scale = 1.0 / (x_ref * x_ref);
  } else {
    for (int k = 0; k < grid_points; ++k) {
      data.omegas.push_back((1.0 - p.band) * w1 + 2.0 * p.band * w1 * k / (grid_points - 1));
    }
    data.scale = 1.0 / (x_ref * x_ref * p.tol_rel * p.tol_rel);
  }
  data.jerk_ref = reference_jerk_integral(uniform(p.T), p.stroke);
  const unsigned n = kind == Kind::kExcess ? 8 : 7;
  double T = p.T;
  ReferenceOptimum best;
  for (const SevenDurations& start : make_starts(p, count, seed)) {
    nlopt_opt opt = nlopt_create(NLOPT_LD_SLSQP, n);
    std::vector<double> lo{p.min_ramp, 0, p.min_ramp, 0, p.min_ramp, 0, p.min_ramp};
    std::vector<double> hi(7, p.T);
    std::vector<double> x(start.begin(), start.end());
    if (kind == Kind::kExcess) {
      lo.push_back(0.0);
      hi.push_back(1e20);
      double z = 0.0;
      for (double w : data.omegas)
        z = std::max(z, std::norm(reference_spectrum(start, p.stroke, w)));
      x.push_back(z * data.scale * 1.01);
    }
    nlopt_set_lower_bounds(opt, lo.data());
    nlopt_set_upper_bounds(opt, hi.data());
    nlopt_set_min_objective(opt,
                            kind == Kind::kJerk    ? jerk_objective
                            : kind == Kind::kNotch ? power_objective
                                                   : epigraph_objective,
                            &data);
    nlopt_add_equality_constraint(opt, sum_constraint, &T, 1e-12);
    std::vector<double> tols(data.omegas.size(), 1e-9);
    if (kind != Kind::kNotch) {
      nlopt_add_inequality_mconstraint(opt, static_cast<unsigned>(data.omegas.size()),
                                       band_constraints, &data, tols.data());
    }
    nlopt_set_ftol_rel(opt, 1e-12);
    nlopt_set_xtol_rel(opt, 1e-12);
    nlopt_set_maxeval(opt, 2000);
    double f = 0.0;
    nlopt_optimize(opt, x.data(), &f);
    nlopt_destroy(opt);
    ++best.starts;
    // Judge the point itself: bounds, sum and (jerk) the band on the solver's grid.
    SevenDurations d;
    bool ok = true;
    double sum = 0.0;
    for (std::size_t i = 0; i < 7; ++i) {
      d[i] = x[i];
      ok = ok && x[i] >= lo[i] - 1e-12;
      sum += x[i];
    }
    ok = ok && std::abs(sum - p.T) < 1e-9;
    double value = 0.0;
    if (kind == Kind::kJerk) {
      double worst = 0.0;
      for (double w : data.omegas) {
        worst = std::max(worst, std::norm(reference_spectrum(d, p.stroke, w)) * data.scale);
      }
      ok = ok && worst <= 1.0 + 1e-8;
      value = reference_jerk_integral(d, p.stroke) / data.jerk_ref;
    } else if (kind == Kind::kNotch) {
      value = 0.0;
      for (std::size_t k = 0; k < data.omegas.size(); ++k) {
        value += data.weights[k] * std::norm(reference_spectrum(d, p.stroke, data.omegas[k])) *
                 data.scale;
      }
    } else {
      value = reference_band_max(d, p.stroke, (1.0 - p.band) * w1, (1.0 + p.band) * w1) / x_ref;
    }
    if (!ok || !std::isfinite(value)) continue;
    ++best.feasible_starts;
    if (!best.feasible || value < best.objective) {
      best.feasible = true;
      best.objective = value;
      best.durations = d;
    }
  }
  return best;
}

}  // namespace

Plateaus reference_plateaus(const SevenDurations& d, double stroke) {
  const Levels<double> lv = levels(d, stroke);
  return {lv.A, lv.B};
}

std::complex<double> reference_spectrum(const SevenDurations& d, double stroke, double omega) {
  const auto X = spectrum(d, stroke, omega);
  return {X[0], X[1]};
}

double reference_jerk_integral(const SevenDurations& d, double stroke) {
  const Levels<double> lv = levels(d, stroke);
  return lv.A * lv.A / d[0] + lv.A * lv.A / d[2] + lv.B * lv.B / d[4] + lv.B * lv.B / d[6];
}

double reference_band_max(const SevenDurations& d, double stroke, double lo, double hi) {
  constexpr int kIntervals = 4000;
  auto f = [&](double w) { return std::abs(reference_spectrum(d, stroke, w)); };
  std::vector<double> v(kIntervals + 1);
  const double h = (hi - lo) / kIntervals;
  for (int k = 0; k <= kIntervals; ++k) v[static_cast<std::size_t>(k)] = f(lo + h * k);
  double best = *std::max_element(v.begin(), v.end());
  for (int k = 1; k < kIntervals; ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (!(v[i] >= v[i - 1] && v[i] >= v[i + 1])) continue;
    double a = lo + h * (k - 1), b = lo + h * (k + 1);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 80; ++it) {
      const double x1 = b - g * (b - a), x2 = a + g * (b - a);
      if (f(x1) > f(x2)) {
        b = x2;
      } else {
        a = x1;
      }
    }
    best = std::max(best, f(0.5 * (a + b)));
  }
  return best;
}

double reference_x_ref(const SpectralProblem& p) {
  return reference_band_max(uniform(p.T), p.stroke, (1.0 - p.band) * p.omega1,
                            (1.0 + p.band) * p.omega1);
}

ReferenceOptimum reference_min_jerk_band(const SpectralProblem& p, int starts, int grid_points,
                                         std::uint64_t seed) {
  return run(p, Kind::kJerk, starts, grid_points, seed);
}

ReferenceOptimum reference_min_band_excess(const SpectralProblem& p, int starts, int grid_points,
                                           std::uint64_t seed) {
  return run(p, Kind::kExcess, starts, grid_points, seed);
}

ReferenceOptimum reference_multi_notch(const SpectralProblem& p, int starts, std::uint64_t seed) {
  return run(p, Kind::kNotch, starts, 0, seed);
}

}  // namespace slosh::test
