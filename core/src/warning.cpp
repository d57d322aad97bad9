#include "slosh/core/warning.hpp"

#include <algorithm>
#include <stdexcept>

namespace slosh {

namespace {

constexpr WarningKindInfo kKinds[] = {
    {WarningKind::kLinearModelUnreliable, "linear_model_unreliable", "peak |acceleration| ",
     "the law's peak acceleration is beyond the linear model's validity: rely on the nonlinear "
     "prediction",
     StatusEffect::kNone, ""},
    {WarningKind::kModelsOutOfRange, "models_out_of_range", "peak horizontal acceleration ",
     "the law's peak horizontal acceleration tilts the free surface (quasi-statically) down to "
     "the container's bottom: neither model describes the liquid there",
     StatusEffect::kNone, ""},
    {WarningKind::kSurfaceTension, "surface_tension", "radius ",
     "the container is so narrow that surface tension, which is not modelled, matters (a "
     "rectangular tank's sentence opens with \"half the shorter side \")",
     StatusEffect::kNone, ""},
    {WarningKind::kShallowFill, "shallow_fill", "fill ratio ",
     "the fill ratio h/R is in the shallow-liquid regime, which is not modelled",
     StatusEffect::kNone, ""},
    {WarningKind::kSpill, "spill", "predicted sloshing height during the motion ",
     "the predicted sloshing height during the motion exceeds the free board: liquid will "
     "spill; the plan is not optimal",
     StatusEffect::kNotOptimal,
     "the predicted sloshing exceeds the free board (liquid will spill)"},
    {WarningKind::kWaveExceedsFill, "wave_exceeds_fill", "predicted wave ",
     "a predicted wave (during or after the motion) is deeper than the fill: the liquid uncovers "
     "the container's bottom, which neither model describes; the plan is not optimal",
     StatusEffect::kNotOptimal,
     "the predicted wave is deeper than the fill (the liquid uncovers the bottom)"},
    {WarningKind::kWorseThanBaseline, "worse_than_baseline", "worse_than_baseline: ",
     "the chosen law leaves more residual sloshing than the uniform baseline law; such a plan "
     "(but baseline's) is not optimal",
     StatusEffect::kNotOptimalExceptBaseline,
     "the law sloshes more than the uniform law (worse_than_baseline)"},
    {WarningKind::kLinearModelBeyondTheory, "linear_model_beyond_theory",
     "linear model beyond its theory: ",
     "a rectangular tank: the linear model's wall height is not small against the depth, or "
     "steeper than the steepest standing wave: its figures are not reliable",
     StatusEffect::kNone, ""},
    {WarningKind::kNonlinearModelNotValid, "nonlinear_model_not_valid",
     "rectangular nonlinear model not valid along the ",
     "a rectangular tank: its nonlinear model is outside its theory (shallow fill, steep wave, "
     "critical depth) or diverged along a side (\"rectangular nonlinear model diverges along "
     "the ...\"), and the linear model answers there; a law held to an eta bound on the "
     "nonlinear model (time_domain's, auto's) met it on those figures, so its plan is not "
     "optimal",
     StatusEffect::kNotOptimalWhenBounded,
     "its eta bound was met on the linear figures standing in for the nonlinear model, out of its "
     "range for this law (nonlinear_model_not_valid)"},
    {WarningKind::kReferenceLinear, "reference_nonlinear_model_not_valid",
     "the uniform law's nonlinear figures ",
     "a rectangular tank: the uniform law (the reference of the reductions) is outside the "
     "nonlinear model's range, so its nonlinear figures are the linear model's (the reductions "
     "then compare both laws' linear figures: reductions_on_linear_model)",
     StatusEffect::kNone, ""},
    {WarningKind::kReductionsOnLinearModel, "reductions_on_linear_model",
     "reductions on the linear model: ",
     "a rectangular tank: one of the plan's law and the uniform law is outside the nonlinear "
     "model's range and the other within it, so their nonlinear figures come from different "
     "models; reduction_pct (and the message's changes) compare both laws' linear figures, and "
     "reduction_pct.model is \"linear\"",
     StatusEffect::kNone, ""},
    {WarningKind::kMotionTooShort, "motion_too_short", "motion too short for the tank: ",
     "a rectangular tank: the move is an impulse to the tank's modes; every law of this duration "
     "that moves one way leaves nearly the uniform law's residual wave, so a plan of a shaping "
     "strategy is not optimal (baseline's is, unless another kind says otherwise)",
     StatusEffect::kNotOptimalExceptBaseline,
     "the motion is too short for any law to act on the tank's modes"},
    {WarningKind::kYawModesNotModelled, "yaw_modes_not_modelled", "yaw modes not modelled: ",
     "a rectangular tank turns (a rotary table) with a yaw acceleration whose share at its "
     "corners drives the modes odd in both directions, which the models leave out: the "
     "predicted heights are a lower bound",
     StatusEffect::kNone, ""},
    {WarningKind::kModalSumNotConverged, "modal_sum_not_converged",
     "modal sum not converged along the ",
     "a rectangular tank long against the distance a wave travels in the motion: the first mode "
     "the model leaves out has a period over half the motion time, so the higher modes answer "
     "the motion dynamically and their waves are missing from the figures, which are not "
     "reliable",
     StatusEffect::kNone, ""},
    {WarningKind::kTrajectoryEndMoving, "trajectory_end_moving", "the trajectory ",
     "simulate of a sampled trajectory: it starts or ends moving (at a speed or turning rate "
     "above what the samples' rounding explains), and the answer says what it assumed there",
     StatusEffect::kNone, ""},
    {WarningKind::kFillRangeBeyondModels, "fill_range_beyond_models", "fill height range ",
     "options.uncertainty.fill_height_mm reaches, at its low end, a fill the models do not "
     "describe (a cylinder's shallow-liquid regime, a rectangular tank's fill below its "
     "nonlinear model's depth range) while the nominal fill is within them: the range scales the "
     "nominal fill's models, so the worst case and the robustness figures near that end are not "
     "reliable",
     StatusEffect::kNone, ""},
    {WarningKind::kTimeLimitedCandidates, "time_limited_candidates", "time_limited_candidates: ",
     "auto only: a candidate ran out of its time budget (status time_limit), so the choice "
     "depends on the budget and the machine's load; such a plan is not cached",
     StatusEffect::kNone, ""},
};

}  // namespace

std::span<const WarningKindInfo> warning_kinds() {
  return kKinds;
}

const WarningKindInfo& warning_kind_info(WarningKind kind) {
  for (const WarningKindInfo& info : kKinds) {
    if (info.kind == kind) return info;
  }
  throw std::logic_error("a warning kind without a row in the table");
}

std::vector<std::string> warning_texts(const std::vector<Warning>& warnings) {
  std::vector<std::string> out;
  out.reserve(warnings.size());
  for (const Warning& w : warnings) out.push_back(w.text);
  return out;
}

std::vector<std::string> warning_codes(const std::vector<Warning>& warnings) {
  std::vector<std::string> out;
  out.reserve(warnings.size());
  for (const Warning& w : warnings) out.emplace_back(warning_kind_info(w.kind).code);
  return out;
}

bool has_warning(const std::vector<Warning>& warnings, WarningKind kind) {
  return std::any_of(warnings.begin(), warnings.end(),
                     [kind](const Warning& w) { return w.kind == kind; });
}

bool compares_on_linear_model(const std::vector<Warning>& warnings) {
  return has_warning(warnings, WarningKind::kReductionsOnLinearModel) ||
         (has_warning(warnings, WarningKind::kNonlinearModelNotValid) &&
          has_warning(warnings, WarningKind::kReferenceLinear));
}

}  // namespace slosh
