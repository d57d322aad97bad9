#pragma once
// The linear modal equations of a rectangular tank re-typed from docs/models.md ("Rectangular
// containers") and integrated by classical RK4 at a fine fixed step: the independent reference
// the rectangular responses and plans are checked against. Nothing here calls slosh::core but
// the law's acceleration.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "slosh/core/law/motion_law.hpp"

namespace slosh::test {

/// One direction's modes: omega_n, wall gain G_n, one zeta, and its share of the acceleration.
struct Modes {
  std::vector<double> w, g;
  double zeta{};
  double component{};  // share of the acceleration along this direction
};

/// The modes along `side` (the other side `across`) at fill h, water's nu = 1e-6 m^2/s;
/// `side_walls` false: the 2-D tank without the side walls' damping.
inline Modes direction(double side, double across, double h, double component, int modes,
                       bool side_walls = true) {
  constexpr double kPi = std::numbers::pi, kG = 9.81, kNu = 1.0e-6;
  Modes m;
  m.component = component;
  for (int n = 1; n <= modes; ++n) {
    const double k = (2 * n - 1) * kPi / side;
    m.w.push_back(std::sqrt(kG * k * std::tanh(k * h)));
    m.g.push_back(4 * std::tanh(k * h) / ((2 * n - 1) * kPi));
  }
  const double k = kPi / side;
  m.zeta = std::sqrt(kNu / (2 * m.w[0])) * (k * (1 - 2 * h / side) / std::sinh(2 * k * h) +
                                            1 / side + (side_walls ? 1 / across : 0.0));
  return m;
}

struct RefPeaks {
  double motion{}, rest{};
};

/// Classical RK4 at step dt of x_n'' + 2 zeta w_n x_n' + w_n^2 x_n = -c a(t) for every mode of
/// every direction; the peaks of sum over directions of |sum_n G_n x_n| on the sample grid.
inline RefPeaks rk4_peaks(const std::vector<Modes>& dirs, const MotionLaw& law, double rest,
                          double dt) {
  struct State {
    double x{}, v{};
  };
  std::vector<std::vector<State>> s(dirs.size());
  for (std::size_t d = 0; d < dirs.size(); ++d) s[d].resize(dirs[d].w.size());
  const double T = law.duration();
  const auto steps = static_cast<long>(std::llround((T + rest) / dt));
  RefPeaks p;
  auto acc = [&](double t) { return t < T ? law.at(t).acceleration : 0.0; };
  for (long i = 0; i < steps; ++i) {
    const double t = static_cast<double>(i) * dt;
    const double a0 = acc(t), am = acc(t + dt / 2), a1 = acc(t + dt);
    double eta = 0.0;
    for (std::size_t d = 0; d < dirs.size(); ++d) {
      double eta_d = 0.0;
      for (std::size_t n = 0; n < dirs[d].w.size(); ++n) {
        const double w = dirs[d].w[n], c = dirs[d].component, z = dirs[d].zeta;
        auto f = [&](double x, double v, double a) { return -2 * z * w * v - w * w * x - c * a; };
        State& q = s[d][n];
        const double k1x = q.v, k1v = f(q.x, q.v, a0);
        const double k2x = q.v + dt / 2 * k1v, k2v = f(q.x + dt / 2 * k1x, k2x, am);
        const double k3x = q.v + dt / 2 * k2v, k3v = f(q.x + dt / 2 * k2x, k3x, am);
        const double k4x = q.v + dt * k3v, k4v = f(q.x + dt * k3x, k4x, a1);
        q.x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
        q.v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
        eta_d += dirs[d].g[n] * q.x;
      }
      eta += std::abs(eta_d);
    }
    const double t1 = static_cast<double>(i + 1) * dt;
    if (t1 <= T + 1e-12) {
      p.motion = std::max(p.motion, eta);
    } else {
      p.rest = std::max(p.rest, eta);
    }
  }
  return p;
}

}  // namespace slosh::test
