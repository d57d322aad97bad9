#include "http_server.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <csignal>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "version.hpp"

namespace slosh::service {

namespace {

httplib::Server* g_server = nullptr;

void handle_signal(int) {
  if (g_server != nullptr) g_server->stop();
}

}  // namespace

int run_server(const ServerConfig& config, const std::string& port_file) {
  httplib::Server server;
  server.Get("/healthz", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(nlohmann::json{{"status", "ok"}, {"version", kVersion}}.dump(),
                    "application/json");
  });
  server.Get("/readyz", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(nlohmann::json{{"status", "ready"}}.dump(), "application/json");
  });

  int port = config.port;
  if (port == 0) {
    port = server.bind_to_any_port(config.host);
  } else if (!server.bind_to_port(config.host, port)) {
    port = -1;
  }
  if (port < 0) {
    spdlog::error("cannot bind {}:{}", config.host, config.port);
    return 1;
  }
  if (!port_file.empty()) std::ofstream(port_file) << port << '\n';
  g_server = &server;
  std::signal(SIGINT, handle_signal);
  std::signal(SIGTERM, handle_signal);
  spdlog::info("slosh {} listening on http://{}:{}", kVersion, config.host, port);
  const bool ok = server.listen_after_bind();
  g_server = nullptr;
  spdlog::info("slosh stopped");
  return ok ? 0 : 1;
}

}  // namespace slosh::service
