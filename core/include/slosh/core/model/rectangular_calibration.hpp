#pragma once
// Calibration of a rectangular tank (SPEC §15) from moves that drive one or both of its
// directions: the frequency scale and damping ratio of each direction the moves drive, and one
// height gain (and each series' time offset where asked), fitted by bounded least squares with
// exact gradients. The model fitted is simulate's (every linear mode, the dominant mode's
// third-order oscillator and the second mode it drives; its linear model where the nonlinear
// one does not hold), integrated in dual numbers over each direction's scale and damping
// (model/rectangular_direction_dual.hpp).

#include <array>
#include <string>
#include <vector>

#include "slosh/core/model/calibration.hpp"
#include "slosh/core/model/format.hpp"

namespace slosh {

/// One measured move of a rectangular tank at its own orientation.
struct RectangularMeasuredMove {
  /// Its law and what was measured: a series or peaks of simulate's wave height (the signed
  /// wall ahead when one direction moves, the highest corner |eta_L| + |eta_W| when both do).
  /// A series' offset is estimated when it says fit_offset, as calibrate() does.
  MeasuredMove move;
  /// Angle from the motion to the tank's side L [deg], as RectangularTank::orientation_deg.
  double orientation_deg{};
};

/// One direction's fitted frequency scale and damping ratio.
struct DirectionCalibration {
  /// Whether some move drives this direction. When none does, its parameters stay at their
  /// priors with state kFixed, and the result's notes say that the direction is unmeasured.
  bool measured{false};
  FittedParameter omega_scale;  ///< scale of the direction's natural frequencies [-]
  FittedParameter zeta;         ///< damping ratio of the direction's modes [-]
};

struct RectangularCalibrationResult {
  CalibrationStatus status{CalibrationStatus::kFailed};
  DirectionCalibration length;  ///< the modes along L
  DirectionCalibration width;   ///< the modes along W
  FittedParameter height_gain;  ///< gain on the predicted wall heights of both directions [-]
  std::vector<MoveFit> moves;
  double sigma{};    ///< residual standard deviation [m]
  int iterations{};  ///< LM steps over all refits
  /// A direction left unmeasured, a parameter held at its prior (which one, why), each a sentence.
  std::vector<std::string> notes;
  /// Non-empty when the moves drive both directions but cannot tell their parameters apart: the
  /// sentence says which and which moves would; status is then kFailed and every value is its
  /// prior.
  std::string refused;
};

/// Fits the tank of `format` (its container rectangular; its orientation unused, each move
/// carries its own) to `moves` (at least one, validated as for calibrate()). The parameters are
/// those of `settings`: omega_scale's and zeta's setting (fit, initial, bounds) hold for each
/// direction, height_gain's for the one gain; zeta's prior is each direction's own boundary-layer
/// damping unless an initial value is given; alpha is each direction's theory value, held (the
/// Duffing coefficient follows from the depth, docs/models.md).
[[nodiscard]] RectangularCalibrationResult calibrate_rectangular(
    const Format& format, const ModelOptions& base,
    const std::vector<RectangularMeasuredMove>& moves, const CalibrationSettings& settings);

/// The fit's parameters in the order of rectangular_calibration_residuals: the length's
/// omega_scale and zeta, the width's omega_scale and zeta, height_gain.
using RectangularCalibrationValues = std::array<double, 5>;

/// The fit's residuals at `p` with each move's series starting at `offsets[i]` on its clock
/// (simulate's wave height minus the measured one: every series sample, then the motion and rest
/// peaks, move by move) and, when `jacobian` is given, their exact derivatives (one row per
/// residual; columns: the 5 values of `p`, then one per move whose series fits its offset, in
/// move order). For tests and diagnostics.
void rectangular_calibration_residuals(const Format& format, const ModelOptions& base,
                                       const std::vector<RectangularMeasuredMove>& moves,
                                       const RectangularCalibrationValues& p,
                                       const std::vector<double>& offsets,
                                       const NonlinearOptions& nonlinear,
                                       std::vector<double>* residuals,
                                       std::vector<std::vector<double>>* jacobian);

}  // namespace slosh
