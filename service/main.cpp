// `slosh`: the command-line entry point (serve, plan, simulate, batch, export).

#include <CLI/CLI.hpp>

#include <iostream>
#include <optional>
#include <string>

#include "batch_command.hpp"
#include "cli_commands.hpp"
#include "config.hpp"
#include "export_command.hpp"
#include "http_server.hpp"
#include "version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"slosh: anti-sloshing motion-law planner for packaging machines"};
  app.set_version_flag("--version", std::string("slosh ") + slosh::kVersion);
  app.require_subcommand(1);

  // Precedence: embedded defaults < --config file < SLOSH_* environment < flags.
  const slosh::service::ServerConfig defaults;
  std::string config_path;
  std::optional<std::string> host;
  std::optional<int> port;
  std::string port_file;
  auto* serve = app.add_subcommand("serve", "Run the HTTP/JSON service");
  serve->add_option("--config", config_path, "JSON config file (see config/slosh.json)");
  serve->add_option("--host", host, "Bind address [default " + defaults.host + "; env SLOSH_HOST]");
  serve
      ->add_option("--port", port,
                   "TCP port, 0 = any free port [default " + std::to_string(defaults.port) +
                       "; env SLOSH_PORT]")
      ->check(CLI::Range(0, 65535));
  serve->add_option("--port-file", port_file, "Write the bound port to this file");
  std::optional<std::size_t> workers, queue;
  std::optional<std::string> cache;
  serve
      ->add_option("--workers", workers,
                   "Solve workers, 0 = the cores [default 0; env SLOSH_WORKERS]")
      ->check(CLI::Range(0, 1024));
  serve
      ->add_option("--queue", queue,
                   "Solves that may wait; beyond, 503 [default " + std::to_string(defaults.queue) +
                       "; env SLOSH_QUEUE]")
      ->check(CLI::Range(1, 100000));
  serve->add_option("--cache", cache,
                    "SQLite file of the plan cache, \"\" = memory only [default " +
                        defaults.cache_path + "; env SLOSH_CACHE]");

  std::string request = "-";
  auto* simulate = app.add_subcommand(
      "simulate", "Simulate a motion law on a format (JSON in, the /v1/simulate response out)");
  simulate->add_option("--request", request, "Request JSON file, or - for stdin")
      ->capture_default_str();

  auto* plan = app.add_subcommand(
      "plan", "Plan the 7-segment law of a format (JSON in, the /v1/plans response out)");
  plan->add_option("--request", request, "Request JSON file, or - for stdin")
      ->capture_default_str();

  slosh::service::BatchCommandOptions batch_options;
  std::string batch_progress = "auto";
  auto* batch = app.add_subcommand(
      "batch", "Plan a recipe table (CSV or JSON lines in, a plan table as CSV or JSON out)");
  batch->add_option("--in", batch_options.in, "Recipe table file, or - for stdin")
      ->capture_default_str();
  batch->add_option("--out", batch_options.out, "Plan table file, or - for stdout")
      ->capture_default_str();
  batch
      ->add_option("--in-format", batch_options.in_format,
                   "Recipe table format (auto: from the extension .csv/.jsonl/.ndjson/.json)")
      ->check(CLI::IsMember({"auto", "csv", "jsonl", "json"}))
      ->capture_default_str();
  batch
      ->add_option("--out-format", batch_options.out_format,
                   "Plan table format (auto: from the extension; csv for -)")
      ->check(CLI::IsMember({"auto", "csv", "jsonl", "json"}))
      ->capture_default_str();
  batch->add_option("--config", config_path, "JSON config file (workers, cache, solve budget)");
  batch
      ->add_option("--workers", workers,
                   "Parallel solves, 0 = the cores [default 0; env SLOSH_WORKERS]")
      ->check(CLI::Range(0, 1024));
  batch->add_option("--cache", cache,
                    "SQLite plan cache shared with `slosh serve`, \"\" = none [default " +
                        defaults.cache_path + "; env SLOSH_CACHE]");
  batch->add_option(
      "--server", batch_options.server,
      "Send the table to a running service (http://host:port) instead of solving here");
  batch->add_option("--chunk", batch_options.chunk, "Recipes per request in --server mode")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  batch
      ->add_option("--progress", batch_progress,
                   "Progress bar on stderr: auto (when stderr is a terminal), always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}))
      ->capture_default_str();
  batch->add_flag("--full", batch_options.full, "JSON output: add the whole plan to each row");

  slosh::service::ExportCommandOptions export_options;
  auto* export_cmd = app.add_subcommand(
      "export", "Cam table (t, position, velocity, acceleration, jerk) of a plan or a law as CSV");
  export_cmd
      ->add_option("--request", export_options.request,
                   "Plan request (solved or read from the cache) or simulate request with \"law\"; "
                   "- for stdin")
      ->capture_default_str();
  export_cmd->add_option("--out", export_options.out, "Cam table CSV file, or - for stdout")
      ->required();
  export_cmd->add_option("--period-ms", export_options.period_ms, "Controller cycle [ms]")
      ->capture_default_str();
  export_cmd->add_option("--segments", export_options.segments,
                         "Also write the 7-segment table (durations, jerks, A, B) to this CSV");
  export_cmd->add_flag("--allow-infeasible", export_options.allow_infeasible,
                       "Export an infeasible or time-limited plan (its best reachable law) too");
  export_cmd->add_option("--config", config_path, "JSON config file (cache, solve budget)");
  export_cmd->add_option("--cache", cache,
                         "SQLite plan cache shared with `slosh serve`, \"\" = none [default " +
                             defaults.cache_path + "; env SLOSH_CACHE]");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : slosh::service::kExitInvalidInput;
  }
  slosh::service::ServerConfig server = defaults;
  if (*serve || *batch || *export_cmd) {
    try {
      if (!config_path.empty()) slosh::service::apply_config_file(config_path, server);
      slosh::service::apply_environment(slosh::service::slosh_environment(), server);
    } catch (const std::exception& e) {
      std::cerr << "slosh " << app.get_subcommands().front()->get_name() << ": " << e.what()
                << '\n';
      return slosh::service::kExitInvalidInput;
    }
    if (workers) server.workers = *workers;
    if (cache) server.cache_path = *cache;
  }
  if (*serve) {
    if (host) server.host = *host;
    if (port) server.port = *port;
    if (queue) server.queue = *queue;
    return slosh::service::run_server(server, port_file);
  }
  if (*simulate) return slosh::service::run_simulate_command(request);
  if (*plan) return slosh::service::run_plan_command(request);
  if (*batch) {
    batch_options.config = server;
    batch_options.progress = batch_progress == "always"  ? slosh::service::ProgressMode::kAlways
                             : batch_progress == "never" ? slosh::service::ProgressMode::kNever
                                                         : slosh::service::ProgressMode::kAuto;
    return slosh::service::run_batch_command(batch_options);
  }
  if (*export_cmd) {
    export_options.config = server;
    return slosh::service::run_export_command(export_options);
  }
  return slosh::service::kExitInvalidInput;
}
