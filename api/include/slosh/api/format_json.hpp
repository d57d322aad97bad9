#pragma once
// JSON <-> format, fluid and model types. The HTTP/CLI surface speaks mm and s; core is SI.

#include <string>

#include <nlohmann/json.hpp>

#include "slosh/api/fields.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/model/sloshing_model.hpp"

namespace slosh::api {

/// Allowed ranges of the request fields (user units).
namespace ranges {
inline const Range kRadiusMm{1.0, 2000.0, "mm"};
inline const Range kContainerHeightMm{0.0, 10000.0, "mm", true};
/// The sides of a rectangular container (SPEC §15): as the cylinder's diameter, 2 R.
inline const Range kSideMm{1.0, 4000.0, "mm"};
/// The angle of a rectangular container's side L to the motion.
inline const Range kOrientationDeg{-180.0, 180.0, "deg"};
// Lower bounds that keep the model physical and its numbers finite: a film under 1 mm and a
// stroke under 0.01 mm are not formats a line runs.
inline const Range kFillHeightMm{1.0, 5000.0, "mm"};
inline const Range kStrokeMm{0.01, 100000.0, "mm"};
inline const Range kMotionTimeS{0.05, 60.0, "s"};
inline const Range kDensity{100.0, 20000.0, "kg/m^3"};
inline const Range kViscosity{0.0, 10.0, "Pa·s", true};
inline const Range kZeta{0.0, 0.5, "", false, true};
inline const Range kAlpha{0.0, 2.0, ""};
/// omega_scale and height_gain of a calibrated model (options.model): (0, 10].
inline const Range kModelScale{0.0, 10.0, "", true, false};
inline const Range kRestTimeS{0.0, 60.0, "s"};
inline const Range kSamplePeriodS{1e-4, 1.0, "s"};
inline const Range kMinRampS{1e-3, 1.0, "s"};
/// Most samples a series returns (both ends included): 50 s at the controller's 1 ms cycle, about
/// 6 MB of JSON.
constexpr int kMaxSeriesSamples{50000};
}  // namespace ranges

/// Parses and validates `format` (container, fill, fluid, stroke, motion time). The container is
/// the cylinder {"radius_mm", "height_mm"?} ("shape": "cylinder" optional) or {"shape":
/// "rectangular", "length_mm", "width_mm", "height_mm"?, "orientation_deg"? (default 0)}.
[[nodiscard]] Format parse_format(const nlohmann::json& format, const std::string& path = "format");

/// The required top-level "format" of a request body (plan and simulate).
[[nodiscard]] Format parse_request_format(const nlohmann::json& body);

/// Parses `fluid`: a catalogue name or {"density_kg_m3", "viscosity_pa_s"}.
[[nodiscard]] Fluid parse_fluid(const nlohmann::json& fluid, const std::string& path);

/// Parses the model members of an options object (modes, damping, alpha) into `options`.
void parse_model_options(const nlohmann::json& options, const std::string& path,
                         ModelOptions& model);

/// Reads options.model (a calibrated model: omega_scale, zeta, alpha, height_gain; each
/// optional) into `model`, after parse_model_options; zeta and alpha override options.damping
/// and options.alpha, and giving both is refused (422 naming options.model.<member>).
void parse_calibrated_model(const nlohmann::json& options, const std::string& path,
                            ModelOptions& model);

/// Parses options.damping (a correlation name or {"zeta": z}; thesis when absent) into `model`.
void parse_damping(const nlohmann::json& options, const std::string& path, ModelOptions& model);

/// A rectangular container's model takes neither the cylinder's damping correlations nor its
/// alpha (its damping is the tank's boundary layer unless a zeta is given, its Duffing
/// coefficient follows from the depth): a 422 naming options.damping given as a correlation
/// name, options.alpha or options.model.alpha; for a cylinder, a 422 naming
/// options.model.width_omega_scale or width_zeta (a rectangular tank's width only).
void refuse_cylinder_model_options(const Format& format, const nlohmann::json& options,
                                   const std::string& path);

/// The format echoed back in user units.
[[nodiscard]] nlohmann::json format_json(const Format& format);

/// A rectangular tank's model beside "model"'s driven direction: per direction ("length",
/// "width") its share of the motion, f_hz, omega_rad_s, zeta, alpha, K_mm, sloshing masses and
/// wall gains of the tank's own model (not driven), and which are excited.
[[nodiscard]] nlohmann::json rectangular_model_json(const RectangularModel& model);

/// Adds a rectangular tank's model to a "model" object (model_json of its driven direction):
/// "rectangular" (rectangular_model_json) and "damping": "rectangular" (the tank's laminar
/// boundary-layer damping) unless the damping ratio was given.
void add_rectangular_model(nlohmann::json& out_model, const RectangularModel& model,
                           const ModelOptions& options);

/// "model": omega_rad_s, f_hz, zeta, C, alpha, K_mm, masses, gains.
[[nodiscard]] nlohmann::json model_json(const SloshingModel& model, const ModelOptions& options);

/// GET /v1/fluids body: the catalogue with sources.
[[nodiscard]] nlohmann::json fluids_json();

}  // namespace slosh::api
