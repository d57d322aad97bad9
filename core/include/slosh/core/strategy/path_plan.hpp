#pragma once
// Planning along a planar path (SPEC §14): the law s(t) moves the container along a path of
// lines and arcs, its 7 durations spanning the path length. The world-frame acceleration is the
// tangential s'' plus the normal s'^2 / rho on the arcs, and the wave follows the planar models
// (planar_response.hpp). time_domain optimises the planar nonlinear model itself (the bound on
// eta_rest holds over the whole wall, with exact sensitivities); every other strategy shapes the
// tangential acceleration as it does on a straight line of the path's length, and its law is
// then verified on both planar models. Pure numerics: no JSON, no logging.

#include <optional>
#include <vector>

#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/response/planar_response.hpp"
#include "slosh/core/strategy/path_report.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh {

/// Plans a law along `path` for `format` (its stroke is set to the path length). Options as
/// plan(); the machine limits mean: v_max on s', a_max on the total horizontal acceleration
/// sqrt(s''^2 + (s'^2 / rho)^2), j_max on the tangential jerk s'''. options.robustness and an
/// active options.uncertainty are not applied along a path (no robustness report). The status
/// follows the verification on the planar models and the path's limits; its predictions
/// (PlanResult::prediction, baseline and the candidates') are the planar models' peaks along the
/// path, and its message says how the law was made (time_domain: on the planar nonlinear model;
/// the others: the tangential acceleration shaped, the normal one not).
[[nodiscard]] PlanResult plan_on_path(const Format& format, const PlanarPath& path,
                                      Strategy strategy, const PlanOptions& options);

/// The report of a plan_on_path result: its law's and the uniform law's verified figures along
/// the path, with the wall direction of every peak (the same computation the plan was verified by).
[[nodiscard]] PathPlanReport path_plan_report(const PlanResult& result, const PlanarPath& path,
                                              double motion_time, double rest_time);

/// The verified figures of `law` along `path`.
[[nodiscard]] PathPrediction predict_on_path(const SloshingModel& model, const PlanarPath& path,
                                             const MotionLaw& law, double rest_time);

/// Largest total horizontal acceleration sqrt(s''^2 + (kappa s'^2)^2) of `law` along `path`
/// [m/s^2] and where [s], and the largest normal acceleration: each law piece on each path
/// element sampled at 64 points and every local maximum refined by golden section to 1e-12 s.
struct PathAcceleration {
  double total{};
  double time{};
  double normal{};
};
[[nodiscard]] PathAcceleration path_acceleration(const PlanarPath& path, const MotionLaw& law);

}  // namespace slosh
