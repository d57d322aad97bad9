#pragma once
// Where the nonlinear model of a rectangular tank holds (SPEC §15, docs/models.md "Nonlinear
// model of a rectangular tank"): a pure check that a plan calls to decide between the nonlinear
// answer and the linear one with a warning, never a silent extrapolation.

#include <string>

#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/response/rectangular_response.hpp"

namespace slosh {

/// Critical depth ratio h / side of the third-order theory: the frequency correction c of
/// rectangular_frequency_correction vanishes at k_1 h = 1.05809, h / side = 0.33680 (Tadjbakhsh &
/// Keller 1960; Fultz 1962 observed the change from soft to hard spring there; Faltinsen et al.
/// 2000, Waterhouse 1994).
inline constexpr double kRectangularCriticalDepthRatio{0.33680};

/// Size of the fifth-order frequency coefficient at the critical depth: there a standing wave of
/// first-harmonic wall amplitude A has omega = omega_1 (1 + c5 (k_1 A)^4) with c5 = -0.28 (soft
/// spring), measured on the fully nonlinear reference of tests/support/hos_tank.hpp (k_1 A =
/// 0.08 to 0.16 give -0.277 to -0.284; Waterhouse 1994 derived the fifth-order theory near the
/// critical depth). Near the critical depth the model is not used where this neglected term is
/// at least the third-order one it keeps: |c| < 0.28 (k_1 eta)^2, c of
/// rectangular_frequency_correction (at the steepness limit 0.3: 0.3208 < h / side < 0.3575).
inline constexpr double kRectangularCriticalFifthOrder{0.28};

/// Which of the model's limits an excited direction violates.
enum class RectangularNonlinearLimit {
  kNone,           ///< valid
  kShallowDepth,   ///< h / side < kRectangularMinDepthRatio
  kDiverged,       ///< a wall height that is not finite (the integration diverged)
  kSteepness,      ///< k_1 eta > kRectangularMaxSteepness (eta the direction's peak wall height)
  kCriticalDepth,  ///< |c| < kRectangularCriticalFifthOrder (k_1 eta)^2 near the critical depth
};

/// The verdict.
struct RectangularNonlinearValidity {
  bool valid{true};
  RectangularNonlinearLimit limit{RectangularNonlinearLimit::kNone};
  /// The direction that failed (meaningless when valid); the length when both fail.
  TankAxis axis{TankAxis::kLength};
  /// Empty when valid; otherwise one sentence naming the direction, the quantity, its value
  /// and the range, ending "; linear model used" (the exact texts are in the tests).
  std::string reason;
};

/// Peak wall heights the nonlinear model is asked to carry per direction [m] (>= 0). Zero means
/// "not known yet": only the depth limits are checked for that direction.
struct RectangularWaveHeights {
  double along_length{};  ///< peak |eta| at the walls normal to L [m]
  double along_width{};   ///< peak |eta| at the walls normal to W [m]
};

/// The larger of the motion and rest peaks of each direction of `peaks`.
[[nodiscard]] RectangularWaveHeights wave_heights(const RectangularPeaks& peaks);

/// Whether the rectangular nonlinear model (the dominant mode of each direction as the
/// third-order oscillator of make_rectangular_direction_model) holds for `model` moved along
/// model.orientation_deg with the given wall heights. Contract:
/// - Only the excited directions are checked: those with a non-zero component of
///   axis_components(model.orientation_deg) (L at 0 and 180 deg, W at +-90 deg, both otherwise).
/// - Per direction, in this order: the depth ratio h / side (side = model.along_*.radius,
///   h = fill_height) must be >= kRectangularMinDepthRatio (0.24); a non-finite height is
///   kDiverged; the steepness k_1 eta = pi eta / side must be <= kRectangularMaxSteepness (0.3);
///   and the third-order coefficient c(h / side) must keep |c| >= 0.28 (k_1 eta)^2 (fails only
///   near the critical depth 0.3368, and never for eta = 0).
/// - Both excited directions are checked. When one fails, its verdict is returned; when both
///   fail, the length's verdict (limit, axis) with a reason naming both: the length's sentence
///   without its tail, "; ", then the width's sentence (one warning, every direction out of
///   range named); valid otherwise.
/// - Pure: no allocation beyond the reason text, no state; the model is assumed built by
///   make_rectangular_model (sides and fill height positive and finite).
[[nodiscard]] RectangularNonlinearValidity rectangular_nonlinear_validity(
    const RectangularModel& model, const RectangularWaveHeights& heights = {});

}  // namespace slosh
