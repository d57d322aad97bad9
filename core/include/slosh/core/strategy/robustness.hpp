#pragma once
// How a law's sloshing changes when the tank's frequencies are not the model's (SPEC §10): the
// law re-simulated with every mode frequency scaled by (1 + delta) on both models (exact linear
// response, accurate nonlinear one), and the interval of delta around 0 where the limits hold.

#include <functional>
#include <optional>
#include <vector>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh {

/// Default half width of the sweep of a plan without uncertainty [-] (+-10 %).
inline constexpr double kDefaultRobustnessSweep{0.10};
/// Points of the sweep, both ends included [-].
inline constexpr int kRobustnessPoints{21};
/// Relative excess over a limit that still counts as met (the verification's round-off) [-].
inline constexpr double kRobustnessSlack{1e-6};

/// What robustness_report sweeps and judges.
struct RobustnessSweep {
  double delta_lo{-kDefaultRobustnessSweep};  ///< first delta [-], <= 0
  double delta_hi{kDefaultRobustnessSweep};   ///< last delta [-], >= 0
  int points{kRobustnessPoints};              ///< evenly from delta_lo to delta_hi, >= 2
  double zeta{};                              ///< damping ratio at every point [-]
  double rest_time{kDefaultRestTime};         ///< rest window [s]
  double eta_rest_max{};                      ///< limit on eta_rest [m]
  std::optional<double> eta_motion_max;       ///< limit on eta_motion when given [m]
};

/// One point of the sweep.
struct RobustnessPoint {
  double delta{};  ///< every mode frequency is omega_n (1 + delta) [-]
  SloshPeaks linear;
  SloshPeaks nonlinear;
  bool holds_linear{false};     ///< the limits hold on the linear model
  bool holds_nonlinear{false};  ///< the limits hold on the nonlinear model
};

/// The interval of delta around 0 over which the limits hold [-].
struct DeltaInterval {
  /// Ends [-]: where the margin (the largest eta / limit, minus 1) crosses 0, linearly
  /// interpolated between the last point that holds and the first that does not; a sweep end
  /// when every point up to it holds.
  double lo{};
  double hi{};
  bool lo_is_sweep_end{false};  ///< lo is the sweep's first delta: the interval may extend
  bool hi_is_sweep_end{false};  ///< hi is the sweep's last delta
};

struct RobustnessReport {
  RobustnessSweep sweep;
  /// Sorted by delta: the evenly spaced points, plus delta = 0 when the grid misses it.
  std::vector<RobustnessPoint> points;
  /// Where the limits hold around delta = 0; nullopt when they do not hold at 0.
  std::optional<DeltaInterval> linear;
  std::optional<DeltaInterval> nonlinear;
  /// Each model's largest eta_motion and eta_rest over the sweep, with the time of each in its
  /// point's response [m, s]; a NaN value when the model diverged at some point.
  SloshPeaks worst_linear;
  SloshPeaks worst_nonlinear;
};

/// The deltas a sweep evaluates, sorted: `points` evenly from delta_lo to delta_hi (a symmetric
/// sweep hits 0 exactly), plus 0 when the grid misses it [-].
[[nodiscard]] std::vector<double> robustness_deltas(const RobustnessSweep& sweep);

/// The sweep of `law` on `nominal` (every frequency of it scaled, zeta = sweep.zeta). When
/// `at_zero` is given it is taken as the peaks at delta = 0 with the nominal zeta (the plan's own
/// verified prediction) instead of simulating them again.
[[nodiscard]] RobustnessReport robustness_report(
    const SloshingModel& nominal, const MotionLaw& law, const RobustnessSweep& sweep,
    const std::optional<std::pair<SloshPeaks, SloshPeaks>>& at_zero = std::nullopt);

/// robustness_report of `law` moved along `path` (SPEC §14): every point's peaks from the planar
/// models (planar_linear_peaks, planar_nonlinear_peaks), the wave maximised over the wall.
/// `out_of_time` (optional) is asked before each point: nullopt once it says so (each point
/// verifies the law along the whole path again).
[[nodiscard]] std::optional<RobustnessReport> robustness_report_on_path(
    const SloshingModel& nominal, const PlanarPath& path, const MotionLaw& law,
    const RobustnessSweep& sweep, const std::function<bool()>& out_of_time = {});

/// The report of a sweep whose points are simulated already (sorted by delta, one at delta = 0,
/// each with its peaks): each point judged by the sweep's limits, the holding intervals and the
/// worst cases (robustness_report's judgement, for models it does not sweep itself).
[[nodiscard]] RobustnessReport judged_report(const RobustnessSweep& sweep,
                                             std::vector<RobustnessPoint> points);

}  // namespace slosh
