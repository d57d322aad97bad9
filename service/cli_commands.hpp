#pragma once
// The CLI subcommands that print JSON: same bodies and responses as the HTTP API.

#include <optional>
#include <string>

namespace slosh::service {

/// Exit codes of the CLI.
enum ExitCode : int { kExitOk = 0, kExitFailure = 1, kExitInvalidInput = 2 };

/// `slosh simulate --request FILE|-`: prints the simulate response on stdout; on invalid input
/// prints the error envelope on stderr and returns kExitInvalidInput.
int run_simulate_command(const std::string& request_path);

/// `slosh plan --request FILE|- [--view full|compact]`: prints the plan response on stdout (exit 0
/// whatever the plan's status, which the JSON carries), in the view named by `view` (none = full;
/// see api::compact_plan); invalid input (an unknown view too) as for simulate.
int run_plan_command(const std::string& request_path,
                     const std::optional<std::string>& view = std::nullopt);

/// `slosh min-time --request FILE|-`: prints the min-time response (SPEC §9) on stdout, every
/// strategy searched in turn (exit 0 whatever their status); invalid input as for simulate.
int run_min_time_command(const std::string& request_path);

/// `slosh calibrate --request FILE|-`: prints the POST /v1/calibrations response on stdout (the
/// fit runs without a time budget; a "name" is echoed, not stored); invalid input as for simulate.
int run_calibrate_command(const std::string& request_path);

}  // namespace slosh::service
