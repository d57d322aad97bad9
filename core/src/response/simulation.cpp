#include "slosh/core/response/simulation.hpp"

#include "slosh/core/model/modal_truncation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "slosh/core/constants.hpp"
#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/response/rectangular_nonlinear_direction.hpp"
#include "text.hpp"

namespace slosh {

using detail::fixed;
using detail::fixed_above;

namespace {

/// The wall height judged of a wave `eta_motion` during and `eta_rest` after the motion [m]: the
/// larger (a shallow fill rings on after the motion, and its wave there can exceed the one during
/// it), with its sentence naming both when the one after is the larger; nullopt when not finite.
std::optional<std::pair<double, std::string>> judged_height(double eta_motion, double eta_rest) {
  const bool after = std::isfinite(eta_rest) && eta_rest > eta_motion;
  const double eta = after ? eta_rest : eta_motion;
  if (!std::isfinite(eta)) return std::nullopt;
  return std::pair{
      eta,
      "wall height " + fixed(eta * 1e3, 1) + " mm" +
          (after ? " (after the motion; " + fixed(eta_motion * 1e3, 1) + " mm during it)" : "")};
}

/// Where the linear model's own assumption, a wave small against the depth and the tank, fails
/// on a rectangular tank: the highest linear wall or corner height above kLinearMaxDepthShare of
/// the fill height `h` (shallow fill: the wave speed itself depends on the amplitude), or one
/// direction's wave (its walls alone, `directions`) steeper along its own side than the steepest
/// standing wave (Penney & Price 1952: k A = 0.68), which no liquid can carry. A corner adds both
/// directions' waves, but each is a standing wave of its own side and is judged on it. Only the
/// nonlinear model's range was checked before, and outside it the linear model answers: these say
/// that this answer is out of theory too.
std::vector<std::string> beyond_linear_theory(const RectangularTank& t, double h, double eta_motion,
                                              double eta_rest, const DirectionWaves& directions) {
  constexpr double kLinearMaxDepthShare{0.5};
  constexpr double kSteepestStandingWave{0.68};
  std::vector<std::string> w;
  if (const auto highest = judged_height(eta_motion, eta_rest);
      highest && highest->first > kLinearMaxDepthShare * h) {
    w.push_back("linear model beyond its theory: " + highest->second + " is " +
                fixed_above(highest->first / h, kLinearMaxDepthShare) + " of the fill height " +
                fixed(h * 1e3, 1) + " mm (above " + fixed(kLinearMaxDepthShare, 1) +
                "), a wave not small against the depth; the figures are not reliable");
  }
  const struct {
    const char* name;
    double side;
    const SloshPeaks& wave;
  } sides[] = {{"length", t.length, directions.length}, {"width", t.width, directions.width}};
  // Both directions too steep: one sentence names both (as the nonlinear model's range does).
  std::string steep;
  for (const auto& [name, side, wave] : sides) {
    const auto height = judged_height(wave.motion.value, wave.rest.value);
    if (!height) continue;
    const double steepness = rectangular_wavenumber(side, 1) * height->first;
    if (steepness > kSteepestStandingWave) {
      steep += (steep.empty() ? "" : " and ") + std::string("along the ") + name + " " +
               fixed(side * 1e3, 1) + " mm, the " + height->second +
               " is a wave steepness k1 eta = " + fixed_above(steepness, kSteepestStandingWave);
    }
  }
  if (!steep.empty()) {
    w.push_back("linear model beyond its theory: " + steep + ", above the steepest standing wave " +
                fixed(kSteepestStandingWave, 2) +
                " (Penney & Price 1952); the figures are not reliable");
  }
  return w;
}

/// The sentence saying that the deepest of the predicted waves (`linear` and `nonlinear` during
/// the motion, `rest_linear` after it) [m] exceeds the fill height `h` [m]: a trough that deep
/// would uncover the bottom (the wall's crest and the trough are of one size in the models, the
/// surface tilting about the mean level), which both models exclude. nullopt when none does.
std::optional<std::string> wave_deeper_than_fill(double h, double linear, double nonlinear,
                                                 double rest_linear) {
  const double motion = std::max(linear, nonlinear);
  const bool after = std::isfinite(rest_linear) && rest_linear > motion;
  const double eta = after ? rest_linear : motion;
  if (!std::isfinite(eta) || !(eta > h)) return std::nullopt;
  const char* model = after || linear >= nonlinear ? "linear" : "nonlinear";
  return "predicted wave " + fixed(eta * 1e3, 1) + " mm (" + model + " model, " +
         (after ? "after" : "during") + " the motion) is deeper than the fill height " +
         fixed(h * 1e3, 1) +
         " mm: the liquid uncovers the container's bottom, which neither model describes; a "
         "longer motion time or a deeper fill avoids it";
}

/// The spill warning when a predicted eta_motion exceeds the free board [m]: the larger
/// prediction decides, and the sentence says which model gave it and the other's (the linear
/// one alone when the nonlinear figures are the linear model's).
std::optional<std::string> spill_warning(double free_board, double eta_motion_linear,
                                         double eta_motion_nonlinear, bool nonlinear_in_range) {
  const bool linear_larger = eta_motion_linear > eta_motion_nonlinear;
  const double eta = linear_larger ? eta_motion_linear : eta_motion_nonlinear;
  const double other = linear_larger ? eta_motion_nonlinear : eta_motion_linear;
  if (!(eta > free_board)) return std::nullopt;
  const std::string board = " exceeds the free board " + fixed(free_board * 1e3, 1) +
                            " mm (container height - fill height): liquid will spill";
  if (!nonlinear_in_range) {
    return "predicted sloshing height during the motion " + fixed(eta_motion_linear * 1e3, 1) +
           " mm (linear model; the nonlinear model is out of its range)" + board;
  }
  return "predicted sloshing height during the motion " + fixed(eta * 1e3, 1) + " mm (" +
         (linear_larger ? "linear" : "nonlinear") + " model; " +
         (linear_larger ? "nonlinear" : "linear") + " model " + fixed(other * 1e3, 1) + " mm)" +
         board;
}

}  // namespace

std::vector<Warning> validity_warnings(const Format& format, double peak_abs_acceleration,
                                       double eta_motion_linear, double eta_motion_nonlinear,
                                       bool nonlinear_in_range, double eta_rest_linear,
                                       const DirectionWaves* linear_directions) {
  std::vector<Warning> w;
  const double R = format.container.radius;
  const double h = format.fill_height;
  // Beyond the limit by more than round-off (a plateau of exactly 10 m/s^2 computes as 10 + 2e-15).
  if (peak_abs_acceleration > kLinearModelMaxAcceleration * (1.0 + 1e-12)) {
    w.push_back(
        {WarningKind::kLinearModelUnreliable,
         "peak |acceleration| " + fixed(peak_abs_acceleration, 2) + " m/s^2 exceeds " +
             fixed(kLinearModelMaxAcceleration, 0) +
             " m/s^2: the linear model is unreliable at this level (JDSMC 2022 sec. 5, 7); " +
             (nonlinear_in_range ? std::string("rely on the nonlinear prediction")
                                 : std::string("the nonlinear model is out of its range too, "
                                               "so no prediction is reliable"))});
  }
  if (!format.container.rectangular && peak_abs_acceleration > kGravity * h / R) {
    // A steady horizontal acceleration a tilts the free surface to the slope a/g, raising it by
    // R a/g at the wall: beyond g h / R even that quasi-static surface reaches the bottom. Both
    // models assume a liquid over the whole bottom with a small, unbroken surface, so neither
    // describes such a motion (a law that reaches it briefly may still slosh little, but no
    // figure of either model can be promised).
    w.push_back(
        {WarningKind::kModelsOutOfRange,
         "peak horizontal acceleration " + fixed(peak_abs_acceleration, 2) +
             " m/s^2 exceeds g h / R = " + fixed(kGravity * h / R, 2) +
             " m/s^2, where a free surface tilted to the quasi-static slope a/g reaches the "
             "container's bottom: both models are outside what they describe (the liquid "
             "may leave the bottom and the wave break), so neither prediction is reliable"});
  }
  if (format.container.rectangular) {
    // A rectangular tank's shallow fill is judged by its nonlinear model's range
    // (rectangular_nonlinear_peaks); surface tension by half its shorter side.
    const RectangularTank& t = *format.container.rectangular;
    const double half = 0.5 * std::min(t.length, t.width);
    if (half < kMinModelledRadius) {
      w.push_back(
          {WarningKind::kSurfaceTension, "half the shorter side " + fixed(half * 1e3, 1) +
                                             " mm is below " + fixed(kMinModelledRadius * 1e3, 0) +
                                             " mm: surface tension matters and is not modelled"});
    }
    // Without each direction's waves, the corner's bounds both (it is their sum).
    const SloshPeaks corner{{eta_motion_linear, 0.0}, {eta_rest_linear, 0.0}};
    const DirectionWaves bound{corner, corner};
    for (std::string& beyond :
         beyond_linear_theory(t, h, eta_motion_linear, eta_rest_linear,
                              linear_directions != nullptr ? *linear_directions : bound)) {
      w.push_back({WarningKind::kLinearModelBeyondTheory, std::move(beyond)});
    }
  } else if (R < kMinModelledRadius) {
    w.push_back({WarningKind::kSurfaceTension, "radius " + fixed(R * 1e3, 1) + " mm is below " +
                                                   fixed(kMinModelledRadius * 1e3, 0) +
                                                   " mm: surface tension matters and is not "
                                                   "modelled"});
  }
  if (!format.container.rectangular && below_limit(h / R, kMinFillRatio)) {
    w.push_back({WarningKind::kShallowFill,
                 "fill ratio h/R = " + detail::fixed_below(h / R, kMinFillRatio) + " is below " +
                     fixed(kMinFillRatio, 1) + ": shallow-liquid regime, not modelled"});
  }
  if (std::optional<std::string> deeper = wave_deeper_than_fill(
          h, eta_motion_linear, nonlinear_in_range ? eta_motion_nonlinear : 0.0, eta_rest_linear)) {
    w.push_back({WarningKind::kWaveExceedsFill, std::move(*deeper)});
  }
  if (format.container.height) {
    if (std::optional<std::string> spill =
            spill_warning(*format.container.height - h, eta_motion_linear, eta_motion_nonlinear,
                          nonlinear_in_range)) {
      w.push_back({WarningKind::kSpill, std::move(*spill)});
    }
  }
  return w;
}

std::optional<InvalidInput> validate_simulation_input(const Format& f, const MotionLaw& law,
                                                      const SimulationOptions& options) {
  if (f.container.rectangular) {
    const RectangularTank& t = *f.container.rectangular;
    if (auto bad = first_out_of_range({
            {PlanInput::kContainerLength, t.length, positive()},
            {PlanInput::kContainerWidth, t.width, positive()},
            {PlanInput::kContainerOrientation, t.orientation_deg, closed_range(-180.0, 180.0)},
        })) {
      return bad;
    }
  }
  if (auto bad = first_out_of_range({
          {PlanInput::kContainerRadius, f.container.rectangular ? 1.0 : f.container.radius,
           positive()},
          {PlanInput::kContainerHeight, f.container.height.value_or(1.0), positive()},
          {PlanInput::kFillHeight, f.fill_height, positive()},
          {PlanInput::kFluidDensity, f.fluid.density, positive()},
          {PlanInput::kFluidViscosity, f.fluid.viscosity, non_negative()},
          {PlanInput::kStroke, f.stroke, non_negative()},
          {PlanInput::kMotionTime, f.motion_time, positive()},
      })) {
    return bad;
  }
  if (auto model = validate_model_options(options.model)) return model;
  if (law.pieces().empty()) {
    return refused(PlanInput::kLaw, 0.0, positive(), "law has no pieces: nothing to simulate");
  }
  if (const double duration = law.duration(); !positive().contains(duration)) {
    return refused(PlanInput::kLaw, duration, positive(),
                   "law duration = " + detail::sig3(duration) + " s must be finite and > 0 s");
  }
  if (const double stroke = law.stroke(); !std::isfinite(stroke)) {
    return refused(PlanInput::kLaw, stroke, {},
                   "law stroke = " + detail::sig3(stroke) + " m must be finite");
  }
  if (!non_negative().contains(options.rest_time)) {
    return out_of_range(PlanInput::kRestTime, -1, options.rest_time, non_negative());
  }
  if (options.sample_period && !positive().contains(*options.sample_period)) {
    return out_of_range(PlanInput::kSamplePeriod, -1, *options.sample_period, positive());
  }
  return std::nullopt;
}

namespace {

/// The series sampled at options.sample_period over the motion and the rest window.
template <class Linear, class Nonlinear>
TimeSeries sampled_series(const MotionLaw& law, const SimulationOptions& options,
                          const Linear& eta_linear, const Nonlinear& eta_nonlinear) {
  const double dt = *options.sample_period;
  const double end = law.duration() + options.rest_time;
  const auto n = static_cast<std::size_t>(std::floor(end / dt + 1e-9));
  TimeSeries s;
  for (std::size_t i = 0; i <= n; ++i) {
    const double t = std::min(end, dt * static_cast<double>(i));
    const KinematicState k = law.at(t);
    s.t.push_back(t);
    s.a.push_back(k.acceleration);
    s.v.push_back(k.velocity);
    s.s.push_back(k.position);
    s.eta_linear.push_back(eta_linear(t));
    s.eta_nonlinear.push_back(eta_nonlinear(t));
  }
  return s;
}

/// The wave height series of a rectangular tank: signed at the wall ahead when one direction
/// moves, else the highest corner (highest_corner, the measure of the peaks, so that the
/// series' maximum is the peak); the nonlinear one by each direction's nonlinear response
/// (RectangularNonlinearDirection), or the linear model's where the nonlinear model does not
/// hold (`nonlinear_holds` false).
struct RectangularSeries {
  RectangularLinearResponse linear;
  std::vector<RectangularNonlinearDirection> nonlinear;
  bool nonlinear_holds{true};

