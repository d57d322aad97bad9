#pragma once
// The numerical scheme of the nonlinear model, shared by NonlinearResponse (doubles) and
// NonlinearSensitivity (dual numbers), so both integrate exactly the same discrete response
// (internal to the core).

#include "slosh/core/model/sloshing_model.hpp"

namespace slosh::detail {

/// xbar'' of eq. 2.35 for the container acceleration a [m/s^2], any scalar type.
template <typename S>
S nonlinear_rhs(const SloshingModel& m, const S& x, const S& v, const S& a) {
  const double w = m.omega1();
  const double c2 = m.C * m.C;
  const S c2x2 = c2 * x * x;
  const S num = 2.0 * w * m.zeta * v * (1.0 + c2x2) + c2 * x * v * v +
                w * w * x * (1.0 + m.alpha * x * x) + a / m.radius;
  return -num / (1.0 + c2x2);
}

/// Cubic Hermite of x on one interval at theta in [0, 1], any scalar type.
template <typename S>
S hermite(const S& x0, const S& v0, const S& x1, const S& v1, const S& H, const S& s) {
  const S one(1.0);
  const S h00 = (one + 2.0 * s) * (one - s) * (one - s);
  const S h10 = s * (one - s) * (one - s);
  const S h01 = s * s * (3.0 - 2.0 * s);
  const S h11 = s * s * (s - one);
  return h00 * x0 + h10 * H * v0 + h01 * x1 + h11 * H * v1;
}

/// One classical RK4 step of (x, v) with the container acceleration at the start, middle and end.
template <typename S>
void rk4_step(const SloshingModel& m, S& x, S& v, const S& h, const S& a0, const S& a_mid,
              const S& a1) {
  const S half_h = 0.5 * h;
  const S k1x = v;
  const S k1v = nonlinear_rhs(m, x, v, a0);
  const S k2x = v + half_h * k1v;
  const S k2v = nonlinear_rhs(m, x + half_h * k1x, k2x, a_mid);
  const S k3x = v + half_h * k2v;
  const S k3v = nonlinear_rhs(m, x + half_h * k2x, k3x, a_mid);
  const S k4x = v + h * k3v;
  const S k4v = nonlinear_rhs(m, x + h * k3x, k4x, a1);
  const S sixth_h = h * (1.0 / 6.0);
  x = x + sixth_h * (k1x + 2.0 * (k2x + k3x) + k4x);
  v = v + sixth_h * (k1v + 2.0 * (k2v + k3v) + k4v);
}

}  // namespace slosh::detail
