#pragma once
// The HTTP service. The HTTP library stays behind this interface.

#include <string>

namespace slosh::service {

/// Server settings (defaults are the embedded defaults of `make run`).
struct ServerConfig {
  std::string host{"127.0.0.1"};  ///< bind address
  int port{8080};                 ///< TCP port; 0 picks a free one
};

/// Runs the server until SIGINT/SIGTERM; returns the process exit code. When `port_file` is not
/// empty, the bound port is written there once the server listens (used by tests).
int run_server(const ServerConfig& config, const std::string& port_file = "");

}  // namespace slosh::service
