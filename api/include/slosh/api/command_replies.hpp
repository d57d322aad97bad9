#pragma once
// The replies of the `slosh` commands that answer as the HTTP API does (simulate, plan,
// min-time, calibrate, fluids), request text in and reply text out, so that the command line
// reads and writes no JSON itself. Replies are indented by 2 spaces for a terminal.

#include <optional>
#include <string>
#include <string_view>

#include "slosh/api/error.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::api {

/// A rectangular container of the format flags.
struct QuickRectangle {
  double length_mm{};                     ///< side L [mm]
  double width_mm{};                      ///< side W [mm]
  std::optional<double> orientation_deg;  ///< angle of L to the motion [deg]; unset: 0
};

/// The move flags of `slosh plan` and `slosh min-time`: an arc, or format.motion as JSON text.
struct QuickMotion {
  /// An arc: radius [mm], angle [deg], the container turning (default true): format.motion
  /// {"type": "arc", ...}.
  std::optional<double> arc_radius_mm, arc_angle_deg;
  std::optional<bool> turns;
  /// format.motion as JSON text (`--motion FILE`, named by motion_source).
  std::optional<std::string> motion_text;
  std::string motion_source;
};

/// The format flags of `slosh plan` (a quick look without a request file).
struct QuickPlan {
  double radius_mm{};                         ///< container radius [mm] (unused with `rectangular`)
  std::optional<QuickRectangle> rectangular;  ///< a rectangular container instead
  std::optional<double> height_mm;            ///< container height [mm]; unset: none given
  double fill_mm{};                           ///< fill height [mm]
  std::optional<std::string> fluid;           ///< a catalogue fluid, or else
  std::optional<double> density_kg_m3;        ///< a custom fluid's density [kg/m^3]
  std::optional<double> viscosity_pa_s;       ///< and dynamic viscosity [Pa s]
  double stroke_mm{};                         ///< [mm] (unused with an arc or a motion)
  QuickMotion motion;                         ///< an arc or a motion instead of the stroke
  double time_s{};                            ///< motion time [s]
  std::string strategy{"auto"};
};

/// The POST /v1/simulate reply to `request`; ApiError for invalid input.
[[nodiscard]] std::string simulate_reply(std::string_view request);

/// The POST /v1/calibrations reply to `request` (no time budget; a "name" is echoed, not stored).
[[nodiscard]] std::string calibration_reply(std::string_view request);

/// The POST /v1/min-time reply to `request`, without a server budget: options.time_limit_s (per
/// strategy) may be up to its maximum, which is also its default.
[[nodiscard]] std::string min_time_reply(std::string_view request);
/// The same with the move flags `motion` as the request's format.motion (the request then gives
/// neither format.stroke_mm nor format.motion: refused naming the member and the flag).
[[nodiscard]] std::string min_time_reply(std::string_view request, const QuickMotion& motion);

/// The POST /v1/plans reply to `request` in `view`; ApiError for invalid input (and for a
/// compact view of a request with sampled series).
[[nodiscard]] std::string plan_reply(std::string_view request, PlanView view);
/// The same for the plan request the format flags `quick` stand for (their values are checked by
/// the request parser, errors naming the request's fields).
[[nodiscard]] std::string plan_reply(const QuickPlan& quick, PlanView view);

/// The short text summary of the plan of `request` (plan_summary_text); ApiError for invalid input.
[[nodiscard]] std::string plan_summary_reply(std::string_view request);
[[nodiscard]] std::string plan_summary_reply(const QuickPlan& quick);

/// The GET /v1/fluids body, or (`as_table`) the catalogue as a text table.
[[nodiscard]] std::string fluids_reply(bool as_table);

/// The error envelope of `error`, as the API answers it.
[[nodiscard]] std::string error_envelope_text(const ApiError& error);

}  // namespace slosh::api
