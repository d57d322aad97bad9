#pragma once
// The nonlinear model (eq. 2.35) integrated exactly as NonlinearResponse does (DOP853 with equal
// steps on every segment, its order-7 dense output) together with its forward sensitivity: every
// step carries the exact derivatives of its state and interpolant with respect to the 7
// durations (the scheme linearised stage by stage, the right-hand side by its partials), so the
// peaks of the accurate response come with exact gradients (internal to the core).

#include <array>
#include <cmath>
#include <vector>

#include "response/nonlinear_scheme.hpp"
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

struct SensitivityPass;

class NonlinearSensitivity {
 public:
  NonlinearSensitivity(const SloshingModel& model, double stroke, double rest_time,
                       const NonlinearOptions& options = {});

  /// Integrates the model for durations d (reusing the buffers of the previous call): segment k
  /// in n_k equal steps h_k = d_k / n_k, n_k its own count (steps of at most the scheme's step)
  /// or, when larger, the frozen count (freeze_steps).
  ///
  /// `until` [s]: the rest window is integrated only up to the end of its step that holds this
  /// time (its step grid unchanged, so every value and gradient up to there is the same to the
  /// last bit); a caller that reads nothing later saves the rest of the window. Default: all.
  ///
  /// `gradients` false: the values alone (a fifth of the work), the same to the last bit as with
  /// the derivatives; window_peak's gradient is then zero and abs_eta_at takes no gradients.
  void compute(const double* d, double until = INFINITY, bool gradients = true);
  /// Whether the last compute() carried the derivatives.
  [[nodiscard]] bool has_gradients() const { return gradients_; }
  /// Whether the last compute() covered the whole rest window.
  [[nodiscard]] bool complete() const { return complete_; }
  /// Integrates the rest window of the last compute() to its end, when compute() stopped it
  /// early: the same steps from the same state at T, so the result is that of compute(d) to the
  /// last bit, without integrating the motion again.
  void complete_rest();
  /// Fixes a least step count per segment, one step more than the durations d take, for every
  /// compute() until the next call. Near d (each d_k shrinking, or growing by up to a step) the
  /// counts then do not change and the discrete response is a smooth function of the
  /// durations: a count that followed d would jump wherever d_k / n_k crosses the largest step,
  /// and the response with it, by its discretisation error, and the solver's model of the
  /// problem (built from exact gradients) would not hold across the jump. Farther away the
  /// counts still follow d, so no step is ever longer than the scheme's. Returns whether the
  /// counts changed.
  bool freeze_steps(const double* d);
  /// Whether a run frozen at `from` (freeze_steps(from)) integrates `at` with more steps than
  /// frozen on some segment: there the counts follow the durations, and the response the run saw
  /// between `from` and `at` is not smooth (a solver may stop at such a jump short of the optimum).
  [[nodiscard]] bool outgrows_frozen_steps(const double* from, const double* at) const;
  /// max |eta(t)| over [t_begin, t_end] of the dense output, found exactly (the roots of the
  /// interpolant's derivative on every step), with the exact gradient at fixed t.
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
  bool frozen_{false};
  double until_{INFINITY};  // the rest window's last needed time of the running compute() [s]
  bool complete_{false};    // the last compute() integrated the whole rest window
  bool gradients_{true};    // the last compute() carried the derivatives
  // The state at the end of the motion of the last compute() (x, v and their derivatives, T
  // and dT), where complete_rest() starts, and the number of motion steps before the rest's.
  double end_x_{}, end_v_{}, end_t_{};
  std::array<double, 8> end_dx_{}, end_dv_{}, end_dt_{};
  std::size_t motion_steps_{};
  std::array<std::size_t, kSegments> steps_{};  // frozen step count per segment
  [[nodiscard]] Dual7 x_at(std::size_t step, double t) const;
  friend struct SensitivityPass;

  // Per step: start and length with their derivatives, and xbar's interpolant (a polynomial in
  // the step fraction) with the derivatives of its coefficients; the derivative rows hold the 7
  // durations and a zero pad (two AVX vectors).
  std::vector<double> tv_, hv_;
  std::vector<DensePoly<double>> xv_;
  std::vector<std::array<double, 8>> dt_, dh_;
  std::vector<std::array<std::array<double, 8>, kDenseTerms>> dx_;
};

}  // namespace slosh::detail
