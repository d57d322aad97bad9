#pragma once
// What the planner verifies a rectangular tank's law by (SPEC §15): the tank's own responses
// (RectangularLinearResponse and the rectangular nonlinear model, the highest wall or corner),
// not the driven direction models the strategies optimise on.

#include <functional>
#include <optional>
#include <string>
#include <utility>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/strategy/robustness.hpp"

namespace slosh {

/// A law's peaks on a rectangular tank.
struct RectangularPrediction {
  SloshPeaks linear;     ///< the highest wall or corner of the linear model [m]
  SloshPeaks nonlinear;  ///< of the nonlinear model, or the linear one outside its range [m]
  SloshPeaks length;     ///< the walls normal to L alone, nonlinear (or linear) model [m]
  SloshPeaks width;      ///< the walls normal to W alone [m]
  DirectionWaves linear_directions;  ///< each direction's walls alone, linear model [m]
  /// Empty, or why the linear model answers for the nonlinear one (rectangular_nonlinear_peaks).
  std::string warning;
};

[[nodiscard]] RectangularPrediction rectangular_prediction(const RectangularModel& model,
                                                           const MotionLaw& law, double rest_time);

/// The share of the uniform law's eta_rest (linear model) from which a motion is too short for
/// the tank (motion_too_short_for_mode) [-]: every law of the duration that moves one way leaves
/// at least this share, so a plan can reduce the wave by a tenth at most. A short motion time
/// alone does not decide it: on a long shallow tank the higher modes, n omega_1 apart, are not
/// impulses yet and carry much of the uniform law's wave, which a law can reduce (4 m tank
/// filled 50 mm, 1 s: 0.09 of the first period, and time_domain halves the wave).
inline constexpr double kMotionTooShortShare{0.9};

/// A floor of the linear eta_rest (the highest wall or corner over the rest window of
/// `rest_time` [s]) that every law of `motion_time` [s] moving `stroke` [m] one way (velocity
/// >= 0) leaves on the tank [m]: the wall heights are the velocity convolved with the step
/// responses, so at any time of the rest window they are at least the stroke times the least
/// step response over the last motion time (each direction's, and both summed with either
/// sign for a corner). 0 when the motion lasts half the slowest first period or more (a law
/// can then cancel a first mode) or a mode is not underdamped.
[[nodiscard]] double one_way_rest_floor(const RectangularModel& model, double stroke,
                                        double motion_time, double rest_time);

/// Empty, or the sentence saying that the move of `stroke` [m] in `motion_time` [s] is an impulse
/// to the tank's modes: one_way_rest_floor reaches kMotionTooShortShare of the uniform law's
/// linear eta_rest `uniform_rest` [m] over the same rest window. It names the motion time's
/// share of the slowest excited direction's first period and the floor's share of the uniform
/// law's eta_rest, rounded down.
[[nodiscard]] std::string motion_too_short_for_mode(const RectangularModel& model, double stroke,
                                                    double motion_time, double rest_time,
                                                    double uniform_rest);

/// A direction whose static wall height is below this share of the other's is left out of what
/// the strategies optimise (rectangular_axis_tank) [-]: its waves move the tank's peaks by less
/// than that share, below the 1e-7 to which time_domain meets its bounds, and a tank turned a
/// hair off an axis (89.9999999 degrees from a PLC's float) must plan as on the axis, where the
/// optimisers, whose local searches can turn on the last digits of their data, would otherwise
/// see a different problem.
inline constexpr double kNegligibleDirectionShare{1e-8};

/// The share of the residual wave (the second direction's first-mode wave per unit spectrum over
/// the most excited one's) from which fir_chain, iir, the shaper and min_jerk_band design for
/// both directions in full [-]. Below it the second direction enters their designs by its
/// engagement, share / kFullDirectionShare: its first mode then leaves, per unit spectrum at its
/// frequency, under a thousandth of the wave the first direction's leaves at its own, below the
/// linear model's accuracy and any measured fill, so a partial design costs nothing that
/// matters, and every design moves continuously from the one-direction design on the axis
/// (share 0) to the two-direction one.
inline constexpr double kFullDirectionShare{1e-3};

/// How far the second direction of a turned tank enters the filters' and min_jerk_band's
/// designs: min(1, share / kFullDirectionShare) [-], 0 on an axis.
[[nodiscard]] double direction_engagement(double share);

/// The tank turned onto its nearest axis (orientation a multiple of 90 degrees) when the motion
/// drives a direction below kNegligibleDirectionShare of the other's static wall height; nullopt
/// otherwise (the tank on an axis already, or both directions driven). The planner's strategies
/// see this tank; the plan's figures stay those of the tank itself.
[[nodiscard]] std::optional<RectangularModel> rectangular_axis_tank(const RectangularModel& model);

/// True when the motion drives both of the tank's directions (orientation not a multiple of 90
/// degrees).
[[nodiscard]] bool both_directions_excited(double orientation_deg);

/// The sweep of SPEC §10 on the tank: every frequency of both directions scaled by (1 + delta);
/// each direction keeps its own damping ratio unless `sweep.zeta` differs from the most excited
/// direction's (an uncertainty range's least damping), which then holds for both. `at_zero` as
/// in robustness_report. `out_of_time`, when given, is asked before each point's simulation: a
/// tank whose period is tiny against a long motion makes every point costly, and a plan's budget
/// covers its report; nullopt when it said true (the report left unfinished).
[[nodiscard]] std::optional<RobustnessReport> rectangular_robustness_report(
    const RectangularModel& model, const MotionLaw& law, const RobustnessSweep& sweep,
    const std::optional<std::pair<SloshPeaks, SloshPeaks>>& at_zero = std::nullopt,
    const std::function<bool()>& out_of_time = {});

}  // namespace slosh
