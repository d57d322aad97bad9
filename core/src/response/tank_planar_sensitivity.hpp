#pragma once
// A rectangular tank's models along a planar path (rectangular_planar.hpp: both directions'
// modes in the tank's frame, linear or nonlinear, the liquid's spin when the tank turns) driven
// by a 7-segment law, integrated by DOP853 in dual numbers over the 7 durations on the smooth
// pieces of path_law_duals.hpp (internal to the core; what time_domain optimises along a path
// for a tank). The model's formulas are RectangularPlanarResponse's (rectangular_planar_model.hpp);
// the liquid's spin w_l' = sqrt(nu max(|theta'|, |w_l|)) / h (theta' - w_l) (planar_spin.hpp) is
// one more coordinate of the same state, its angle integral the position and w_l the rate, so
// its rise at the corners carries exact derivatives too.
//
// The height is the verification's: the highest corner |odd_L| + |odd_W| + |even_L + even_W|
// plus the spin's rise w_l^2 (L^2 + W^2) / (12 g). A sum of absolute values has kinks, so its
// maxima are located as the verification locates them (samples at <= 1 ms and <= 1/64 of the
// fastest modelled period on the dense output, golden-section refinement), and a row at a
// located peak has the gradient at that fixed time (envelope theorem).

#include <array>
#include <cstddef>
#include <limits>
#include <vector>

#include "response/dual8.hpp"
#include "response/nonlinear_scheme.hpp"
#include "response/path_law_duals.hpp"
#include "response/path_sensitivity.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/response/planar_response.hpp"
#include "slosh/core/response/rectangular_planar.hpp"

namespace slosh::detail {

struct TankSensitivityPass;

class TankPlanarSensitivity final : public PathSensitivity {
 public:
  /// `frame_angle`: the world angle of the tank's L axis at the path's start [rad]
  /// (tank_frame_angle); `steps_per_period`: steps per period of the fastest modelled mode (the
  /// step is also at most 50 ms); `options`: the spin model and the liquid's viscosity.
  TankPlanarSensitivity(const RectangularModel& tank, const PlanarPath& path, double frame_angle,
                        double rest_time, RectangularPlanarModel which, double steps_per_period,
                        const PlanarOptions& options = {});

  void compute(const double* d, double until = std::numeric_limits<double>::infinity()) override;
  void freeze_steps(const double* d) override;
  /// The highest corner with the spin's rise at each time, with its gradient.
  void eta_at(const std::vector<double>& t, std::vector<double>& values,
              std::vector<std::array<double, kSegments>>& gradients) const override;
  /// The largest height over [lo, hi], located on the dense output (the file comment).
  [[nodiscard]] double peak_time(double lo, double hi) const override;
  [[nodiscard]] std::vector<PlanarWindowPeak> window_peaks(double t_begin, double t_end,
                                                           double window) const override;
  [[nodiscard]] double motion_time() const override { return motion_time_; }
  /// The highest corner with the spin's rise at t (values only) [m].
  [[nodiscard]] double eta_highest(double t) const;
  /// The fastest modelled mode [rad/s].
  [[nodiscard]] double fastest_omega() const { return fastest_; }

  /// One stored step: the four signals (odd L, even L, odd W, even W) and the spin's angle, as
  /// dual polynomials in the step fraction, and the signals' and the spin rate's values.
  struct Stored {
    D8 t0, h;
    std::array<std::array<D8, kDenseTerms>, 5> poly{};
    std::array<std::array<double, kDenseTerms>, 5> value{};  ///< the spin's rate in row 4
  };

 private:
  friend struct TankSensitivityPass;
  [[nodiscard]] std::size_t step_at(double t) const;

  RectangularModel tank_;
  PlanarPath path_;
  double frame_angle_;
  double rest_time_;
  RectangularPlanarModel which_;
  double h_max_{};
  double steps_per_period_{};
  double fastest_{};
  double peak_step_{};
  double spin_gain_{};  ///< (L^2 + W^2) / (12 g) when the tank turns and spins, else 0 [s^2 m]
  double nu_{};
  double until_{std::numeric_limits<double>::infinity()};
  double motion_time_{};
  PathLawDuals law_;
  FrozenSteps frozen_;
  std::vector<Stored> steps_;
  std::vector<double> t0_values_;
};

}  // namespace slosh::detail
