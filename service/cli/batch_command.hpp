#pragma once
// `slosh batch`: a recipe table in, a plan table out (locally on a worker pool, or through a
// running service's POST /v1/plans/batch); or a table of minimum motion times (locally, or
// through POST /v1/min-time).

#include <cstddef>
#include <optional>
#include <string>

#include "cli/progress_bar.hpp"
#include "config/server_config.hpp"

namespace slosh::service {

/// Exit code of a batch whose table was processed but some rows could not be planned.
constexpr int kExitSomeRowsFailed = 3;
/// Exit code of a run stopped by Ctrl-C (SIGINT), as a shell reports a process the signal ended.
constexpr int kExitInterrupted = 130;

/// The ranges of the server-mode patience options, checked by their flags and by
/// run_batch_command alike.
constexpr int kMaxRetries = 1000;
constexpr int kMinGiveUpAfterS = 1;
constexpr int kMaxGiveUpAfterS = 86400;

struct BatchCommandOptions {
  /// Recipe table path, "-" = stdin. Default "-".
  std::string in{"-"};
  /// Plan table path, "-" = stdout. A file is written as "<out>.partial" and renamed when the
  /// table is complete. Default "-".
  std::string out{"-"};
  /// auto (from the extension; CSV for "-") | csv | jsonl | json.
  std::string in_format{"auto"};
  std::string out_format{"auto"};
  /// Local solving: workers (0 = the cores), cache file, memory entries, solve budget.
  ServerConfig config;
  /// Base URL of a running service (http://host:port); empty = solve locally. min_time mode POSTs
  /// each row to its /v1/min-time.
  std::string server;
  /// Recipes per POST /v1/plans/batch in server mode (<= the server's batch_max; plan mode).
  /// Default 64.
  std::size_t chunk{64};
  /// Server mode: how many times a call the service answers 503 ("not now", e.g. its replicas'
  /// Redis is down) is sent again, each after the answer's Retry-After (1 to 30 s), before the
  /// run stops. 0 to kMaxRetries. Default 30.
  int retries{30};
  /// Server mode: how long the progress of a started batch job is polled while the service does
  /// not answer at all (the replica that runs it is paused or restarting) before the run stops,
  /// leaving the job alone [s]. kMinGiveUpAfterS to kMaxGiveUpAfterS. Default 60: twice the
  /// default batch_job_stale_s,
  /// past which the other replicas call such a job failed.
  int give_up_after_s{60};
  ProgressMode progress{ProgressMode::kAuto};
  /// Adds the whole plan to each JSON row (as view "full").
  bool full{false};
  /// Adds the plan to each JSON row in this view: "full" or "compact" (api::parse_plan_view);
  /// nullopt = none (unless `full`).
  std::optional<std::string> view;
  /// "plan" (a plan per recipe) or "min_time" (each strategy's minimum motion time per recipe,
  /// SPEC §9: motion_time_s is the upper end of the search; locally with the min-time answers of
  /// the cache file, or through --server). Default "plan".
  std::string mode{"plan"};
};

/// Runs the batch; returns 0 when every row was planned, kExitSomeRowsFailed when some rows
/// carry an error (the table is still complete), kExitInvalidInput for an unreadable table or bad
/// options, kExitFailure when the run stopped (server unreachable, output not writable).
int run_batch_command(const BatchCommandOptions& options);

}  // namespace slosh::service
