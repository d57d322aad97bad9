// `slosh`: the command-line entry point (serve, simulate).

#include <CLI/CLI.hpp>

#include <iostream>

#include "cli_commands.hpp"
#include "http_server.hpp"
#include "version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"slosh: anti-sloshing motion-law planner for packaging machines"};
  app.set_version_flag("--version", std::string("slosh ") + slosh::kVersion);
  app.require_subcommand(1);

  slosh::service::ServerConfig server;
  std::string port_file;
  auto* serve = app.add_subcommand("serve", "Run the HTTP/JSON service");
  serve->add_option("--host", server.host, "Bind address")->capture_default_str();
  serve->add_option("--port", server.port, "TCP port (0 = any free port)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  serve->add_option("--port-file", port_file, "Write the bound port to this file");

  std::string request = "-";
  auto* simulate = app.add_subcommand(
      "simulate", "Simulate a motion law on a format (JSON in, the /v1/simulate response out)");
  simulate->add_option("--request", request, "Request JSON file, or - for stdin")
      ->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : slosh::service::kExitInvalidInput;
  }
  if (*serve) return slosh::service::run_server(server, port_file);
  if (*simulate) return slosh::service::run_simulate_command(request);
  return slosh::service::kExitInvalidInput;
}
