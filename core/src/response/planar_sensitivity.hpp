#pragma once
// The planar nonlinear model (planar_nonlinear.cpp) driven by a 7-segment law along a planar
// path, integrated by the same DOP853 scheme in dual numbers over the 7 durations: every step
// carries the exact derivatives of its state and interpolant, so the wave height at any time
// comes with its exact gradient (internal to the core; what time_domain optimises along a path
// for a cylinder). The steps never cross a point where the drive is not smooth
// (path_law_duals.hpp).

#include <array>
#include <cstddef>
#include <cstring>
#include <limits>
#include <vector>

#include "response/dual8.hpp"
#include "response/nonlinear_scheme.hpp"
#include "response/path_law_duals.hpp"
#include "response/path_sensitivity.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "solve/dual.hpp"

namespace slosh::detail {

/// The planar nonlinear model's right-hand side (planar_nonlinear.cpp) at a_z = 0 on dual
/// states, linearised by hand: the value lanes are the model's formula in double, operation for
/// operation as generic dual arithmetic would compute them; the derivative lanes are the 2 x 6
/// Jacobian (q_x, q_y, v_x, v_y, a_x, a_y) applied to the inputs' lanes: 12 lane products instead
/// of the ~17 dual products (three lane operations each) of the formula in duals, and the same
/// derivatives up to rounding.
struct PlanarTangentRhs {
  double w2{};          ///< omega_1^2 [1/s^2]
  double two_zw{};      ///< 2 zeta omega_1 [1/s]
  double c2{};          ///< C^2 [1/m^2]
  double alpha{};       ///< the stiffening coefficient alpha [1/m^2]
  double inv_radius{};  ///< 1 / R [1/m]

  [[gnu::always_inline]] DualPair operator()(const DualPair& x, const DualPair& v,
                                             const std::array<D8, 2>& a) const {
    const double qx = x.c[0].x[0], qy = x.c[1].x[0];
    const double vx = v.c[0].x[0], vy = v.c[1].x[0];
    const double ax = a[0].x[0], ay = a[1].x[0];
    const double r2 = qx * qx + qy * qy;
    const double v2 = vx * vx + vy * vy;
    const double qv = qx * vx + qy * vy;
    const double stiff = w2 * (1.0 + alpha * r2);
    const double damp = c2 * qv;
    const double bx = -(c2 * (v2 * qx) + stiff * qx + two_zw * (vx + qx * damp) + inv_radius * ax);
    const double by = -(c2 * (v2 * qy) + stiff * qy + two_zw * (vy + qy * damp) + inv_radius * ay);
    const double inv_den = 1.0 / (c2 * r2 + 1.0);
    const double lam = (c2 * (qx * bx + qy * by)) * inv_den;
    // The partials of b = (bx, by) by z = (q_x, q_y, v_x, v_y, a_x, a_y).
    const double s2 = 2.0 * w2 * alpha;  // d stiff / d r2, times 2 for d r2 / d q = 2 q
    const double common = c2 * v2 + stiff + two_zw * damp;
    const double tzc = two_zw * c2;
    const std::array<double, 6> dbx{-(common + s2 * qx * qx + tzc * qx * vx),
                                    -(s2 * qy * qx + tzc * qx * vy),
                                    -(2.0 * c2 * vx * qx + two_zw + tzc * qx * qx),
                                    -(2.0 * c2 * vy * qx + tzc * qx * qy),
                                    -inv_radius,
                                    0.0};
    const std::array<double, 6> dby{-(s2 * qx * qy + tzc * qy * vx),
                                    -(common + s2 * qy * qy + tzc * qy * vy),
                                    -(2.0 * c2 * vx * qy + tzc * qy * qx),
                                    -(2.0 * c2 * vy * qy + two_zw + tzc * qy * qy),
                                    0.0,
                                    -inv_radius};
    // lam = c2 (q . b) / (1 + c2 r2): its partials by the quotient rule.
    std::array<double, 6> dlam{};
    for (std::size_t z = 0; z < 6; ++z) dlam[z] = c2 * (qx * dbx[z] + qy * dby[z]);
    dlam[0] += c2 * bx - lam * 2.0 * c2 * qx;
    dlam[1] += c2 * by - lam * 2.0 * c2 * qy;
    for (double& l : dlam) l *= inv_den;
    // out = b - lam q.
    std::array<double, 6> jx{}, jy{};
    for (std::size_t z = 0; z < 6; ++z) {
      jx[z] = dbx[z] - dlam[z] * qx;
      jy[z] = dby[z] - dlam[z] * qy;
    }
    jx[0] -= lam;
    jy[1] -= lam;
    std::array<Lanes4, 2> ox, oy;
    for (std::size_t h = 0; h < 2; ++h) {
      const Lanes4 qx4 = half(x.c[0], h), qy4 = half(x.c[1], h);
      const Lanes4 vx4 = half(v.c[0], h), vy4 = half(v.c[1], h);
      const Lanes4 ax4 = half(a[0], h), ay4 = half(a[1], h);
      ox[h] = broadcast(jx[0]) * qx4 + broadcast(jx[1]) * qy4 + broadcast(jx[2]) * vx4 +
              broadcast(jx[3]) * vy4 + broadcast(jx[4]) * ax4 + broadcast(jx[5]) * ay4;
      oy[h] = broadcast(jy[0]) * qx4 + broadcast(jy[1]) * qy4 + broadcast(jy[2]) * vx4 +
              broadcast(jy[3]) * vy4 + broadcast(jy[4]) * ax4 + broadcast(jy[5]) * ay4;
    }
    DualPair out;
    out.c[0] = d8_of(ox[0], ox[1], bx - lam * qx);
    out.c[1] = d8_of(oy[0], oy[1], by - lam * qy);
    return out;
  }
};

struct PlanarSensitivityPass;

class PlanarSensitivity final : public PathSensitivity {
 public:
  /// `steps_per_period`: steps per period of mode 1 (the step is also at most 50 ms).
  PlanarSensitivity(const SloshingModel& model, const PlanarPath& path, double rest_time,
                    double steps_per_period);

