#pragma once
// Sloshing responses to a motion law: the exact multi-mode linear model and the nonlinear
// fundamental-mode model (thesis eq. 2.22/2.24 and 2.35/2.36; SPEC §2). Both start at rest, run
// over the motion window [0, T] and the rest window (T, T + rest_time].

#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/peak_finder.hpp"

namespace slosh {

/// Peak wall heights of a response.
struct SloshPeaks {
  Peak motion;  ///< max |eta| on [0, T]: value [m], time [s]
  Peak rest;    ///< max |eta| on (T, T + rest_time]: value [m], time [s]
};

/// A rectangular tank's wall heights of each direction alone [m]: the walls normal to L (the
/// modes along L) and those normal to W, during and after the motion.
struct DirectionWaves {
  SloshPeaks length;
  SloshPeaks width;
};

/// State of one mode.
struct ModeState {
  double x{};      ///< displacement [m] (linear) or xbar [-] (nonlinear)
  double x_dot{};  ///< its rate
};

/// Closed-form response of one linear mode on one law piece, tau = t - t_begin:
/// x = sum r_k tau^k + P cos(W tau) + Q sin(W tau) + tau (U cos(W tau) + V sin(W tau))
///   + exp(-sigma tau) (c1 cos(wd tau) + c2 sin(wd tau)).
/// U, V are only non-zero for an undamped mode forced exactly at its natural frequency.
struct LinearModePiece {
  std::array<double, 4> r{};
  double P{}, Q{}, U{}, V{}, W{};
  double c1{}, c2{};
  /// sigma = zeta w; wd = w sqrt(1 - zeta^2) under-damped, w sqrt(zeta^2 - 1) over-damped, 1
  /// critically damped (the homogeneous part is then exp(-sigma tau) (c1 cosh + c2 sinh), resp.
  /// exp(-sigma tau) (c1 + c2 tau)).
  double sigma{}, wd{};
  double slow{};  ///< over-damped: the slow decay rate sigma - wd
  enum class Damping : unsigned char { kUnder, kCritical, kOver } damping{Damping::kUnder};
  [[nodiscard]] ModeState at(double tau) const;
  /// x alone (the peak search's hot path).
  [[nodiscard]] double position(double tau) const;
};

/// Linear model solved exactly: on every law piece the forcing -a(t) is a cubic plus one harmonic,
/// so each mode's response is a particular solution plus the damped homogeneous one, in closed
/// form (no time stepping). The response is continuous and can be evaluated at any t.
class LinearResponse {
 public:
  LinearResponse(const SloshingModel& model, const MotionLaw& law, double rest_time);

  /// Wall sloshing height eta(t) = sum_n eta_gain_n x_n(t) [m].
  [[nodiscard]] double eta(double t) const;
  /// State of mode n (0-based) at t.
  [[nodiscard]] ModeState mode_state(int mode, double t) const;
  /// Peaks of |eta| located on the continuous response (samples at <= 1 ms and <= 1/64 of the
  /// fastest period, each candidate refined by golden section to 1e-10 s).
  [[nodiscard]] SloshPeaks peaks() const;
  /// peaks() of every response, equal to it bit for bit; responses on the same sample grid (the
  /// robustness report's sweep of one law) are scanned side by side, a few per vector.
  [[nodiscard]] static std::vector<SloshPeaks> peaks_of(
      const std::vector<LinearResponse>& responses);
  [[nodiscard]] double motion_time() const { return motion_time_; }
  [[nodiscard]] double end_time() const { return end_time_; }

  /// The response gain_a eta_a(t) + gain_b eta_b(t) of two responses over the same pieces and
  /// rest window (laws that differ by a scale), as one response with both's modes side by side
  /// (at most 2 kMaxModes), so that peaks() scans the sum exactly (rectangular_linear.cpp).
  /// Throws std::invalid_argument when the pieces differ.
  [[nodiscard]] static LinearResponse combined(const LinearResponse& a, double gain_a,
                                               const LinearResponse& b, double gain_b);

 private:
  [[nodiscard]] std::size_t piece_index(double t) const;  // piece holding t > 0

