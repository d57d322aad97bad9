#include "slosh/core/model/uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "slosh/core/strategy/planner.hpp"
#include "text.hpp"

namespace slosh {

namespace {

using detail::sig3;

/// Fill heights between the ends at which zeta is evaluated (the correlations are not all
/// monotone in h/R) [-].
constexpr int kZetaFillSamples{5};
/// Largest viscosity the planner accepts [Pa s] (as for the format's fluid).
constexpr double kMaxViscosity{1e6};

InvalidInput element_refusal(PlanInput input, int index, double value, const InputBounds& bounds,
                             std::string message) {
  InvalidInput e = refused(input, value, bounds, std::move(message));
  e.index = index;
  return e;
}

/// A (min, max) range: each element finite and within `bounds`, min <= max, `nominal` inside.
std::optional<InvalidInput> validate_pair(PlanInput input, const std::array<double, 2>& pair,
                                          const InputBounds& bounds, double nominal,
                                          const char* name, const char* unit) {
  for (int i = 0; i < 2; ++i) {
    if (!bounds.contains(pair[i])) return out_of_range(input, i, pair[i], bounds);
  }
  const std::string text = "[" + sig3(pair[0]) + ", " + sig3(pair[1]) + "] " + unit;
  if (pair[0] > pair[1]) {
    return element_refusal(
        input, 1, pair[1], InputBounds{pair[0], bounds.hi},
        std::string(name) + " = " + text + " is empty: the maximum must be >= the minimum");
  }
  if (nominal < pair[0] || nominal > pair[1]) {
    const int index = nominal < pair[0] ? 0 : 1;
    const InputBounds allowed =
        index == 0 ? InputBounds{bounds.lo, nominal} : InputBounds{nominal, bounds.hi};
    return element_refusal(input, index, pair[static_cast<std::size_t>(index)], allowed,
                           std::string(name) + " = " + text + " must contain the nominal " +
                               sig3(nominal) + " " + unit);
  }
  return std::nullopt;
}

Format with_fill_and_viscosity(Format f, double fill_height, double viscosity) {
  f.fill_height = fill_height;
  f.fluid.viscosity = viscosity;
  return f;
}

}  // namespace

std::optional<InvalidInput> validate_uncertainty(const Format& format, const ModelOptions& model,
                                                 const Uncertainty& u) {
  if (!closed_range(0.0, kMaxOmegaError).contains(u.omega_error)) {
    return out_of_range(PlanInput::kOmegaError, -1, u.omega_error,
                        closed_range(0.0, kMaxOmegaError));
  }
  if (u.fill_height) {
    const double top = std::min(kMaxPlanLength, format.container.height.value_or(kMaxPlanLength));
    if (auto bad = validate_pair(PlanInput::kFillHeightRange, *u.fill_height,
                                 closed_range(kMinPlanLength, top), format.fill_height,
                                 "fill_height", "m")) {
      return bad;
    }
  }
  if (u.viscosity) {
    if (model.damping == DampingCorrelation::kExplicit) {
      return refused(PlanInput::kViscosityRange, (*u.viscosity)[0], InputBounds{},
                     "a viscosity range has no effect with an explicit zeta: give a zeta "
                     "correlation, or no viscosity range");
    }
    if (auto bad = validate_pair(PlanInput::kViscosityRange, *u.viscosity,
                                 closed_range(0.0, kMaxViscosity), format.fluid.viscosity,
                                 "viscosity", "Pa s")) {
      return bad;
    }
  }
  const double samples = static_cast<double>(u.sample_points);
  const InputBounds sample_bounds = closed_range(kMinUncertaintySamples, kMaxUncertaintySamples);
  if (!sample_bounds.contains(samples)) {
    return out_of_range(PlanInput::kUncertaintySamples, -1, samples, sample_bounds);
  }
  return std::nullopt;
}

namespace {

/// The first natural frequency of the format at another fill [rad/s]: the cylinder's, or the
/// rectangular tank's most excited direction's (only a tank square to the motion is planned
/// over a range: one direction).
double first_frequency(const Format& format, double fill) {
  if (!format.container.rectangular) return natural_frequency(format.container.radius, fill, 1);
  return make_sloshing_model(with_fill_and_viscosity(format, fill, format.fluid.viscosity),
                             ModelOptions{})
      .omega1();
}

/// The damping ratio of the format by a correlation (the rectangular tank's own damping for
/// any correlation but kExplicit, which uncertainty_range handles).
double correlated_zeta(const Format& format, DampingCorrelation correlation) {
  if (!format.container.rectangular) return damping_ratio(format, correlation);
  return make_sloshing_model(format, ModelOptions{}).zeta;
}

}  // namespace

UncertaintyRange uncertainty_range(const Format& format, const ModelOptions& model,
                                   const Uncertainty& u) {
  const double h = format.fill_height;
  const double nu = format.fluid.viscosity;
  const double w1 = first_frequency(format, h);
  const std::array<double, 2> fills = u.fill_height.value_or(std::array<double, 2>{h, h});
  const std::array<double, 2> viscosities = u.viscosity.value_or(std::array<double, 2>{nu, nu});
  UncertaintyRange r;
  r.scale_lo = first_frequency(format, fills[0]) / w1 * (1.0 - u.omega_error);
  r.scale_hi = first_frequency(format, fills[1]) / w1 * (1.0 + u.omega_error);
  if (model.damping == DampingCorrelation::kExplicit) {
    r.zeta_lo = r.zeta_hi = model.explicit_zeta;
  } else {
    r.zeta_lo = INFINITY;
    r.zeta_hi = -INFINITY;
    for (int k = 0; k < kZetaFillSamples; ++k) {
      const double fill = fills[0] + (fills[1] - fills[0]) * k / (kZetaFillSamples - 1);
      for (double v : viscosities) {
        const double z = correlated_zeta(with_fill_and_viscosity(format, fill, v), model.damping);
        r.zeta_lo = std::min(r.zeta_lo, z);
        r.zeta_hi = std::max(r.zeta_hi, z);
      }
    }
  }
  r.omega_lo = w1 * r.scale_lo;
  r.omega_hi = w1 * r.scale_hi;
  return r;
}

SloshingModel scaled_model(const SloshingModel& model, double scale, double zeta) {
  SloshingModel m = model;
  for (double& w : m.omega) w *= scale;
  m.zeta = zeta;
  return m;
}

std::vector<SloshingModel> sample_models(const SloshingModel& nominal,
                                         const UncertaintyRange& range, int points) {
  std::vector<SloshingModel> models;
  models.reserve(static_cast<std::size_t>(points));
  for (int k = 0; k < points; ++k) {
    const double s = points == 1
                         ? range.scale_mid()
                         : range.scale_lo + (range.scale_hi - range.scale_lo) * k / (points - 1);
    models.push_back(scaled_model(nominal, s, range.zeta_lo));
  }
  return models;
}

}  // namespace slosh
