#pragma once
// Every kind of warning a plan can carry, in one table: the kind is set where the warning is
// made, and the compact view's code, the OpenAPI description and the honest-status rule (which
// kinds keep a plan from being `optimal`) all read it here, never the sentence.

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace slosh {

/// What a warning says (SPEC §2's validity limits, the planner's findings).
enum class WarningKind {
  kLinearModelUnreliable,    ///< peak |a| beyond the linear model's validity
  kModelsOutOfRange,         ///< peak a beyond g h / R: the surface reaches the bottom
  kSurfaceTension,           ///< a container too narrow for the models
  kShallowFill,              ///< the cylinder's fill ratio in the shallow-liquid regime
  kSpill,                    ///< eta_motion above the free board
  kWaveExceedsFill,          ///< a wave deeper than the fill: the liquid uncovers the bottom
  kWorseThanBaseline,        ///< the law leaves more sloshing than the uniform law
  kLinearModelBeyondTheory,  ///< a rectangular tank's linear model out of its theory
  kNonlinearModelNotValid,   ///< a rectangular tank's nonlinear model out of range or diverged
  kReferenceLinear,          ///< the uniform law's nonlinear figures are the linear model's
  kReductionsOnLinearModel,  ///< the law's and the uniform law's nonlinear figures differ in model
  kMotionTooShort,           ///< no law of this duration can act on the tank's modes
  kYawModesNotModelled,      ///< a turning tank's yaw drives modes the models leave out
  kFillRangeBeyondModels,    ///< a fill height range reaching a fill the models do not describe
  kModalSumNotConverged,     ///< a rectangular tank's modes left out answer the motion dynamically
  kTrajectoryEndMoving,      ///< a sampled trajectory starts or ends moving
  kTimeLimitedCandidates,    ///< auto: a candidate ran out of its time budget
};

/// Whether a kind keeps a plan whose law meets its constraints from being `optimal` (SPEC §5
/// "Honest status").
enum class StatusEffect {
  kNone,        ///< a caveat on the figures only
  kNotOptimal,  ///< for every strategy: the law's own outcome (spill, bottom uncovered)
  kNotOptimalExceptBaseline,  ///< a shaping law's promise fails; the uniform law promises none
  /// For the strategies held to an eta bound on the nonlinear model (time_domain, auto): the
  /// bound was met on figures that stand in for that model.
  kNotOptimalWhenBounded,
};

/// One kind's row of the table.
struct WarningKindInfo {
  WarningKind kind;
  /// The code: what the compact view and a batch row list for such a warning.
  std::string_view code;
  /// How the warning's text begins (for the OpenAPI description; never matched).
  std::string_view prefix;
  /// When it is given, for the OpenAPI description.
  std::string_view meaning;
  StatusEffect effect;
  /// The reason a plan's message leads with ("not optimal: <reason>") when effect applies.
  std::string_view reason;
};

/// One warning: its kind and its sentence (with the numbers and the remedy).
struct Warning {
  WarningKind kind;
  std::string text;
  bool operator==(const Warning&) const = default;
};

/// Every kind, in the order the OpenAPI description lists them.
[[nodiscard]] std::span<const WarningKindInfo> warning_kinds();

/// The row of `kind`.
[[nodiscard]] const WarningKindInfo& warning_kind_info(WarningKind kind);

/// The sentences of `warnings`, in order.
[[nodiscard]] std::vector<std::string> warning_texts(const std::vector<Warning>& warnings);

/// The code of each of `warnings`, in order (one per warning).
[[nodiscard]] std::vector<std::string> warning_codes(const std::vector<Warning>& warnings);

/// True when one of `warnings` is of `kind`.
[[nodiscard]] bool has_warning(const std::vector<Warning>& warnings, WarningKind kind);

/// True when a plan with `warnings` compares its law with the uniform law on the linear model: a
/// rectangular tank's nonlinear model holds for one of the two laws only
/// (`reductions_on_linear_model`) or for neither (`nonlinear_model_not_valid` and
/// `reference_nonlinear_model_not_valid`), so both laws' nonlinear figures are not the
/// nonlinear model's.
[[nodiscard]] bool compares_on_linear_model(const std::vector<Warning>& warnings);

}  // namespace slosh
