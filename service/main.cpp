// `slosh`: the command-line entry point (serve, plan, simulate).

#include <CLI/CLI.hpp>

#include <iostream>
#include <optional>
#include <string>

#include "cli_commands.hpp"
#include "config.hpp"
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

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : slosh::service::kExitInvalidInput;
  }
  if (*serve) {
    slosh::service::ServerConfig server = defaults;
    try {
      if (!config_path.empty()) slosh::service::apply_config_file(config_path, server);
      slosh::service::apply_environment(slosh::service::slosh_environment(), server);
    } catch (const std::exception& e) {
      std::cerr << "slosh serve: " << e.what() << '\n';
      return slosh::service::kExitInvalidInput;
    }
    if (host) server.host = *host;
    if (port) server.port = *port;
    if (workers) server.workers = *workers;
    if (queue) server.queue = *queue;
    if (cache) server.cache_path = *cache;
    return slosh::service::run_server(server, port_file);
  }
  if (*simulate) return slosh::service::run_simulate_command(request);
  if (*plan) return slosh::service::run_plan_command(request);
  return slosh::service::kExitInvalidInput;
}
