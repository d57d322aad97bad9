#pragma once
// The integration shared by the planar models (internal to the core): the DOP853 scheme of the
// straight-line nonlinear model (nonlinear_scheme.hpp) on a small state vector, equal steps on
// every smooth piece of the drive, the exact per-step maximum of the wall height over the wall,
// and the rest window's early end by the model's energy bound.
//
// A model supplies (Model concept):
//   static constexpr std::size_t N;                       state components
//   Vec<N> rhs(const Vec<N>& x, const Vec<N>& v, const PlanarExcitation& e) const;
//   void wave(const DensePoly<Vec<N>>& x_poly, Poly& ex, Poly& ey) const;   E over a step
//   double free_bound(const Vec<N>& x, const Vec<N>& v, double horizon) const;
//                                                         bound of |E| in free motion up to
//                                                         `horizon` seconds ahead
//   double fastest_omega() const;                         [rad/s], sets the step

#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "slosh/core/constants.hpp"
#include "slosh/core/response/planar_response.hpp"
#include "slosh/core/response/response.hpp"

#include "response/nonlinear_scheme.hpp"
#include "response/planar_spin.hpp"

namespace slosh::detail {

/// A fixed-size state vector with element-wise arithmetic (what the DOP853 templates need).
template <std::size_t N>
struct Vec {
  std::array<double, N> c{};
  Vec() = default;
  Vec(double v) { c.fill(v); }  // NOLINT(google-explicit-constructor): scalars broadcast
  double& operator[](std::size_t i) { return c[i]; }
  double operator[](std::size_t i) const { return c[i]; }
};
template <std::size_t N>
Vec<N> operator+(const Vec<N>& a, const Vec<N>& b) {
  Vec<N> r;
  for (std::size_t i = 0; i < N; ++i) r.c[i] = a.c[i] + b.c[i];
  return r;
}
template <std::size_t N>
Vec<N> operator-(const Vec<N>& a, const Vec<N>& b) {
  Vec<N> r;
  for (std::size_t i = 0; i < N; ++i) r.c[i] = a.c[i] - b.c[i];
  return r;
}
template <std::size_t N>
Vec<N> operator*(const Vec<N>& a, const Vec<N>& b) {
  Vec<N> r;
  for (std::size_t i = 0; i < N; ++i) r.c[i] = a.c[i] * b.c[i];
  return r;
}
template <std::size_t N>
Vec<N> operator*(double a, const Vec<N>& b) {
  Vec<N> r;
  for (std::size_t i = 0; i < N; ++i) r.c[i] = a * b.c[i];
  return r;
}
template <std::size_t N>
Vec<N> operator*(const Vec<N>& b, double a) {
  return a * b;
}

using Poly = std::array<double, kDenseTerms>;

/// The largest f(s) = |E(s)| + g w(s)^2 over s in [lo, hi] of a step (E = (ex, ey), w the
/// liquid's spin) and where: the ends and every interior maximum, a root of f' located on 8
/// sub-intervals and refined by the Illinois false position to 1e-13 of the step.
struct StepMax {
  double value{-1.0};
  double s{};
  double direction{};
};
StepMax step_max(const Poly& ex, const Poly& ey, const Poly& w, double vortex_gain);

/// A bound of max f over the step (sum of |coefficients|): steps that cannot hold a new peak are
/// not searched.
double step_bound(const Poly& ex, const Poly& ey, const Poly& w, double vortex_gain);

/// Rate of the liquid's spin-up through the bottom Ekman layer [1/s] (planar_response.hpp).
inline double ekman_rate(double nu, double fill_height, double theta_dot, double spin) {
  const double omega = std::max(std::abs(theta_dot), std::abs(spin));
  return std::sqrt(nu * omega) / fill_height;
}

/// R^2 / (4 g): the forced vortex's rise at the wall per (rad/s)^2 of spin [m s^2] (0 when the
/// spin is not modelled).
inline double vortex_gain(const SloshingModel& model, const PlanarOptions& options) {
  return options.spin == SpinLag::kNone ? 0.0 : model.radius * model.radius / (4.0 * kGravity);
}

/// The largest y = |q|^2 an isotropic 2-D oscillator can reach in free motion, from its energy and
/// angular momentum normalised by w^2: e = E / w^2 with E = kinetic + w^2 (y/2 + alpha y^2/4),
/// l2 = (L / w)^2 with L = q x q'. At any instant the kinetic energy holds at least the rotation's
/// L^2 / (2 y) (the paraboloid's extra inertia only adds radial motion), so
/// l2 / (2 y) + y / 2 + alpha y^2 / 4 <= e, and y is below the largest root. E never increases in
/// free motion and L decays exactly as exp(-2 zeta w t) (the damping's torque is -2 zeta w L:
/// the paraboloid's part of the damping is radial), so the root for the energy now and the
/// angular momentum at the horizon bounds y up to the horizon. Alpha = 0: the closed form; else
/// Newton's method from the root for l2 = 0, whose iterates fall monotonically onto the root (the
/// left side is convex in y), so every iterate is itself a bound.
inline double oscillator_reach(double e, double l2, double alpha) {
  if (alpha == 0.0) return e + std::sqrt(std::max(e * e - l2, 0.0));
  double y = 2.0 * e / (0.5 + std::sqrt(0.25 + alpha * e));
  for (int it = 0; it < 4 && l2 > 0.0; ++it) {
    const double g = 0.25 * alpha * y * y + 0.5 * y + 0.5 * l2 / y - e;
    const double dg = 0.5 * alpha * y + 0.5 - 0.5 * l2 / (y * y);
    if (!(g > 0.0) || !(dg > 0.0)) break;
    y -= g / dg;
  }
  return y;
}

/// The largest |q|^2 of an isotropic 2-D oscillator over a free-motion horizon, from e and l2 as
/// oscillator_reach() takes them and k = zeta w. On every sixteenth of the horizon the reach for
/// the energy at its start and the angular momentum at its end bounds |q|^2 by Y; the damping then
/// dissipates at least 2 k |q'|^2 >= 2 k L^2 / Y (in these units, 2 k l2 / Y), so the energy at
/// its end is at most e - l2 (1 - z) / (2 Y), z = exp(-4 k h); on the stretch the reach grows
/// with time (it falls with l2 faster than with the guaranteed energy loss while |q|^2 <= Y), so
/// its largest value is the reach at the end. The bound follows a swirling wave's slow decay,
/// which the reach for the energy now and the angular momentum at the horizon's end does not.
inline double oscillator_reach_over(double e, double l2, double alpha, double k, double horizon) {
  constexpr int kParts = 16;
  double best = oscillator_reach(e, l2, alpha);
  if (!(l2 > 0.0) || !(horizon > 0.0)) return best;
  const double z = std::exp(-4.0 * k * horizon / kParts);
  for (int i = 0; i < kParts; ++i) {
    const double Y = oscillator_reach(e, l2 * z, alpha);
    if (!(Y > 0.0)) break;
    e -= l2 * (1.0 - z) / (2.0 * Y);
    l2 *= z;
    best = std::max(best, oscillator_reach(e, l2, alpha));
  }
  return best;
}

/// The longest step on drive piece p [s]: at most h_max, and steps_per_period steps per period of
/// the law piece's harmonic and per turn of the heading at the piece's largest rate (on an arc
/// the world-frame acceleration turns with the heading, so a fast whirl on a tiny radius forces
/// the liquid far faster than its modes). Exactly h_max where neither bound is shorter.
inline double drive_piece_step(double h_max, const DrivePiece& p, double steps_per_period) {
  return piece_max_step(piece_max_step(h_max, p.harmonic_omega, steps_per_period), p.heading_rate,
                        steps_per_period);
}

/// Relative margin of the rest window's stopping test (as nonlinear_response.cpp).
inline constexpr double kPlanarStopMargin{1e-6};

/// Integrates `model` over the drive and the rest window; stores every step in `keep` (then the
/// whole rest window is integrated) or stops once the rest window's peak is proved found.
template <typename Model>
PlanarPeaks integrate_planar(const Model& model, const PlanarDrive& drive, double rest_time,
                             const PlanarOptions& options, double vortex_gain,
                             std::vector<PlanarStep>* keep) {
  constexpr std::size_t N = Model::N;
  using V = Vec<N>;
  const double h_max = std::min(
      options.max_step, 2.0 * std::numbers::pi / model.fastest_omega() / options.steps_per_period);
  const double T = drive.duration();
  const std::vector<DrivePiece>& pieces = drive.pieces();
  const SpinTrack spin = drive.turns() && vortex_gain > 0.0
                             ? SpinTrack(drive, rest_time, model.sloshing_model(), options)
                             : SpinTrack();
  const PlanarExcitation at_rest{};
  auto rhs = [&model](const V& x, const V& v, const PlanarExcitation& e) {
    return model.rhs(x, v, e);
  };
  PlanarPeaks peaks;
  bool rest_found = false;
  V x(0.0), v(0.0);
  DopStep<V> step;
  Poly ex{}, ey{}, w{};
  for (std::size_t k = 0; k <= pieces.size(); ++k) {
    const bool in_rest = k == pieces.size();
    const DrivePiece p = in_rest ? DrivePiece{T, T + rest_time} : pieces[k];
    const double L = p.t_end - p.t_begin;
    if (!(L > 0.0)) continue;
    const std::size_t n = step_count(L, drive_piece_step(h_max, p, options.steps_per_period), 1);
    const double h = L / static_cast<double>(n);
    auto excitation = [&](double t) { return in_rest ? at_rest : drive.excitation(k, t); };
    V f0 = rhs(x, v, excitation(p.t_begin));
    PlanarPeak& window = in_rest ? peaks.rest : peaks.motion;
    for (std::size_t j = 0; j < n; ++j) {
      const double t0 = p.t_begin + h * static_cast<double>(j);
      PlanarExcitation end{};
      auto acc = [&](std::size_t i) {
        if (i == 12) return end;  // c_12 = c_11 = 1
        const PlanarExcitation e = excitation(t0 + kDopC[i] * h);
        if (i == 11) end = e;
        return e;
      };
      dop853_step(rhs, acc, x, v, f0, V(h), true, step, false);
      model.wave(step.x_poly, ex, ey);
      if (!spin.empty()) w = spin.over(t0, h);
      if (!(in_rest && rest_found) && step_bound(ex, ey, w, vortex_gain) > window.value) {
        const StepMax m = step_max(ex, ey, w, vortex_gain);
        if (m.value > window.value) window = {m.value, t0 + m.s * h, m.direction};
      }
      if (keep != nullptr) keep->push_back({t0, h, ex, ey, w});
      x = step.x1;
      v = step.v1;
      f0 = step.f1;
      if (in_rest && !rest_found) {
        // Once the container stops turning the spin only decays.
        const double spin_rate = horner(w, 1.0);
        const double horizon = T + rest_time - (t0 + h);
        const double bound = model.free_bound(x, v, horizon) + vortex_gain * spin_rate * spin_rate;
        if (bound * (1.0 + kPlanarStopMargin) <= peaks.rest.value) {
          rest_found = true;
          if (keep == nullptr) break;
        }
      }
    }
  }
  if (!std::isfinite(x[0]) || !std::isfinite(v[0])) {
    peaks.motion.value = peaks.rest.value = std::numeric_limits<double>::quiet_NaN();
  }
  return peaks;
}

}  // namespace slosh::detail

namespace slosh {

/// Fills a PlanarResponse (its friend): one function per model.
struct PlanarBuilder {
  static void linear(PlanarResponse& r, const SloshingModel& model, const PlanarDrive& drive,
                     double rest_time, const PlanarOptions& options);
  static void nonlinear(PlanarResponse& r, const SloshingModel& model, const PlanarDrive& drive,
                        double rest_time, const PlanarOptions& options);
};

}  // namespace slosh
