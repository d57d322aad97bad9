#pragma once
// What time_domain along a path optimises on (internal to the core): a model's response to a
// 7-segment law along the path, integrated in dual numbers over the 7 durations, with the wall
// height (or the highest corner) at any time and its exact gradient. PlanarSensitivity is the
// cylinder's planar nonlinear model, TankPlanarSensitivity a rectangular tank's models.

#include <array>
#include <limits>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"

namespace slosh::detail {

/// A local maximum of the wall height over a window of the response.
struct PlanarWindowPeak {
  double value{};  ///< [m]
  double time{};   ///< [s]
};

class PathSensitivity {
 public:
  virtual ~PathSensitivity() = default;
  /// Integrates the model for the durations d over the motion and the rest window, or only as far
  /// as the step that reaches `until` [s] (the same steps as the whole window's, so the response
  /// up to there is the same to the last bit; times later than that are not to be read).
  virtual void compute(const double* d, double until = std::numeric_limits<double>::infinity()) = 0;
  /// Fixes the least step count of every smooth piece at one more than d takes, for every
  /// compute() until the next call while the pieces keep their order (so the discrete response
  /// stays smooth in the durations during a solver's run).
  virtual void freeze_steps(const double* d) = 0;
  /// The height at each time of `t` (any order) with its gradient over the durations.
  virtual void eta_at(const std::vector<double>& t, std::vector<double>& values,
                      std::vector<std::array<double, kSegments>>& gradients) const = 0;
  /// The time of the largest height over [lo, hi] (any two times inside the response). A row
  /// bounded there follows its peak as the durations move, and its value (continuous in the
  /// durations) has the gradient at fixed time (envelope theorem).
  [[nodiscard]] virtual double peak_time(double lo, double hi) const = 0;
  /// The largest height in every window of `window` seconds over [t_begin, t_end].
  [[nodiscard]] virtual std::vector<PlanarWindowPeak> window_peaks(double t_begin, double t_end,
                                                                   double window) const = 0;
  [[nodiscard]] virtual double motion_time() const = 0;
};

}  // namespace slosh::detail
