#pragma once
// A rectangular tank's models along a motion (rectangular_planar.hpp) as one state: both
// directions' modes, linear or each direction as RectangularNonlinearDirection (internal to the
// core). The right-hand side and the wall signals are templates over the state's scalar, so the
// verification (RectangularPlanarResponse, doubles) and the optimiser's sensitivity
// (TankPlanarSensitivity, dual numbers over the 7 durations) integrate the same formulas.

#include <algorithm>
#include <array>
#include <cstddef>

#include "response/nonlinear_scheme.hpp"
#include "slosh/core/model/sloshing_model.hpp"

namespace slosh::detail {

/// The excitation in the tank's frame at one instant.
struct TankExcitation {
  double a[2]{};        ///< along L, along W [m/s^2]
  double g_scale{1.0};  ///< 1 + a_z / g
};

/// One direction's coefficients.
struct TankDirection {
  double side{};
  double zeta{};
  std::array<double, kMaxModes> w2{}, two_zw{}, gain{};
  // Nonlinear dominant mode and second mode (RectangularNonlinearDirection).
  double alpha{}, K{}, k_raw{}, even_gain{}, s2{}, two_zs{}, d4{}, d5{};
  double fastest{};
};

[[nodiscard]] TankDirection tank_direction(const SloshingModel& m, bool nonlinear);

/// Both directions with M modes each. Linear state per direction: x_1..x_M (the sloshing
/// masses' displacements [m]). Nonlinear: xbar (the dominant mode, [-]), x_2..x_M, b_2 (the
/// second mode's elevation without the height gain [m]). A state type may hold more coordinates
/// after these 2 kPer (the sensitivity's liquid spin): rhs leaves them 0.
template <std::size_t M, bool Nonlinear>
struct TankModel {
  static constexpr std::size_t kPer = Nonlinear ? M + 1 : M;
  static constexpr std::size_t N = 2 * kPer;
  std::array<TankDirection, 2> dir;

  /// `e.a[d]` the acceleration along direction d (a double or a dual), `e.g_scale` a double.
  template <typename V, typename E>
  V rhs(const V& x, const V& v, const E& e) const {
    V out(0.0);
    for (std::size_t d = 0; d < 2; ++d) {
      const TankDirection& c = dir[d];
      const std::size_t o = d * kPer;
      const auto& a = e.a[d];
      if constexpr (Nonlinear) {
        const auto xb = x[o], vb = v[o];
        const auto xdd =
            -c.two_zw[0] * vb - c.w2[0] * e.g_scale * xb * (1.0 + c.alpha * xb * xb) - a / c.side;
        out[o] = xdd;
        for (std::size_t n = 1; n < M; ++n) {
          out[o + n] = -c.two_zw[n] * v[o + n] - c.w2[n] * e.g_scale * x[o + n] - a;
        }
        const auto beta = c.k_raw * xb, beta_dot = c.k_raw * vb, beta_dd = c.k_raw * xdd;
        out[o + M] = -c.two_zs * v[o + M] - c.s2 * e.g_scale * x[o + M] - c.d4 * beta * beta_dd -
                     c.d5 * beta_dot * beta_dot;
      } else {
        for (std::size_t n = 0; n < M; ++n) {
          out[o + n] = -c.two_zw[n] * v[o + n] - c.w2[n] * e.g_scale * x[o + n] - a;
        }
      }
    }
    return out;
  }

  /// The four signals over a step: odd L, even L, odd W, even W (T the state's scalar).
  template <typename T, typename P>
  void signals(const P& p, std::array<std::array<T, kDenseTerms>, 4>& eta) const {
    for (std::size_t k = 0; k < kDenseTerms; ++k) {
      for (std::size_t d = 0; d < 2; ++d) {
        const TankDirection& c = dir[d];
        const std::size_t o = d * kPer;
        T odd(0.0), even(0.0);
        if constexpr (Nonlinear) {
          odd = c.K * p[k][o];
          for (std::size_t n = 1; n < M; ++n) odd = odd + c.gain[n] * p[k][o + n];
          even = c.even_gain * p[k][o + M];
        } else {
          for (std::size_t n = 0; n < M; ++n) odd = odd + c.gain[n] * p[k][o + n];
        }
        eta[2 * d][k] = odd;
        eta[2 * d + 1][k] = even;
      }
    }
  }

  [[nodiscard]] double fastest_omega() const { return std::max(dir[0].fastest, dir[1].fastest); }
};

}  // namespace slosh::detail
