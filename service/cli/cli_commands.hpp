#pragma once
// The CLI subcommands that print JSON: same bodies and responses as the HTTP API.

#include <optional>
#include <string>
#include <vector>

namespace slosh::service {

/// Exit codes of the CLI.
enum ExitCode : int { kExitOk = 0, kExitFailure = 1, kExitInvalidInput = 2 };

/// `slosh simulate --request FILE|-`: prints the simulate response on stdout; on invalid input
/// prints the error envelope on stderr and returns kExitInvalidInput. A non-empty
/// `trajectory_path` (`--trajectory FILE.csv`) is the request's format.motion.
int run_simulate_command(const std::string& request_path, const std::string& trajectory_path = {});

/// The move flags of `slosh plan` and `slosh min-time` (add_motion_flags registers them for
/// both): a rotary table's (or a curved track's) arc instead of the stroke, its radius [mm] and
/// the angle turned [deg, signed, left positive]; `turns`: the container turns with the table
/// (default true, a carriage on a curved track keeps its heading: false); or a file holding
/// format.motion (a line, an arc or a path, SPEC §14). Unset = not given.
struct MotionFlags {
  std::optional<double> arc_radius_mm, arc_angle_deg;
  std::optional<bool> turns;
  std::optional<std::string> motion_path;
};

/// Why the move flags conflict (--motion with the arc's flags, --turns without an arc), or ""
/// when they do not.
[[nodiscard]] std::string motion_flags_problem(const MotionFlags& m);

/// The format flags of `slosh plan` (a quick look without a request file): lengths in mm, the
/// motion time in s, density kg/m^3, viscosity Pa s; unset = not given.
struct QuickPlanFlags : MotionFlags {
  std::optional<double> radius_mm, fill_mm, height_mm, stroke_mm, time_s;
  /// A rectangular container instead of the radius: sides [mm] and orientation [deg].
  std::optional<double> length_mm, width_mm, orientation_deg;
  std::optional<std::string> fluid;                     ///< a catalogue name (slosh fluids)
  std::optional<double> density_kg_m3, viscosity_pa_s;  ///< a custom fluid instead
  std::optional<std::string> strategy;                  ///< default auto
  /// The flags given, as typed ("--radius", ...), in the order of the help.
  [[nodiscard]] std::vector<std::string> given() const;
};

/// Everything `slosh plan` takes.
struct PlanCommandOptions {
  std::string request_path{"-"};
  bool request_given{false};  ///< --request was on the command line
  QuickPlanFlags quick;
  std::optional<std::string> view;  ///< full (default) or compact; JSON output only
  std::optional<std::string>
      format;  ///< text or json; default json with a request, text with flags
};

/// `slosh plan --request FILE|- [--view full|compact] [--format json|text]` or `slosh plan
/// --radius R (or --length L --width W [--orientation DEG]) --fill H --fluid NAME --stroke S
/// --time T [--height C] [--strategy NAME]` (or, for the move, `--arc-radius R --arc-angle A
/// [--turns true|false]` or `--motion FILE.json` instead of --stroke): prints
/// the plan on stdout, as the /v1/plans response (json, the view named by `view`) or as a short
/// summary (text, api::plan_summary_text); exit 0 whatever the plan's status. Invalid input as for
/// simulate (the envelope on stderr; with text output the message and the flag it came from); flags
/// that conflict or are missing: a one-line message on stderr, exit 2.
int run_plan_command(const PlanCommandOptions& options);

/// `slosh fluids [--format text|json]`: the fluid catalogue (json: the GET /v1/fluids body).
int run_fluids_command(const std::string& format);

/// `slosh min-time --request FILE|- [--arc-radius R --arc-angle A [--turns true|false] |
/// --motion FILE.json]`: prints the min-time response (SPEC §9) on stdout, every strategy
/// searched in turn (exit 0 whatever their status); the move flags are the request's
/// format.motion, as for `slosh plan`; invalid input as for simulate; move flags that conflict
/// or are incomplete: a one-line message on stderr, exit 2.
int run_min_time_command(const std::string& request_path, const MotionFlags& motion = {});

/// `slosh calibrate --request FILE|-`: prints the POST /v1/calibrations response on stdout (the
/// fit runs without a time budget; a "name" is echoed, not stored); invalid input as for simulate.
int run_calibrate_command(const std::string& request_path);

}  // namespace slosh::service