  [[nodiscard]] double eta_linear(double t) const {
    const double l = linear.eta_length(t), w = linear.eta_width(t);
    return l == 0.0 || w == 0.0 ? l + w : std::abs(l) + std::abs(w);
  }
  [[nodiscard]] double eta_nonlinear(double t) const {
    if (!nonlinear_holds) return eta_linear(t);
    if (nonlinear.size() == 1) return nonlinear[0].eta_odd(t) + nonlinear[0].eta_even(t);
    // The measure the peaks take (rectangular_nonlinear_peaks): the series' maximum is the peak.
    return highest_corner(nonlinear[0].eta_odd(t), nonlinear[0].eta_even(t),
                          nonlinear[1].eta_odd(t), nonlinear[1].eta_even(t));
  }
};

/// Fills `r` for a rectangular tank; the linear waves of each direction alone.
DirectionWaves simulate_rectangular(const Format& format, const MotionLaw& law,
                                    const SimulationOptions& options, SimulationResult& r) {
  r.rectangular = rectangular_model_of(format, options.model);
  const RectangularModel& m = *r.rectangular;
  const RectangularNonlinearPeaks nonlinear =
      rectangular_nonlinear_peaks(m, law, options.rest_time, options.nonlinear);
  RectangularSeries series{
      RectangularLinearResponse(m, law, options.rest_time), {}, nonlinear.nonlinear};
  const RectangularPeaks linear = series.linear.peaks();
  r.linear = linear.highest;
  r.nonlinear = nonlinear.peaks.highest;
  r.rectangular_peaks = nonlinear.peaks;
  if (!nonlinear.warning.empty()) {
    r.warnings.push_back({WarningKind::kNonlinearModelNotValid, nonlinear.warning});
  }
  if (!options.sample_period) return {linear.along_length, linear.along_width};
  if (series.nonlinear_holds) {
    for (const DrivenDirection& d : driven_directions(m)) {
      const SloshingModel& own = d.axis == TankAxis::kLength ? m.along_length : m.along_width;
      series.nonlinear.emplace_back(own, law.scaled(d.component), options.rest_time,
                                    options.nonlinear);
    }
  }
  r.series = sampled_series(
      law, options, [&series](double t) { return series.eta_linear(t); },
      [&series](double t) { return series.eta_nonlinear(t); });
  return {linear.along_length, linear.along_width};
}

}  // namespace

SimulationResult simulate(const Format& format, const MotionLaw& law,
                          const SimulationOptions& options) {
  SimulationResult r;
  if (std::optional<InvalidInput> invalid = validate_simulation_input(format, law, options)) {
    r.invalid_input = std::move(invalid);
    return r;
  }
  r.model = make_sloshing_model(format, options.model);
  r.kinematics = law.summary();
  std::optional<DirectionWaves> directions;
  if (format.container.rectangular) {
    directions = simulate_rectangular(format, law, options, r);
  } else {
    const LinearResponse linear(r.model, law, options.rest_time);
    const NonlinearResponse nonlinear(r.model, law, options.rest_time, options.nonlinear);
    r.linear = linear.peaks();
    r.nonlinear = nonlinear.peaks();
    if (options.sample_period) {
      r.series = sampled_series(
          law, options, [&linear](double t) { return linear.eta(t); },
          [&nonlinear](double t) { return nonlinear.eta(t); });
    }
  }
  // So far r.warnings holds only the rectangular nonlinear model's out-of-range reason.
  const bool nonlinear_in_range = r.warnings.empty();
  std::vector<Warning> warnings = validity_warnings(
      format, std::max(r.kinematics.a_peak_positive, r.kinematics.a_peak_negative),
      r.linear.motion.value, r.nonlinear.motion.value, nonlinear_in_range, r.linear.rest.value,
      directions ? &*directions : nullptr);
  warnings.insert(warnings.end(), r.warnings.begin(), r.warnings.end());
  if (format.container.rectangular && r.rectangular) {
    for (Warning& t : modal_truncation_warnings(*format.container.rectangular, format.fill_height,
                                                *r.rectangular, law, options.rest_time)) {
      warnings.push_back(std::move(t));
    }
  }
  r.warnings = std::move(warnings);
  return r;
}

}  // namespace slosh
