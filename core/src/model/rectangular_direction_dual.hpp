#pragma once
// One direction of a rectangular tank as simulate models it (RectangularNonlinearDirection, or
// RectangularLinearResponse where the nonlinear model does not hold), integrated in dual numbers
// over the direction's omega_scale and zeta so that its wall elevations come with exact
// parameter gradients (forward-mode automatic differentiation through the integrators; internal
// to the core):
// - the dominant mode: eq. 2.35 with C = 0 (the third-order oscillator; alpha = 0 in the linear
//   model) by DOP853 on NonlinearResponse's grid with its dense output;
// - the higher antisymmetric modes n >= 2: the linear oscillators of LinearResponse, each by
//   DOP853 on the grid of its own period (LinearResponse's closed form to the integrator's
//   accuracy, ~1e-10 of the wave);
// - the second (even) mode driven by the dominant one: RectangularNonlinearDirection's RK4 on its
//   grid with its cubic Hermite dense output (nonlinear model only).

#include <array>
#include <vector>

#include "response/nonlinear_scheme.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/response.hpp"
#include "solve/dual.hpp"

namespace slosh::detail {

/// Derivative directions: the direction's omega_scale (0) and zeta (1).
using Dual2 = Dual<2>;

/// A wall elevation with its gradient over (omega_scale, zeta) and its rate in time.
struct DirectionSample {
  double value{};                    ///< [m]
  std::array<double, 2> gradient{};  ///< [m]
  double rate{};                     ///< d value / dt [m/s] (a series offset's derivative)
};

class RectangularDirectionDual {
 public:
  /// `base`: the direction's model (make_rectangular_direction_model) with omega_scale and
  /// height_gain 1 (its zeta is replaced by compute's); `law`: the acceleration along the
  /// direction (the motion's law scaled by its component); `nonlinear`: simulate's nonlinear
  /// model (true) or its linear one (false).
  RectangularDirectionDual(SloshingModel base, MotionLaw law, double rest_time,
                           const NonlinearOptions& options, bool nonlinear);

  /// Integrates the direction for these parameters.
  void compute(double omega_scale, double zeta);

  /// Every antisymmetric mode at the wall x = +side/2 (eta_odd) [m], height gain 1.
  [[nodiscard]] DirectionSample odd(double t) const;
  /// The second mode at either wall (eta_even) [m], height gain 1; 0 in the linear model.
  [[nodiscard]] DirectionSample even(double t) const;
  /// The peak search's sampling step of simulate for this direction [s].
  [[nodiscard]] double peak_step() const { return peak_step_; }

  /// One oscillator's trajectory: step starts and lengths, state over each step in theta.
  struct Trajectory {
    std::vector<double> t0, h;
    std::vector<DensePoly<Dual2>> x, v;
    double gain{};  ///< wall elevation per unit of the state [-] (K, or G_n)
  };

 private:
  struct State {
    Dual2 x, v;
  };
  [[nodiscard]] static State state_at(const Trajectory& tr, double t);
  void integrate_second_mode(const Dual2& w, const Dual2& zeta, double scale);

  SloshingModel base_;
  MotionLaw law_;
  double rest_time_;
  NonlinearOptions options_;
  bool nonlinear_;
  std::vector<Trajectory> modes_;  // the dominant mode (in xbar), then the higher ones (in x_n)
  std::vector<double> t2_;         // the second mode's RK4 nodes
  std::vector<Dual2> b_, b_dot_;
  double peak_step_{};
};

}  // namespace slosh::detail
