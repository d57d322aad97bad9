#include "http_server.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <pthread.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "version.hpp"

namespace slosh::service {

namespace {

// Writes the port to `path` atomically (temporary file + rename) so a reader never sees a
// partial number.
bool write_port_file(const std::string& path, int port) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << port << '\n';
    if (!out) return false;
  }
  return std::rename(tmp.c_str(), path.c_str()) == 0;
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

  // SIGINT / SIGTERM are blocked in every thread and taken synchronously by one waiter thread,
  // which stops the server outside any signal handler.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

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
  std::atomic<bool> finished{false};
  std::thread waiter([&] {
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    if (finished) return;
    spdlog::info("signal {} received, stopping", signal_number);
    // A signal that arrives before the accept loop runs must still stop it.
    while (!server.is_running() && !finished) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    server.stop();
  });
  if (!port_file.empty() && !write_port_file(port_file, port)) {
    spdlog::error("cannot write the port file {}", port_file);
  }
  spdlog::info("slosh {} listening on http://{}:{}", kVersion, config.host, port);
  const bool ok = server.listen_after_bind();
  finished = true;
  pthread_kill(waiter.native_handle(), SIGTERM);  // wakes sigwait if no signal came
  waiter.join();
  spdlog::info("slosh stopped");
  return ok ? 0 : 1;
}

}  // namespace slosh::service