  std::vector<double> gains_;
  std::vector<double> piece_begin_;            // start time of every piece (law pieces + rest)
  std::vector<LinearModePiece> coefficients_;  // [piece * modes + mode]
  double motion_time_{};
  double end_time_{};
  double peak_step_{};
};

/// Options of the nonlinear integration.
struct NonlinearOptions {
  /// Largest step [s]. The actual step is min(max_step, period_1 / steps_per_period) (and at most
  /// 1/steps_per_period of the period of a piece's harmonic), shrunk so that every law piece is
  /// a whole number of steps. Default 50 ms (the period bound governs).
  double max_step{0.05};
  /// Minimum steps per period of mode 1 [-]. Default 40 (order-8 scheme: the error on eta stays
  /// below 1e-6 of the peak even on harsh laws far into the nonlinear range, docs/models.md).
  double steps_per_period{40.0};
};

/// Nonlinear fundamental-mode model (eq. 2.35) integrated by the order-8 Runge-Kutta scheme of
/// Dormand and Prince (DOP853) with equal steps on every law piece (never across a piece
/// boundary); between steps the response is the scheme's order-7 dense output, so the peaks are
/// the exact maxima of a continuous curve (the roots of its derivative on every step).
///
/// The constructor integrates as far as the peaks need (the rest window up to where the energy
/// bound proves its maximum found); the rest of the rest window is integrated on the first call
/// of eta(), state() or steps(), once (thread-safe; copies share the trajectory).
class NonlinearResponse {
 public:
  NonlinearResponse(const SloshingModel& model, const MotionLaw& law, double rest_time,
                    const NonlinearOptions& options = {});

  /// eta(t) = K xbar(t) [m], for 0 <= t <= end of the rest window (the state is held beyond).
  [[nodiscard]] double eta(double t) const;
  /// xbar and its rate at t (held at the last computed state beyond the rest window).
  [[nodiscard]] ModeState state(double t) const;
  /// The peaks (found while integrating; the rest window's search ends by the energy bound of
  /// docs/models.md, which proves no later maximum can exceed the one found).
  [[nodiscard]] SloshPeaks peaks() const { return peaks_; }
  /// Steps of the whole trajectory (motion and rest window).
  [[nodiscard]] std::size_t steps() const;
  [[nodiscard]] double motion_time() const { return motion_time_; }

  /// Power-basis coefficients of a step's interpolant in theta = (t - t0) / h [-].
  using StepPoly = std::array<double, 8>;

  /// The stored steps and where the rest window's integration resumes (nonlinear_response.cpp).
  struct Trajectory;

 private:
  [[nodiscard]] const Trajectory& trajectory() const;  // completed on first use

  std::shared_ptr<Trajectory> trajectory_;
  SloshPeaks peaks_;
  double K_{};
  double motion_time_{};
};

/// The peaks of NonlinearResponse(model, law, rest_time, options).peaks(), equal to them bit for
/// bit, without keeping the trajectory: the integration stops where the energy bound proves
/// the rest window's maximum found (about half a period after the first turning point after T).
[[nodiscard]] SloshPeaks nonlinear_peaks(const SloshingModel& model, const MotionLaw& law,
                                         double rest_time, const NonlinearOptions& options = {});

/// nonlinear_peaks(models[i], law, rest_time, options) for every i, equal to it bit for bit,
/// computed side by side (a few models a vector: the robustness report's frequency sweep).
[[nodiscard]] std::vector<SloshPeaks> nonlinear_peaks(const std::vector<SloshingModel>& models,
                                                      const MotionLaw& law, double rest_time,
                                                      const NonlinearOptions& options = {});

/// Steps for a stretch of length L with steps <= h_max: ceil(L / h_max), ignoring a
/// round-off excess of 1e-9 step (0.17 s / 1 ms is 170.00000000000003), at least `at_least`.
[[nodiscard]] inline std::size_t step_count(double length, double h_max, std::size_t at_least = 0) {
  // A length that is not positive (or NaN) takes no step: converting a negative count to size_t
  // would ask for ~2^64 steps.
  if (!(length > 0.0)) return at_least;
  const auto n = static_cast<std::size_t>(std::ceil(length / h_max - 1e-9));
  return n < at_least ? at_least : n;
}

/// Right-hand side of eq. 2.35 solved for xbar'' given xbar, xbar' and the container
/// acceleration a [m/s^2].
[[nodiscard]] double nonlinear_acceleration(const SloshingModel& model, double x, double v,
                                            double a);

}  // namespace slosh
