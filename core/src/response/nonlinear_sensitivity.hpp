#pragma once
// The nonlinear model (eq. 2.35) integrated exactly as NonlinearResponse does (RK4 on the
// breakpoint-aligned grid, cubic Hermite dense output) but in dual numbers: every node carries its
// exact derivatives with respect to the 7 durations, so the peaks of the accurate response come
// with exact gradients (automatic differentiation through the integrator; internal to the core).

#include <array>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/response.hpp"
#include "solve/dual.hpp"

namespace slosh::detail {

/// Largest |eta| of the dense response over a time window, with its gradient.
struct WindowPeak {
  double value{};                          ///< max |eta| [m]
  double time{};                           ///< where [s]
  std::array<double, kSegments> gradient;  ///< d value / d dT_i [m/s]
};

class NonlinearSensitivity {
 public:
  NonlinearSensitivity(const SloshingModel& model, double stroke, double rest_time,
                       const NonlinearOptions& options = {});

  /// Integrates the model for durations d (reusing the buffers of the previous call).
  void compute(const double* d);
  /// max |eta(t)| over [t_begin, t_end] of the Hermite dense output, found exactly (the roots of
  /// the cubic's derivative on every interval), with the exact gradient at fixed t.
  [[nodiscard]] WindowPeak window_peak(double t_begin, double t_end) const;
  /// |eta(t)| of the dense output at each of the sorted times `t`, with its exact gradient at
  /// fixed t (row k of `gradients` holds d|eta(t_k)|/d dT_i).
  void abs_eta_at(const std::vector<double>& t, std::vector<double>* values,
                  std::vector<std::array<double, kSegments>>* gradients) const;
  /// Motion time of the last compute() [s].
  [[nodiscard]] double motion_time() const { return motion_time_; }

 private:
  SloshingModel model_;
  double stroke_;
  double rest_time_;
  double h_max_;
  double motion_time_{};
  std::vector<double> tv_;        // node times (values) for the search
  std::vector<Dual7> t_, x_, v_;  // node times, xbar, xbar' with derivatives
};

}  // namespace slosh::detail
