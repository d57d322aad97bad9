// The nonlinear fundamental-mode model of eq. 2.35 made planar: the spherical-pendulum form
// (planar_response.hpp; docs/models.md).

#include <cmath>

#include "response/planar_scheme.hpp"
#include "slosh/core/constants.hpp"

namespace slosh {

namespace {

/// State (xbar, ybar), q = r_1 / R.
struct NonlinearPlanarModel {
  static constexpr std::size_t N = 2;
  using V = detail::Vec<N>;
  double w{}, w2{}, two_zw{}, c2{}, alpha{}, inv_radius{}, K{};
  const SloshingModel* source{};

  explicit NonlinearPlanarModel(const SloshingModel& m)
      : w(m.omega1()),
        w2(m.omega1() * m.omega1()),
        two_zw(2.0 * m.zeta * m.omega1()),
        c2(m.C * m.C),
        alpha(m.alpha),
        inv_radius(1.0 / m.radius),
        K(m.K),
        source(&m) {}

  // M q'' = b with M = I + C^2 q q^T, so q'' = b - C^2 q (q . b) / (1 + C^2 |q|^2).
  V rhs(const V& x, const V& v, const PlanarExcitation& e) const {
    const double qx = x[0], qy = x[1], vx = v[0], vy = v[1];
    const double r2 = qx * qx + qy * qy;
    const double v2 = vx * vx + vy * vy;
    const double qv = qx * vx + qy * vy;
    const double stiff = w2 * (1.0 + e.az / kGravity) * (1.0 + alpha * r2);
    const double bx =
        -(c2 * v2 * qx + stiff * qx + two_zw * (vx + c2 * qx * qv) + e.ax * inv_radius);
    const double by =
        -(c2 * v2 * qy + stiff * qy + two_zw * (vy + c2 * qy * qv) + e.ay * inv_radius);
    const double lam = c2 * (qx * bx + qy * by) / (1.0 + c2 * r2);
    V a;
    a[0] = bx - lam * qx;
    a[1] = by - lam * qy;
    return a;
  }

  void wave(const detail::DensePoly<V>& p, detail::Poly& ex, detail::Poly& ey) const {
    for (std::size_t k = 0; k < detail::kDenseTerms; ++k) {
      ex[k] = K * p[k][0];
      ey[k] = K * p[k][1];
    }
  }

  /// The energy (|q'|^2 + C^2 (q . q')^2) / 2 + w^2 (|q|^2 / 2 + alpha |q|^4 / 4) never increases
  /// in free motion (the damping dissipates 2 zeta w q'^T M q'); with the angular momentum it
  /// bounds |q| up to the horizon (oscillator_reach_over).
  double free_bound(const V& x, const V& v, double horizon) const {
    const double r2 = x[0] * x[0] + x[1] * x[1];
    const double qv = x[0] * v[0] + x[1] * v[1];
    const double v2 = v[0] * v[0] + v[1] * v[1];
    const double e = (0.5 * (v2 + c2 * qv * qv) + w2 * r2 * (0.5 + 0.25 * alpha * r2)) / w2;
    const double l = x[0] * v[1] - x[1] * v[0];
    return K *
           std::sqrt(detail::oscillator_reach_over(e, l * l / w2, alpha, 0.5 * two_zw, horizon));
  }

  double fastest_omega() const { return w; }
  const SloshingModel& sloshing_model() const { return *source; }
};

}  // namespace

void PlanarBuilder::nonlinear(PlanarResponse& r, const SloshingModel& model,
                              const PlanarDrive& drive, double rest_time,
                              const PlanarOptions& options) {
  r.vortex_gain_ = detail::vortex_gain(model, options);
  r.motion_time_ = drive.duration();
  r.peaks_ = detail::integrate_planar(NonlinearPlanarModel(model), drive, rest_time, options,
                                      r.vortex_gain_, &r.steps_);
}

PlanarNonlinearResponse::PlanarNonlinearResponse(const SloshingModel& model,
                                                 const PlanarDrive& drive, double rest_time,
                                                 const PlanarOptions& options) {
  PlanarBuilder::nonlinear(*this, model, drive, rest_time, options);
}

PlanarPeaks planar_nonlinear_peaks(const SloshingModel& model, const PlanarDrive& drive,
                                   double rest_time, const PlanarOptions& options) {
  return detail::integrate_planar(NonlinearPlanarModel(model), drive, rest_time, options,
                                  detail::vortex_gain(model, options), nullptr);
}

}  // namespace slosh
