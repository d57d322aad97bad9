// The linear multi-mode model as isotropic 2-D oscillators in the world frame
// (planar_response.hpp; docs/models.md).

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "response/planar_linear_exact.hpp"
#include "response/planar_scheme.hpp"
#include "slosh/core/constants.hpp"

namespace slosh {

namespace {

/// M modes: state (x_1, y_1, ..., x_M, y_M).
template <std::size_t M>
struct LinearPlanarModel {
  static constexpr std::size_t N = 2 * M;
  using V = detail::Vec<N>;
  std::array<double, M> w2{}, two_zw{}, gain{}, inv_w2{};
  double w_max{};
  const SloshingModel* source{};

  explicit LinearPlanarModel(const SloshingModel& m) : source(&m) {
    for (std::size_t n = 0; n < M; ++n) {
      const double w = m.omega[n];
      w2[n] = w * w;
      inv_w2[n] = 1.0 / (w * w);
      two_zw[n] = 2.0 * m.zeta * w;
      gain[n] = m.eta_gain[n];
      w_max = std::max(w_max, w);
    }
  }

  V rhs(const V& x, const V& v, const PlanarExcitation& e) const {
    V a;
    const double g_scale = 1.0 + e.az / kGravity;
    for (std::size_t n = 0; n < M; ++n) {
      const double k = w2[n] * g_scale;
      a[2 * n] = -two_zw[n] * v[2 * n] - k * x[2 * n] - e.ax;
      a[2 * n + 1] = -two_zw[n] * v[2 * n + 1] - k * x[2 * n + 1] - e.ay;
    }
    return a;
  }

  void wave(const detail::DensePoly<V>& p, detail::Poly& ex, detail::Poly& ey) const {
    for (std::size_t k = 0; k < detail::kDenseTerms; ++k) {
      double sx = 0.0, sy = 0.0;
      for (std::size_t n = 0; n < M; ++n) {
        sx += gain[n] * p[k][2 * n];
        sy += gain[n] * p[k][2 * n + 1];
      }
      ex[k] = sx;
      ey[k] = sy;
    }
  }

  /// Each mode's reach within the horizon (oscillator_reach_over).
  double free_bound(const V& x, const V& v, double horizon) const {
    double b = 0.0;
    for (std::size_t n = 0; n < M; ++n) {
      const double qx = x[2 * n], qy = x[2 * n + 1], vx = v[2 * n], vy = v[2 * n + 1];
      const double e = 0.5 * ((vx * vx + vy * vy) * inv_w2[n] + qx * qx + qy * qy);
      const double l = qx * vy - qy * vx;
      b += std::abs(gain[n]) * std::sqrt(detail::oscillator_reach_over(e, l * l * inv_w2[n], 0.0,
                                                                       0.5 * two_zw[n], horizon));
    }
    return b;
  }

  double fastest_omega() const { return w_max; }
  const SloshingModel& sloshing_model() const { return *source; }
};

template <std::size_t M>
PlanarPeaks run(const SloshingModel& model, const PlanarDrive& drive, double rest_time,
                const PlanarOptions& options, double vortex_gain, std::vector<PlanarStep>* keep) {
  return detail::integrate_planar(LinearPlanarModel<M>(model), drive, rest_time, options,
                                  vortex_gain, keep);
}

PlanarPeaks dispatch(const SloshingModel& model, const PlanarDrive& drive, double rest_time,
                     const PlanarOptions& options, double vortex_gain,
                     std::vector<PlanarStep>* keep) {
  switch (model.modes()) {
    case 1:
      return run<1>(model, drive, rest_time, options, vortex_gain, keep);
    case 2:
      return run<2>(model, drive, rest_time, options, vortex_gain, keep);
    case 3:
      return run<3>(model, drive, rest_time, options, vortex_gain, keep);
    case 4:
      return run<4>(model, drive, rest_time, options, vortex_gain, keep);
    case 5:
      return run<5>(model, drive, rest_time, options, vortex_gain, keep);
    default:
      throw std::invalid_argument("planar linear model: modes must be in [1, 5]");
  }
}

}  // namespace

void PlanarBuilder::linear(PlanarResponse& r, const SloshingModel& model, const PlanarDrive& drive,
                           double rest_time, const PlanarOptions& options) {
  r.vortex_gain_ = detail::vortex_gain(model, options);
  r.motion_time_ = drive.duration();
  r.peaks_ = dispatch(model, drive, rest_time, options, r.vortex_gain_, &r.steps_);
}

PlanarLinearResponse::PlanarLinearResponse(const SloshingModel& model, const PlanarDrive& drive,
                                           double rest_time, const PlanarOptions& options) {
  PlanarBuilder::linear(*this, model, drive, rest_time, options);
}

PlanarPeaks planar_linear_peaks(const SloshingModel& model, const PlanarDrive& drive,
                                double rest_time, const PlanarOptions& options) {
  if (std::optional<PlanarPeaks> exact =
          detail::exact_planar_linear_peaks(model, drive, rest_time, options)) {
    return *exact;
  }
  return dispatch(model, drive, rest_time, options, detail::vortex_gain(model, options), nullptr);
}

}  // namespace slosh