  /// Integrates the model for the durations d over the motion and the rest window, or only as far
  /// as the step that reaches `until` [s] (the same steps as the whole window's, so the response
  /// up to there is the same to the last bit; times later than that are not to be read).
  void compute(const double* d, double until = std::numeric_limits<double>::infinity()) override;
  /// Fixes the least step count of every smooth piece at one more than d takes, for every
  /// compute() until the next call while the pieces keep their order (so the discrete response
  /// stays smooth in the durations during a solver's run).
  void freeze_steps(const double* d) override;
  /// K |q(t)| at each time of `t` (any order) with its gradient over the durations.
  void eta_at(const std::vector<double>& t, std::vector<double>& values,
              std::vector<std::array<double, kSegments>>& gradients) const override;
  /// The time of the largest K |q| over [lo, hi] (any two times inside the response): the
  /// interior maximum where |q|^2 has one (its slope changes sign from + to -), else the larger
  /// end. A row bounded there follows its peak as the durations move, and its value (continuous
  /// in the durations) has the gradient at fixed time (envelope theorem).
  [[nodiscard]] double peak_time(double lo, double hi) const override;
  /// The largest K |q| in every window of `window` seconds over [t_begin, t_end] (exact per
  /// step: the roots of the interpolant's slope).
  [[nodiscard]] std::vector<PlanarWindowPeak> window_peaks(double t_begin, double t_end,
                                                           double window) const override;
  [[nodiscard]] double motion_time() const override { return motion_time_; }

 private:
  struct Stored {
    D8 t0, h;
    DensePoly<DualPair> q;
  };
  friend struct PlanarSensitivityPass;
  double until_{std::numeric_limits<double>::infinity()};
  [[nodiscard]] std::size_t step_at(double t) const;

  SloshingModel model_;
  PlanarPath path_;
  double rest_time_;
  double h_max_;
  double steps_per_period_;
  double motion_time_{};
  PathLawDuals law_;  // the law's state at each segment start (set by its pieces())
  FrozenSteps frozen_;
  std::vector<Stored> steps_;
  std::vector<double> t0_values_;
};

}  // namespace slosh::detail
