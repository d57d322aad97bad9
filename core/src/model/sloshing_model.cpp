#include "slosh/core/model/sloshing_model.hpp"

#include <cmath>
#include <numbers>

#include "slosh/core/model/tank_directions.hpp"

namespace slosh {

namespace {

double reynolds_one(const Format& f) {
  const double R = f.container.radius;
  return f.fluid.kinematic_viscosity() / std::sqrt(kGravity * R * R * R);
}

}  // namespace

double damping_ratio(const Format& format, DampingCorrelation correlation) {
  const double hr = format.fill_height / format.container.radius;
  const double root_re = std::sqrt(reynolds_one(format));
  const double bracket =
      1.0 + 0.318 / std::sinh(1.84 * hr) * (1.0 + (1.0 - hr) / std::cosh(1.84 * hr));
  switch (correlation) {
    case DampingCorrelation::kThesis:
      return 0.79 * root_re * bracket;
    case DampingCorrelation::kPaper:
      return 0.92 * root_re * bracket;
    case DampingCorrelation::kEq227:
      return 0.83 * root_re * std::tanh(1.84 * hr) *
             (1.0 + 2.0 * (1.0 - hr) / std::cosh(3.68 * hr));
    case DampingCorrelation::kEq228:
      return 2.89 / std::numbers::pi * root_re * bracket;
    case DampingCorrelation::kExplicit:
      break;
  }
  return std::nan("");
}

double natural_frequency(double radius, double fill_height, int n) {
  const double xi = kBesselRoots.at(static_cast<std::size_t>(n - 1));
  return std::sqrt(kGravity * xi / radius * std::tanh(xi * fill_height / radius));
}

SloshingModel make_sloshing_model(const Format& format, const ModelOptions& options) {
  if (format.container.rectangular) {
    // A rectangular tank's one model: its most excited direction, driven by the motion.
    return driven_directions(rectangular_model_of(format, options)).front().model;
  }
  SloshingModel m;
  const double R = format.container.radius;
  const double h = format.fill_height;
  m.radius = R;
  m.fill_height = h;
  m.density = format.fluid.density;
  m.fluid_mass = std::numbers::pi * R * R * h * m.density;
  m.zeta = options.damping == DampingCorrelation::kExplicit
               ? options.explicit_zeta
               : damping_ratio(format, options.damping);
  m.alpha = options.alpha;
  for (int n = 1; n <= options.modes; ++n) {
    const double xi = kBesselRoots.at(static_cast<std::size_t>(n - 1));
    const double th = std::tanh(xi * h / R);
    m.omega.push_back(natural_frequency(R, h, n) * options.omega_scale);
    m.mass.push_back(m.fluid_mass * 2.0 * R * th / (xi * h * (xi * xi - 1.0)));
    m.eta_gain.push_back(8.0 * th / (xi * (xi * xi - 1.0)) * options.height_gain);
  }
  const double xi1 = kBesselRoots[0];
  m.C = xi1 * std::tanh(xi1 * h / R);
  m.K = 2.0 * R * m.C / (xi1 * xi1 - 1.0) * options.height_gain;
  return m;
}

std::optional<InvalidInput> validate_model_options(const ModelOptions& m) {
  if (m.modes < 1 || m.modes > static_cast<int>(kMaxModes)) {
    return out_of_range(PlanInput::kModes, -1, m.modes,
                        closed_range(1.0, static_cast<double>(kMaxModes)));
  }
  if (!non_negative().contains(m.alpha)) {
    return out_of_range(PlanInput::kAlpha, -1, m.alpha, non_negative());
  }
  if (m.damping == DampingCorrelation::kExplicit && !non_negative().contains(m.explicit_zeta)) {
    return out_of_range(PlanInput::kZeta, -1, m.explicit_zeta, non_negative());
  }
  if (!calibration_scale_range().contains(m.omega_scale)) {
    return out_of_range(PlanInput::kOmegaScale, -1, m.omega_scale, calibration_scale_range());
  }
  if (!calibration_scale_range().contains(m.height_gain)) {
    return out_of_range(PlanInput::kHeightGain, -1, m.height_gain, calibration_scale_range());
  }
  if (m.width_omega_scale && !calibration_scale_range().contains(*m.width_omega_scale)) {
    return out_of_range(PlanInput::kWidthOmegaScale, -1, *m.width_omega_scale,
                        calibration_scale_range());
  }
  if (m.width_zeta && !non_negative().contains(*m.width_zeta)) {
    return out_of_range(PlanInput::kWidthZeta, -1, *m.width_zeta, non_negative());
  }
  return std::nullopt;
}

}  // namespace slosh
