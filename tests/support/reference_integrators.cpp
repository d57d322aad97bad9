#include "support/reference_integrators.hpp"

#include <algorithm>
#include <cmath>

namespace slosh::test {

std::array<double, 8> TrapezoidAcceleration::knots() const {
  std::array<double, 8> k{};
  for (int i = 0; i < 7; ++i) k[i + 1] = k[i] + d[i];
  return k;
}

double TrapezoidAcceleration::operator()(double t) const {
  const auto k = knots();
  if (t <= 0.0 || t >= k[7]) return 0.0;
  if (t < k[1]) return A * (t - k[0]) / d[0];
  if (t < k[2]) return A;
  if (t < k[3]) return A * (k[3] - t) / d[2];
  if (t < k[4]) return 0.0;
  if (t < k[5]) return -B * (t - k[4]) / d[4];
  if (t < k[6]) return -B;
  return -B * (k[7] - t) / d[6];
}

double Rk4Trajectory::x_at(double time) const {
  if (time <= t.front()) return x.front();
  if (time >= t.back()) return x.back();
  const double h = t[1] - t[0];
  const auto i = std::min(static_cast<std::size_t>(time / h), t.size() - 2);
  const double u = (time - t[i]) / (t[i + 1] - t[i]);
  return x[i] + u * (x[i + 1] - x[i]);
}

Rk4Trajectory rk4_solve(const std::function<double(double, double, double)>& f, double t_end,
                        double step) {
  const auto n = static_cast<std::size_t>(std::ceil(t_end / step));
  const double h = t_end / static_cast<double>(n);
  Rk4Trajectory r;
  r.t.reserve(n + 1);
  r.x.reserve(n + 1);
  r.v.reserve(n + 1);
  double x = 0.0, v = 0.0;
  r.t.push_back(0.0);
  r.x.push_back(x);
  r.v.push_back(v);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = h * static_cast<double>(i);
    const double k1x = v, k1v = f(t, x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = f(t + 0.5 * h, x + 0.5 * h * k1x, k2x);
    const double k3x = v + 0.5 * h * k2v, k3v = f(t + 0.5 * h, x + 0.5 * h * k2x, k3x);
    const double k4x = v + h * k3v, k4v = f(t + h, x + h * k3x, k4x);
    x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
    v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    r.t.push_back(h * static_cast<double>(i + 1));
    r.x.push_back(x);
    r.v.push_back(v);
  }
  return r;
}

std::complex<double> gauss_legendre_spectrum(const std::function<double(double)>& a,
                                             const std::vector<double>& knots, double omega,
                                             double rate) {
  static constexpr std::array<double, 8> kNodes{
      -0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
      0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
  static constexpr std::array<double, 8> kWeights{
      0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
      0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  std::complex<double> sum(0.0);
  for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
    const double L = knots[k + 1] - knots[k];
    if (L <= 0.0) continue;
    const int n = static_cast<int>(std::ceil((std::abs(omega) + rate + 1.0 / L) * L));
    const double h = L / n;
    for (int s = 0; s < n; ++s) {
      const double mid = knots[k] + (s + 0.5) * h;
      for (std::size_t q = 0; q < kNodes.size(); ++q) {
        const double t = mid + 0.5 * h * kNodes[q];
        sum += 0.5 * h * kWeights[q] * a(t) * std::polar(1.0, -omega * t);
      }
    }
  }
  return sum;
}

std::complex<double> dft_bin(const std::vector<double>& samples, double dt, double w) {
  std::complex<double> sum{};
  for (std::size_t n = 0; n < samples.size(); ++n) {
    sum += samples[n] * std::polar(1.0, -w * dt * static_cast<double>(n));
  }
  return sum * dt;
}

double parabola_peak(const Rk4Trajectory& r, double K, double a, double b) {
  std::size_t best = 0;
  double best_value = -1.0;
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    if (r.t[i] < a || r.t[i] > b) continue;
    if (std::abs(r.x[i]) > best_value) {
      best_value = std::abs(r.x[i]);
      best = i;
    }
  }
  if (best == 0 || best + 1 >= r.t.size() || r.t[best - 1] < a || r.t[best + 1] > b) {
    return K * best_value;
  }
  const double y0 = std::abs(r.x[best - 1]), y1 = best_value, y2 = std::abs(r.x[best + 1]);
  const double denom = y0 - 2.0 * y1 + y2;
  if (denom >= 0.0) return K * y1;
  return K * (y1 - 0.125 * (y2 - y0) * (y2 - y0) / denom);
}

double eq235_xbar_dd(double omega, double zeta, double C, double alpha, double radius, double x,
                     double v, double a) {
  return -(2.0 * omega * zeta * (v + C * C * x * x * v) + C * C * x * v * v +
           omega * omega * x * (1.0 + alpha * x * x) + a / radius) /
         (1.0 + C * C * x * x);
}

PlanarPendulumPeaks planar_pendulum_peaks(const PendulumParameters& m,
                                          const std::array<double, 7>& d, double length,
                                          const PathGeometry& at, double rest_time, double step) {
  // A and B from the two lobes' balance and the length: B = A area_p / area_n, then A by the
  // length reached with A = 1 (the same integration, the law linear in A).
  const double area_p = 0.5 * d[0] + d[1] + 0.5 * d[2];
  const double area_n = 0.5 * d[4] + d[5] + 0.5 * d[6];
  const TrapezoidAcceleration unit{d, 1.0, area_p / area_n};
  const auto knots = unit.knots();
  const double T = knots[7];
  using State = std::array<double, 6>;  // s, s', qx, qy, qx', qy'
  const double w = m.omega, c2 = m.C * m.C;
  auto run = [&](const TrapezoidAcceleration& a, bool drive, PlanarPendulumPeaks* out) {
    auto f = [&](double t, const State& y) {
      const double acc = t < T ? a(t) : 0.0;
      const double v = t < T ? y[1] : 0.0;
      const auto [psi, kappa] = at(y[0]);
      const double an = kappa * v * v;
      const double ax = drive ? acc * std::cos(psi) - an * std::sin(psi) : 0.0;
      const double ay = drive ? acc * std::sin(psi) + an * std::cos(psi) : 0.0;
      const double qx = y[2], qy = y[3], vx = y[4], vy = y[5];
      const double r2 = qx * qx + qy * qy, v2 = vx * vx + vy * vy, qv = qx * vx + qy * vy;
      // b = -(C^2 |q'|^2 q + 2 zeta w M q' + w^2 (1 + alpha r2) q + a / R); q'' = M^-1 b.
      const double k = w * w * (1.0 + m.alpha * r2);
      const double bx =
          -(c2 * v2 * qx + 2 * m.zeta * w * (vx + c2 * qx * qv) + k * qx + ax / m.radius);
      const double by =
          -(c2 * v2 * qy + 2 * m.zeta * w * (vy + c2 * qy * qv) + k * qy + ay / m.radius);
      const double lam = c2 * (qx * bx + qy * by) / (1.0 + c2 * r2);
      return State{y[1], acc, vx, vy, bx - lam * qx, by - lam * qy};
    };
    auto add = [](const State& base, const State& slope, double s) {
      State r;
      for (std::size_t j = 0; j < 6; ++j) r[j] = base[j] + s * slope[j];
      return r;
    };
    State y{};
    std::vector<double> cuts(knots.begin(), knots.end());
    cuts.push_back(T + rest_time);
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double L = cuts[k + 1] - cuts[k];
      if (!(L > 0.0)) continue;
      const int n = static_cast<int>(std::ceil(L / step));
      const double h = L / n;
      for (int i = 0; i < n; ++i) {
        const double t = cuts[k] + h * i;
        const double e = 1e-12;  // stages just inside the step: each sees its own piece
        const State k1 = f(t + e, y), k2 = f(t + h / 2, add(y, k1, h / 2));
        const State k3 = f(t + h / 2, add(y, k2, h / 2)), k4 = f(t + h - e, add(y, k3, h));
        for (std::size_t j = 0; j < 6; ++j) y[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
        if (out == nullptr) continue;
        const double eta = m.K * std::hypot(y[2], y[3]);
        if (t + h <= T + 1e-12) {
          out->motion = std::max(out->motion, eta);
        } else if (eta > out->rest) {
          out->rest = eta;
          out->t_rest = t + h;
        }
      }
    }
    return y[0];
  };
  const double A = length / run(unit, false, nullptr);
  PlanarPendulumPeaks out;
  run(TrapezoidAcceleration{d, A, A * area_p / area_n}, true, &out);
  return out;
}

}  // namespace slosh::test
