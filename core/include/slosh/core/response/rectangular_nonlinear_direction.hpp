#pragma once
// One direction of a rectangular tank in the nonlinear model (docs/models.md, "Nonlinear model
// of a rectangular tank"), a multimodal model of Moiseev type after Faltinsen et al. (2000):
// - the dominant mode beta_1 as the third-order oscillator of make_rectangular_direction_model
//   (NonlinearResponse), whose backbone is Tadjbakhsh & Keller's (1960) frequency correction;
// - the second mode b_2 it drives at second order,
//     b_2'' + 2 zeta sigma_2 b_2' + sigma_2^2 b_2 = -d4 beta_1 beta_1'' - d5 beta_1'^2,
//   whose coefficients reproduce Tadjbakhsh & Keller's second-order standing wave;
// - the higher antisymmetric modes n >= 2 of the model (k_n = (2n - 1) pi / side), linear.
// b_2 is the even mode cos(2 pi x' / side) (x' from a wall): it raises both walls alike, so the
// higher wall is |beta_1 + higher| + |b_2| (crests higher than troughs are deep).

#include <cmath>
#include <optional>
#include <vector>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh {

/// Coefficients of the second-mode equation of one direction (side L = model.radius, depth h,
/// k = pi / L, T = tanh(k h)): sigma_2^2 = 2 g k tanh(2 k h) (times omega_scale^2, read from the
/// model's first frequency), d4 = k (T^2 - 1) / (T (1 + T^2)), d5 = -2 k / (T (1 + T^2)) [1/m].
/// With beta_1 = A cos(w t), w = omega_1, the steady b_2 is the wall value of Tadjbakhsh &
/// Keller's second-order term, (k A^2 / 8) [(T^-1 + T) + (3 T^-3 - T^-1) cos(2 w t)].
struct RectangularSecondMode {
  double sigma2{};  ///< [rad/s]
  double d4{};      ///< [1/m]
  double d5{};      ///< [1/m]
};
[[nodiscard]] RectangularSecondMode rectangular_second_mode(const SloshingModel& model);

/// The highest |eta| over the four corners of a tank whose two directions both slosh, from each
/// direction's odd wave (its antisymmetric modes: opposite at its two walls) and its second mode
/// b_2 (the even mode cos(2 pi x' / side): alike at both walls) [m]: the corners carry
/// +-odd_L +-odd_W + even_L + even_W, the highest |odd_L| + |odd_W| + |even_L + even_W|.
/// simulate's series and every peak search of a turned tank take this one measure.
[[nodiscard]] inline double highest_corner(double odd_l, double even_l, double odd_w,
                                           double even_w) {
  return std::abs(odd_l) + std::abs(odd_w) + std::abs(even_l + even_w);
}

/// The response of one direction to the acceleration `law` (already scaled by the direction's
/// component), over [0, T + rest_time].
class RectangularNonlinearDirection {
 public:
  RectangularNonlinearDirection(const SloshingModel& model, const MotionLaw& law, double rest_time,
                                const NonlinearOptions& options = {});

  /// beta_1: dominant-mode elevation at the wall x = +side/2 [m] (K xbar, with the height gain).
  [[nodiscard]] double eta_dominant(double t) const { return first_.eta(t); }
  /// The linear higher antisymmetric modes at the wall x = +side/2 [m] (0 with one mode).
  [[nodiscard]] double eta_higher(double t) const { return higher_ ? higher_->eta(t) : 0.0; }
  /// All antisymmetric modes at the wall x = +side/2 (minus it at x = -side/2) [m].
  [[nodiscard]] double eta_odd(double t) const { return eta_dominant(t) + eta_higher(t); }
  /// b_2: second-mode elevation at either wall [m] (cubic Hermite between the RK4 nodes).
  [[nodiscard]] double eta_even(double t) const;
  /// Higher wall at t: |eta_odd| + |eta_even| [m].
  [[nodiscard]] double wall(double t) const;
  /// Peaks of wall(t) in the motion and rest windows (sampled at <= 1 ms and <= 1/64 of the
  /// period of the fastest mode, the second one included, refined by golden section).
  [[nodiscard]] SloshPeaks peaks() const { return peaks_; }
  /// Sampling step of the peak searches [s].
  [[nodiscard]] double peak_step() const { return peak_step_; }

 private:
  void integrate_second_mode(const SloshingModel& model, const MotionLaw& law, double rest_time);

  NonlinearResponse first_;
  std::optional<LinearResponse> higher_;
  RectangularSecondMode mode2_{};
  double zeta_{};
  double gain_{1.0};  ///< the model's height gain: b_2 is driven by beta_1 / gain
  std::vector<double> t_, b_, b_dot_;
  double peak_step_{};
  SloshPeaks peaks_;
};

}  // namespace slosh
