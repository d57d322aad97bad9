#pragma once
// Independent reference computations for the tests. Nothing here calls into slosh::core: every
// quantity is rebuilt from the SPEC text so the core can be checked against it.

#include <array>
#include <complex>
#include <functional>
#include <utility>
#include <vector>

namespace slosh::test {

/// Acceleration of the 7-segment law from its durations and plateau levels, rebuilt from the
/// SPEC §3 description (0 -> +A, +A, +A -> 0, 0, 0 -> -B, -B, -B -> 0).
struct TrapezoidAcceleration {
  std::array<double, 7> d{};
  double A{};
  double B{};

  [[nodiscard]] double operator()(double t) const;
  /// 0, t_1, ..., t_7.
  [[nodiscard]] std::array<double, 8> knots() const;
};

/// Composite Simpson rule on [a, b] with n (even) intervals; exact for cubics.
template <typename F>
auto simpson(const F& f, double a, double b, int n) -> decltype(f(a)) {
  const double h = (b - a) / n;
  auto sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * f(a + h * i);
  return sum * (h / 3.0);
}

/// Integral of f over consecutive knot intervals, Simpson with n intervals on each.
template <typename F, typename Knots>
auto simpson_piecewise(const F& f, const Knots& knots, int n) -> decltype(f(0.0)) {
  decltype(f(0.0)) total{};
  for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
    if (knots[k + 1] > knots[k]) total += simpson(f, knots[k], knots[k + 1], n);
  }
  return total;
}

/// int a(t) e^{-j omega t} dt over consecutive knot intervals by composite 8-point
/// Gauss-Legendre, with enough sub-intervals that each spans less than one radian of the
/// integrand's oscillation (`rate` [rad/s]: the fastest oscillation of a itself, 0 for a
/// piecewise polynomial); nodes are interior, so a may jump at the knots.
[[nodiscard]] std::complex<double> gauss_legendre_spectrum(const std::function<double(double)>& a,
                                                           const std::vector<double>& knots,
                                                           double omega, double rate = 0.0);

/// Fixed-step classical RK4 of x'' = f(t, x, x') from x = x' = 0 over [0, t_end].
struct Rk4Trajectory {
  std::vector<double> t, x, v;
  /// Linear interpolation between grid points (use with a fine step only).
  [[nodiscard]] double x_at(double time) const;
};
[[nodiscard]] Rk4Trajectory rk4_solve(const std::function<double(double, double, double)>& f,
                                      double t_end, double step);

/// Largest |K x| of the trajectory over [a, b], refined by the parabola through the best sample
/// and its neighbours (the sample spacing alone would cost ~(w dt)^2 / 8 of the peak).
[[nodiscard]] double parabola_peak(const Rk4Trajectory& r, double K, double a, double b);

/// eq. 2.35 of SPEC §2 for xbar = eta / K, re-typed from the text: xbar'' from xbar, xbar' and
/// the container's acceleration a [m/s^2], with the model's omega_1 [rad/s], zeta, C, alpha and
/// radius R [m].
[[nodiscard]] double eq235_xbar_dd(double omega, double zeta, double C, double alpha, double radius,
                                   double x, double v, double a);

/// The parameters of the planar spherical-pendulum model (SPEC §14): omega_1 [rad/s], zeta, C,
/// alpha, the wall-height factor K [m per unit] and the radius R [m].
struct PendulumParameters {
  double omega{}, zeta{}, C{}, alpha{}, K{}, radius{};
};

/// Heading psi [rad] and curvature kappa [1/m] of a planar path at arc length s [m].
using PathGeometry = std::function<std::pair<double, double>(double s)>;

/// The wall height's peaks of the planar model along a path [m], and when the rest one is.
struct PlanarPendulumPeaks {
  double motion{}, rest{}, t_rest{};
};

/// The planar spherical-pendulum model, re-typed from SPEC §14 and docs/models.md:
/// M q'' + C^2 |q'|^2 q + 2 zeta w M q' + w^2 (1 + alpha |q|^2) q + a_h / R = 0 with
/// M = I + C^2 q q^T, driven by the 7-segment law of durations `d` (rebuilt from SPEC §3, its
/// levels set so that it moves `length`) along the path in the world frame (the container does
/// not turn): a_h = s'' T(psi) + kappa s'^2 N(psi). Classical RK4 with the tangential state
/// (s, s') integrated alongside, on steps of at most `step` [s] that end at every switch time.
[[nodiscard]] PlanarPendulumPeaks planar_pendulum_peaks(const PendulumParameters& m,
                                                        const std::array<double, 7>& d,
                                                        double length, const PathGeometry& at,
                                                        double rest_time, double step);

/// Fourier integral int f(t) exp(-j w t) dt of a sampled signal by the DFT sum
/// dt * sum f(n dt) exp(-j w n dt) (rectangle rule, as an FFT bin computes it).
[[nodiscard]] std::complex<double> dft_bin(const std::vector<double>& samples, double dt, double w);

}  // namespace slosh::test
