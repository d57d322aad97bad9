#pragma once
// The HTTP service. The HTTP library stays behind this interface.

#include <string>

#include "config/server_config.hpp"

namespace slosh::service {

/// Runs the server until SIGINT/SIGTERM; returns the process exit code. When `port_file` is not
/// empty, the bound port is written there once the server listens (used by tests). On a signal
/// it stops accepting, finishes the requests and solves in flight, then returns 0.
int run_server(const ServerConfig& config, const std::string& port_file = "");

}  // namespace slosh::service
