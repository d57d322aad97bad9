#pragma once
// A rectangular format's models as the planner drives them (SPEC §15): the tank's model built
// from the plan's model options, and each excited direction as a SloshingModel driven by the
// whole acceleration along the motion, so that every strategy written for one model plans it.

#include <vector>

#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/model/sloshing_model.hpp"

namespace slosh {

/// The rectangular model's options from the plan's: modes, omega_scale and height_gain as given;
/// the damping ratio only when explicit (kExplicit), else the tank's laminar boundary-layer
/// damping. The cylinder's correlations and alpha do not apply to a rectangular tank (its
/// nonlinear coefficient follows from the depth, docs/models.md).
[[nodiscard]] RectangularModelOptions rectangular_model_options(const ModelOptions& options);

/// The model of a rectangular format (format.container.rectangular set; inputs validated).
[[nodiscard]] RectangularModel rectangular_model_of(const Format& format,
                                                    const ModelOptions& options);

/// One excited direction of the tank.
struct DrivenDirection {
  /// The direction's model driven by the acceleration a along the motion instead of its share
  /// c a: eta_gain and K times |c|, alpha times c^2 (with y = xbar / c the direction's equation
  /// xbar'' + ... + w^2 xbar (1 + alpha xbar^2) + c a / side = 0 becomes the same equation in y
  /// with alpha c^2 and forcing a / side, and eta = K xbar = K c y; the sign of c only flips the
  /// wave, the equation being odd). Outside the nonlinear model's depth range alpha is 0: the
  /// dominant mode stays linear, as the linear model answers there.
  SloshingModel model;
  TankAxis axis{TankAxis::kLength};
  double component{};  ///< c: cos(phi) along L, sin(phi) along W [-]
};

/// The excited directions (one when the tank is square to the motion, else two), the most
/// excited first: the larger |c| G_1 / omega_1^2 (the static wall height per unit acceleration),
/// the length on a tie.
[[nodiscard]] std::vector<DrivenDirection> driven_directions(const RectangularModel& model);

/// `model` with its wall heights (eta_gain and K) multiplied by `factor`.
[[nodiscard]] SloshingModel with_height_factor(const SloshingModel& model, double factor);

}  // namespace slosh
