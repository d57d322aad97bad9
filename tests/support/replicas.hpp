#pragma once
// Several real `slosh serve` replicas on loopback for the cross-replica tests: each on its own
// port (chosen by the system at the first start, kept across restarts so a proxy's upstream stays
// valid) with its own directory (port file, logs, SQLite cache unless the extra arguments name a
// --cache), started with given extra arguments, waited for until /readyz answers 200, killed
// (any signal) and restarted.

#include <httplib.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh::test {

class Replica {
 public:
  /// Starts `slosh serve --replica-id id` plus `extra` and waits until it is ready.
  explicit Replica(std::string id, std::vector<std::string> extra = {})
      : id_(std::move(id)), extra_(std::move(extra)) {
    start();
  }
  Replica(const Replica&) = delete;
  Replica& operator=(const Replica&) = delete;

  /// (Re)starts the process on this replica's port (a free one the first time) and waits up to
  /// 20 s for /readyz to answer 200; throws when it does not.
  void start() {
    if (child_) throw std::logic_error("replica " + id_ + " is running");
    std::vector<std::string> args{"serve",
                                  "--host",
                                  "127.0.0.1",
                                  "--port",
                                  std::to_string(port_),
                                  "--port-file",
                                  (dir_ / "port").string(),
                                  "--replica-id",
                                  id_};
    if (std::find(extra_.begin(), extra_.end(), "--cache") == extra_.end()) {
      args.insert(args.end(), {"--cache", (dir_ / "plans.sqlite").string()});
    }
    args.insert(args.end(), extra_.begin(), extra_.end());
    std::filesystem::remove(dir_ / "port");
    write_file(dir_ / "stdin", "");
    ++starts_;
    child_ = std::make_unique<Child>(
        spawn(args, dir_ / "stdin", log_path("stdout"), log_path("stderr")));
    const int port = wait_for_port(dir_ / "port", *child_, std::chrono::seconds(20));
    if (port == 0) throw std::runtime_error("replica " + id_ + " did not start:\n" + log());
    port_ = port;
    if (!wait_ready(std::chrono::seconds(20))) {
      throw std::runtime_error("replica " + id_ + " not ready:\n" + log());
    }
  }

  /// Sends `signal` (SIGKILL: a crash; SIGTERM: a graceful stop) and waits up to 30 s for the
  /// exit; the exit code (128 + signal when killed), nullopt when it did not exit.
  std::optional<int> kill(int signal = SIGKILL) {
    if (!child_) return std::nullopt;
    ::kill(child_->pid(), signal);
    const std::optional<int> code = child_->wait_for(std::chrono::seconds(30));
    if (code) child_.reset();
    return code;
  }

  /// Polls GET /readyz until it answers 200 (ready or degraded) or `timeout` passes.
  bool wait_ready(std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      httplib::Client c = client();
      c.set_connection_timeout(1, 0);
      if (const auto r = c.Get("/readyz"); r && r->status == 200) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

  [[nodiscard]] bool running() const { return child_ != nullptr; }
  [[nodiscard]] const std::string& id() const { return id_; }
  [[nodiscard]] int port() const { return port_; }
  [[nodiscard]] pid_t pid() const { return child_ ? child_->pid() : -1; }
  [[nodiscard]] std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  [[nodiscard]] httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_connection_timeout(5, 0);
    c.set_read_timeout(60, 0);
    return c;
  }
  /// Everything every start of this replica wrote to stdout and stderr.
  [[nodiscard]] std::string log() const {
    std::string text;
    for (int i = 1; i <= starts_; ++i) {
      text += read_file(dir_ / ("stdout." + std::to_string(i))) +
              read_file(dir_ / ("stderr." + std::to_string(i)));
    }
    return text;
  }
  [[nodiscard]] std::filesystem::path dir() const { return dir_ / ""; }

 private:
  std::filesystem::path log_path(const std::string& stream) const {
    return dir_ / (stream + "." + std::to_string(starts_));
  }

  TempDir dir_;
  std::string id_;
  std::vector<std::string> extra_;
  int port_{0};
  int starts_{0};
  std::unique_ptr<Child> child_;
};

/// `n` replicas named `prefix`-1 ... `prefix`-n with the same extra arguments, started one after
/// the other (each ready before the next starts).
class ReplicaSet {
 public:
  ReplicaSet(std::size_t n, const std::vector<std::string>& extra = {},
             const std::string& prefix = "replica") {
    for (std::size_t i = 1; i <= n; ++i) {
      replicas_.push_back(std::make_unique<Replica>(prefix + "-" + std::to_string(i), extra));
    }
  }
  [[nodiscard]] std::size_t size() const { return replicas_.size(); }
  Replica& operator[](std::size_t i) { return *replicas_.at(i); }
  [[nodiscard]] std::vector<int> ports() const {
    std::vector<int> ports;
    for (const auto& r : replicas_) ports.push_back(r->port());
    return ports;
  }

 private:
  std::vector<std::unique_ptr<Replica>> replicas_;
};

/// True once both replicas' logs (each started with the same --replica-id) say that another
/// live replica uses their id, within 20 s.
inline bool both_say_their_id_is_shared(Replica& first, Replica& second) {
  const std::string warning =
      "another live replica uses the replica id '" + first.id() + "' on this Redis";
  return wait_until(
      [&] {
        return first.log().find(warning) != std::string::npos &&
               second.log().find(warning) != std::string::npos;
      },
      std::chrono::seconds(20));
}

}  // namespace slosh::test
