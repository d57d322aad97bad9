#pragma once
// A real `slosh serve` on a free loopback port for the service and CLI tests.

#include <httplib.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "support/process.hpp"

namespace slosh::test {

/// The value of a Prometheus sample line `name{labels} value` in a /metrics text; -1 when absent.
inline double metric(const std::string& text, const std::string& series) {
  const std::string line = "\n" + series + " ";  // a sample line, not a # HELP line
  const auto at = text.find(line);
  if (at == std::string::npos) return -1.0;
  return std::stod(text.substr(at + line.size()));
}

/// A running `slosh serve` with its own directory (cache file, port file, logs).
class Server {
 public:
  explicit Server(std::vector<std::string> extra = {}, const TempDir* shared_dir = nullptr)
      : dir_(shared_dir != nullptr ? *shared_dir : own_dir_) {
    std::vector<std::string> args{"serve", "--host",      "127.0.0.1",         "--port",
                                  "0",     "--port-file", port_file().string()};
    // The SQLite file of this directory, unless `extra` names the cache (e.g. a Redis URL).
    if (std::find(extra.begin(), extra.end(), "--cache") == extra.end()) {
      args.insert(args.end(), {"--cache", cache_file().string()});
    }
    args.insert(args.end(), extra.begin(), extra.end());
    write_file(dir_ / "stdin", "");
    child_ = std::make_unique<Child>(
        test::spawn(args, dir_ / "stdin", dir_ / "stdout", dir_ / "stderr"));
    std::filesystem::remove(port_file());
    port_ = test::wait_for_port(port_file(), *child_, std::chrono::seconds(10));
  }
  [[nodiscard]] int port() const { return port_; }
  [[nodiscard]] std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  [[nodiscard]] std::filesystem::path cache_file() const { return dir_ / "plans.sqlite"; }
  [[nodiscard]] std::filesystem::path port_file() const { return dir_ / "port"; }
  [[nodiscard]] std::string log() const {
    return read_file(dir_ / "stdout") + read_file(dir_ / "stderr");
  }
  [[nodiscard]] httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_connection_timeout(5, 0);
    c.set_read_timeout(60, 0);
    return c;
  }
  Child& child() { return *child_; }
  /// SIGTERM and the exit code (nullopt when still running after 20 s).
  std::optional<int> stop() {
    ::kill(child_->pid(), SIGTERM);
    return child_->wait_for(std::chrono::seconds(20));
  }

 private:
  TempDir own_dir_;
  const TempDir& dir_;
  std::unique_ptr<Child> child_;
  int port_{0};
};

/// The sample `series` of `server`'s /metrics; -1 when absent, -2 when /metrics did not answer.
inline double metric_of(const Server& server, const std::string& series) {
  const auto r = server.client().Get("/metrics");
  return r ? metric(r->body, series) : -2.0;
}

/// Polls every 20 ms until `done` holds; false after `limit`, which only a hung service reaches
/// (the conditions are about counters and states, not about how fast they move).
inline bool wait_until(const std::function<bool()>& done,
                       std::chrono::seconds limit = std::chrono::seconds(120)) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < until) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return done();
}

}  // namespace slosh::test
