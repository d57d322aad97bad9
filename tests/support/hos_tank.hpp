#pragma once
// An independent reference for the rectangular tank's nonlinear model: fully nonlinear,
// inviscid, irrotational flow in a 2-D tank [0, L] x [-h, eta] (walls at x = 0 and x = L) moved
// horizontally with acceleration a(t), by the high-order spectral method of West, Brueckner,
// Janda, Milder & Milton (J. Geophys. Res. 92, 1987) and Dommermuth & Yue (J. Fluid Mech. 184,
// 1987): the surface elevation eta and the surface potential psi on N cosine modes cos(j pi x /
// L) (which satisfy the no-flux walls), the vertical velocity W at the surface from the
// expansion of the potential about z = 0 to order M, and Zakharov's surface equations
//   eta_t = -eta_x psi_x + (1 + eta_x^2) W,
//   psi_t = -g eta - psi_x^2 / 2 + (1 + eta_x^2) W^2 / 2 - a(t) (x - L/2),
// the last term the potential of the inertial body force in the tank frame. Classical RK4 in
// time. Nothing here is shared with the product's model: it solves the Euler equations, not a
// modal system.

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace slosh::testing {

class HosTank {
 public:
  /// Cosine coefficients of eta and psi [m, m^2/s], index j = 0..N-1.
  struct State {
    std::vector<double> eta, psi;
  };

  HosTank(double length, double depth, int modes, int order, double g = 9.81)
      : L_(length), h_(depth), n_(modes), m_(order), g_(g) {
    kappa_.resize(n_);
    x_.resize(n_);
    cos_.assign(n_ * n_, 0.0);
    dsin_.assign(n_ * n_, 0.0);
    for (int j = 0; j < n_; ++j) kappa_[j] = j * std::numbers::pi / L_;
    for (int i = 0; i < n_; ++i) {
      x_[i] = (i + 0.5) * L_ / n_;
      for (int j = 0; j < n_; ++j) {
        cos_[i * n_ + j] = std::cos(kappa_[j] * x_[i]);
        dsin_[i * n_ + j] = -kappa_[j] * std::sin(kappa_[j] * x_[i]);
      }
    }
  }

  [[nodiscard]] int modes() const { return n_; }

  /// Linear natural frequency of mode j [rad/s].
  [[nodiscard]] double omega(int j) const {
    return std::sqrt(g_ * kappa_[j] * std::tanh(kappa_[j] * h_));
  }

  /// Time derivative of the state under the tank acceleration a [m/s^2].
  [[nodiscard]] State rhs(const State& s, double a) const {
    const std::vector<double> eta = grid(s.eta), eta_x = grid_dx(s.eta), psi_x = grid_dx(s.psi);
    // phi^(m) at z = 0 as cosine coefficients: phi^(1) = psi, phi^(m) = -sum_j eta^j / j!
    // d^j phi^(m-j) / dz^j.
    std::vector<std::vector<double>> phi(m_ + 1);
    phi[1] = s.psi;
    for (int m = 2; m <= m_; ++m) {
      std::vector<double> sum(n_, 0.0);
      for (int j = 1; j < m; ++j) add_term(sum, eta, j, grid(dz(phi[m - j], j)), -1.0);
      phi[m] = coefficients(sum);
    }
    // W = sum_m sum_{j <= M - m} eta^j / j! d^{j+1} phi^(m) / dz^{j+1}.
    std::vector<double> w(n_, 0.0);
    for (int m = 1; m <= m_; ++m) {
      for (int j = 0; j <= m_ - m; ++j) add_term(w, eta, j, grid(dz(phi[m], j + 1)), 1.0);
    }
    std::vector<double> eta_t(n_), psi_t(n_);
    for (int i = 0; i < n_; ++i) {
      const double slope2 = 1.0 + eta_x[i] * eta_x[i];
      eta_t[i] = -eta_x[i] * psi_x[i] + slope2 * w[i];
      psi_t[i] = -g_ * eta[i] - 0.5 * psi_x[i] * psi_x[i] + 0.5 * slope2 * w[i] * w[i] -
                 a * (x_[i] - 0.5 * L_);
    }
    return {coefficients(eta_t), coefficients(psi_t)};
  }

  /// One RK4 step of dt from t with the acceleration a(t).
  void step(State& s, double t, double dt, const std::function<double(double)>& a) const {
    auto axpy = [](const State& y, const State& k, double c) {
      State r = y;
      for (std::size_t j = 0; j < y.eta.size(); ++j) {
        r.eta[j] += c * k.eta[j];
        r.psi[j] += c * k.psi[j];
      }
      return r;
    };
    const State k1 = rhs(s, a(t));
    const State k2 = rhs(axpy(s, k1, dt / 2), a(t + dt / 2));
    const State k3 = rhs(axpy(s, k2, dt / 2), a(t + dt / 2));
    const State k4 = rhs(axpy(s, k3, dt), a(t + dt));
    for (std::size_t j = 0; j < s.eta.size(); ++j) {
      s.eta[j] += dt / 6 * (k1.eta[j] + 2 * k2.eta[j] + 2 * k3.eta[j] + k4.eta[j]);
      s.psi[j] += dt / 6 * (k1.psi[j] + 2 * k2.psi[j] + 2 * k3.psi[j] + k4.psi[j]);
    }
  }

  /// Elevation at the wall x = 0 (sum of the coefficients) and x = L (alternating sum) [m].
  [[nodiscard]] static double wall_left(const State& s) {
    double v = 0.0;
    for (double c : s.eta) v += c;
    return v;
  }
  [[nodiscard]] static double wall_right(const State& s) {
    double v = 0.0;
    for (std::size_t j = 0; j < s.eta.size(); ++j) v += (j % 2 == 0 ? 1.0 : -1.0) * s.eta[j];
    return v;
  }

 private:
  std::vector<double> grid(const std::vector<double>& c) const {
    std::vector<double> v(n_, 0.0);
    for (int i = 0; i < n_; ++i) {
      for (int j = 0; j < n_; ++j) v[i] += cos_[i * n_ + j] * c[j];
    }
    return v;
  }
  std::vector<double> grid_dx(const std::vector<double>& c) const {
    std::vector<double> v(n_, 0.0);
    for (int i = 0; i < n_; ++i) {
      for (int j = 0; j < n_; ++j) v[i] += dsin_[i * n_ + j] * c[j];
    }
    return v;
  }
  /// Cosine coefficients of grid values (the DCT-II pair of the midpoint grid, exact for N modes).
  std::vector<double> coefficients(const std::vector<double>& v) const {
    std::vector<double> c(n_, 0.0);
    for (int j = 0; j < n_; ++j) {
      for (int i = 0; i < n_; ++i) c[j] += cos_[i * n_ + j] * v[i];
      c[j] *= (j == 0 ? 1.0 : 2.0) / n_;
    }
    return c;
  }
  /// d^p / dz^p at z = 0 of the potential whose surface coefficients are c (depth h).
  std::vector<double> dz(const std::vector<double>& c, int p) const {
    std::vector<double> r(n_);
    for (int j = 0; j < n_; ++j) {
      const double k = kappa_[j];
      r[j] = c[j] * std::pow(k, p) * (p % 2 == 1 ? std::tanh(k * h_) : 1.0);
    }
    return r;
  }
  /// sum += sign eta^j / j! f (grid values).
  static void add_term(std::vector<double>& sum, const std::vector<double>& eta, int j,
                       const std::vector<double>& f, double sign) {
    double fact = 1.0;
    for (int q = 2; q <= j; ++q) fact *= q;
    for (std::size_t i = 0; i < sum.size(); ++i) {
      sum[i] += sign * std::pow(eta[i], j) / fact * f[i];
    }
  }

  double L_, h_;
  int n_, m_;
  double g_;
  std::vector<double> kappa_, x_, cos_, dsin_;
};

}  // namespace slosh::testing
