#include "slosh/core/model/uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/response/rectangular_response.hpp"
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
/// rectangular tank's most excited direction's (the one its plan's model follows).
double first_frequency(const Format& format, double fill) {
  if (!format.container.rectangular) return natural_frequency(format.container.radius, fill, 1);
  return make_sloshing_model(with_fill_and_viscosity(format, fill, format.fluid.viscosity),
                             ModelOptions{})
      .omega1();
}

/// The excited directions of a rectangular format at another fill and viscosity: their first
/// natural frequencies [rad/s] and damping ratios [-] (one direction, or two on a turned tank).
struct ExcitedDirections {
  std::vector<double> omega;
  std::vector<double> zeta;
};
ExcitedDirections excited_directions(const Format& format, double fill, double viscosity) {
  const RectangularModel m =
      rectangular_model_of(with_fill_and_viscosity(format, fill, viscosity), ModelOptions{});
  const AxisComponents c = axis_components(m.orientation_deg);
  ExcitedDirections out;
  for (const auto& [component, d] :
       {std::pair{c.along_length, &m.along_length}, std::pair{c.along_width, &m.along_width}}) {
    if (component == 0.0) continue;
    out.omega.push_back(d->omega1());
    out.zeta.push_back(d->zeta);
  }
  return out;
}

/// The least and largest frequency factor omega_1(fill) / omega_1(h) at the ends of `fills`:
/// on a turned tank over both directions, whose frequencies move by different factors (tanh(k h)
/// saturates sooner along the shorter side), so that one common factor range covers each.
std::array<double, 2> fill_scales(const Format& format, const std::array<double, 2>& fills) {
  const double h = format.fill_height;
  if (!format.container.rectangular) {
    const double w1 = first_frequency(format, h);
    return {first_frequency(format, fills[0]) / w1, first_frequency(format, fills[1]) / w1};
  }
  const double nu = format.fluid.viscosity;
  const ExcitedDirections nominal = excited_directions(format, h, nu);
  const ExcitedDirections lo = excited_directions(format, fills[0], nu);
  const ExcitedDirections hi = excited_directions(format, fills[1], nu);
  std::array<double, 2> out{INFINITY, -INFINITY};
  for (std::size_t i = 0; i < nominal.omega.size(); ++i) {
    out[0] = std::min(out[0], lo.omega[i] / nominal.omega[i]);
    out[1] = std::max(out[1], hi.omega[i] / nominal.omega[i]);
  }
  return out;
}

/// The damping ratio of the format by a correlation (the rectangular tank's own damping for
/// any correlation but kExplicit, which uncertainty_range handles; on a turned tank the lesser
/// of its two directions').
double correlated_zeta(const Format& format, DampingCorrelation correlation) {
  if (!format.container.rectangular) return damping_ratio(format, correlation);
  const ExcitedDirections d =
      excited_directions(format, format.fill_height, format.fluid.viscosity);
  return *std::min_element(d.zeta.begin(), d.zeta.end());
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
  const std::array<double, 2> scales = fill_scales(format, fills);
  r.scale_lo = scales[0] * (1.0 - u.omega_error);
  r.scale_hi = scales[1] * (1.0 + u.omega_error);
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
