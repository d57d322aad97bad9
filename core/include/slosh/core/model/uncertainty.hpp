#pragma once
// What the model does not know exactly (SPEC §10): a relative error on every mode frequency and
// physical ranges of the fill height and the viscosity, mapped through the model to the range of
// omega_1 and zeta they imply. Robust plans hold over that range; the robustness report sweeps it.

#include <array>
#include <optional>
#include <vector>

#include "slosh/core/invalid_input.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"

namespace slosh {

/// Largest relative frequency error a plan may be asked to hold over [-] (+-50 %).
inline constexpr double kMaxOmegaError{0.5};
/// Fewest and most sample points of a robust design over the range [-].
inline constexpr int kMinUncertaintySamples{2};
inline constexpr int kMaxUncertaintySamples{21};
/// Default number of sample points of a robust design, both ends of the range included [-].
inline constexpr int kDefaultUncertaintySamples{5};

/// The uncertainty a plan must hold over. Every member is optional; `active()` is false for the
/// default (a nominal plan).
struct Uncertainty {
  /// Relative error of every mode frequency [-]: omega_n (1 + delta), |delta| <= omega_error.
  /// In [0, kMaxOmegaError]. Default 0.
  double omega_error{0.0};
  /// Fill heights the format may have [m] (min, max): the nominal fill height within, both > 0.
  /// Through the model: omega_1 (and zeta) at the two ends. Default none.
  std::optional<std::array<double, 2>> fill_height;
  /// Dynamic viscosities the fluid may have [Pa s] (min, max): the nominal within, both >= 0.
  /// Through the damping correlation: the zeta range. Refused with an explicit zeta (no effect).
  /// Default none.
  std::optional<std::array<double, 2>> viscosity;
  /// Sample points of the robust designs over the frequency range, both ends included [-], in
  /// [kMinUncertaintySamples, kMaxUncertaintySamples]. Default 5.
  int sample_points{kDefaultUncertaintySamples};

  /// True when some range is given (omega_error > 0 or a physical range).
  [[nodiscard]] bool active() const {
    return omega_error > 0.0 || fill_height.has_value() || viscosity.has_value();
  }
};

/// The range of the model an Uncertainty implies. Frequencies are the nominal model's scaled by
/// a common factor: omega_n s with s in [scale_lo, scale_hi] (1 inside).
struct UncertaintyRange {
  double scale_lo{1.0};  ///< least frequency factor [-]
  double scale_hi{1.0};  ///< largest frequency factor [-]
  double zeta_lo{};      ///< least damping ratio over the range [-]
  double zeta_hi{};      ///< largest damping ratio over the range [-]
  double omega_lo{};     ///< omega_1 scale_lo [rad/s]
  double omega_hi{};     ///< omega_1 scale_hi [rad/s]

  /// The centre of the frequency range, the factor the filters and notches are designed at [-].
  [[nodiscard]] double scale_mid() const { return 0.5 * (scale_lo + scale_hi); }
  /// The centre of the damping range [-].
  [[nodiscard]] double zeta_mid() const { return 0.5 * (zeta_lo + zeta_hi); }
};

/// The first member of `u` outside what the planner accepts for `format` (omega_error in
/// [0, 0.5]; each range finite, min <= max, the nominal value inside, fill heights in
/// [kMinPlanLength, kMaxPlanLength] and below the container height when given, viscosities in
/// [0, 1e6] Pa s and not with an explicit zeta; sample_points in [2, 21]), or nullopt.
[[nodiscard]] std::optional<InvalidInput> validate_uncertainty(const Format& format,
                                                               const ModelOptions& model,
                                                               const Uncertainty& u);

/// The range `u` implies for the model of `format` (validated inputs): omega_1 at both fill
/// height ends (it grows with h), times (1 -+ omega_error); zeta over the fill heights and
/// viscosities (at both ends of each and at 5 fill heights between, as the correlations are not
/// all monotone in h). Without uncertainty: the nominal omega_1 and zeta.
[[nodiscard]] UncertaintyRange uncertainty_range(const Format& format, const ModelOptions& model,
                                                 const Uncertainty& u);

/// The model with every mode frequency multiplied by `scale` and damping ratio `zeta` (masses,
/// gains and the nonlinear coefficients are the nominal ones: SPEC §10 maps the uncertainty to
/// omega and zeta only).
[[nodiscard]] SloshingModel scaled_model(const SloshingModel& model, double scale, double zeta);

/// The models a robust design holds at: `points` frequency factors evenly over the range, both
/// ends included, each at the least damping of the range (a linear mode's residual and forced
/// amplitude grow as damping falls).
[[nodiscard]] std::vector<SloshingModel> sample_models(const SloshingModel& nominal,
                                                       const UncertaintyRange& range, int points);

}  // namespace slosh
