#pragma once
// The nonlinear model (eq. 2.35) of a calibrated format integrated in dual numbers over the three
// parameters that enter the equation of motion (omega_scale, zeta, alpha): every step's dense
// output carries xbar with its exact derivatives, so eta(t) and the window peaks come with exact
// parameter gradients (automatic differentiation through the integrator; the same scheme (DOP853),
// grid and dense output as NonlinearResponse; internal to the core).

#include <array>
#include <vector>

#include "response/nonlinear_scheme.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/response.hpp"
#include "solve/dual.hpp"

namespace slosh::detail {

using Dual3 = Dual<3>;

/// The equation-of-motion parameters: omega_scale, zeta, alpha (derivative directions 0..2).
using MotionParameters = std::array<double, 3>;

/// eta at one time with its gradient with respect to (omega_scale, zeta, alpha) and its rate.
struct EtaSample {
  double value{};                    ///< eta [m] (signed, gain included)
  std::array<double, 3> gradient{};  ///< d eta / d (omega_scale, zeta, alpha) [m]
  double rate{};                     ///< d eta / d t [m/s]
};

class CalibrationResponse {
 public:
  /// `base` is the model with omega_scale = height_gain = 1 (its omega1 and K are scaled here).
  CalibrationResponse(SloshingModel base, MotionLaw law, double rest_time,
                      const NonlinearOptions& options = {});

  /// Integrates the response for parameters p (height_gain multiplies eta).
  void compute(const MotionParameters& p, double height_gain);
  /// eta at time t (held at the ends beyond [0, end]) with gradient and rate.
  [[nodiscard]] EtaSample eta_at(double t) const;
  /// The largest |eta| over [t_begin, t_end] (found exactly on the dense output) with
  /// its gradient at fixed time (exact wherever the argmax is unique); `value` >= 0.
  [[nodiscard]] EtaSample abs_peak(double t_begin, double t_end) const;
  [[nodiscard]] double motion_time() const { return law_.duration(); }

 private:
  [[nodiscard]] EtaSample sample(std::size_t interval, double t) const;

  SloshingModel base_;
  MotionLaw law_;
  double rest_time_;
  NonlinearOptions options_;
  double gain_{1.0};
  std::vector<double> t_, h_;        // start and length of every step [s]
  std::vector<DensePoly<Dual3>> x_;  // xbar over each step, in theta
  double end_{};                     // end of the rest window [s]
};

}  // namespace slosh::detail
