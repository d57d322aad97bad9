#pragma once
// nginx (Debian nginx-light) in front of loopback replicas, started by the test: deploy/nginx.conf
// itself with its upstream servers, listen line and paths replaced (nginx_test_config), run in the
// foreground (-g 'daemon off;') from a private directory that holds the config, the pid file, the
// logs and the temporary files, so no root is needed (as root, the workers run as root too: the
// directory is private to the test's user).

#include <httplib.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <optional>
#include <regex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "support/process.hpp"

namespace slosh::test {

inline const char* kNginx = "/usr/sbin/nginx";

/// A TCP port that was free on 127.0.0.1 a moment ago (bound to port 0, then closed).
inline int free_loopback_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof addr;
  int port = 0;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0) {
    port = ntohs(addr.sin_port);
  }
  ::close(fd);
  return port;
}

/// deploy/nginx.conf (`deployed`) for a test: the upstream's servers become 127.0.0.1:`ports`
/// (with the deployed max_fails/fail_timeout), the server listens on 127.0.0.1:`listen_port`,
/// the pid file and temporary paths move into `dir`, one worker; as root, `user root;` keeps the
/// worker able to use the private directory. `unlimited` drops the per-client limit_req and
/// limit_conn (the load script's single client would otherwise get 429 beyond 50 requests/s).
inline std::string nginx_test_config(std::string deployed, const std::vector<int>& ports,
                                     int listen_port, const std::string& dir,
                                     bool unlimited = false) {
  const std::regex server_line(R"(\n\s*server\s+slosh-\d+:\d+([^;]*);)");
  std::smatch first;
  if (!std::regex_search(deployed, first, server_line)) {
    throw std::runtime_error("deploy/nginx.conf has no `server slosh-N:port` upstream lines");
  }
  const std::string options = first[1];
  std::string servers;
  for (const int p : ports) {
    servers += "\n        server 127.0.0.1:" + std::to_string(p) + options + ";";
  }
  deployed = std::regex_replace(deployed, server_line, "");
  deployed.replace(deployed.find("keepalive 32;"), 0, servers.substr(1) + "\n        ");
  deployed = std::regex_replace(deployed, std::regex(R"(listen 8080;)"),
                                "listen 127.0.0.1:" + std::to_string(listen_port) + ";");
  deployed = std::regex_replace(deployed, std::regex(R"(/tmp/nginx)"), dir + "/nginx");
  deployed =
      std::regex_replace(deployed, std::regex(R"(worker_processes auto;)"), "worker_processes 1;");
  if (unlimited) {
    deployed = std::regex_replace(deployed, std::regex(R"(\n\s*limit_(req|conn) [^;]*;)"), "");
  }
  if (::geteuid() == 0) deployed = "user root;\n" + deployed;
  return deployed;
}

/// The text of deploy/nginx.conf in the source tree.
inline std::string deployed_nginx_config() {
  return read_file(std::string(SLOSH_SOURCE_DIR) + "/deploy/nginx.conf");
}

/// `nginx -t` of a config text in `dir`; nginx's exit code and output.
inline RunResult nginx_check(const std::string& config, const TempDir& dir) {
  write_file(dir / "nginx.conf", config);
  const std::string command = std::string(kNginx) + " -t -q -p " + (dir / "").string() + " -e " +
                              (dir / "error.log").string() + " -c " +
                              (dir / "nginx.conf").string() + " > " + (dir / "t.out").string() +
                              " 2>&1";
  RunResult r;
  r.exit_code = std::system(command.c_str());
  r.out = read_file(dir / "t.out");
  return r;
}

/// nginx in front of loopback ports, stopped (SIGTERM to its process group, then SIGKILL) when
/// destroyed.
class NginxProxy {
 public:
  explicit NginxProxy(const std::vector<int>& upstream_ports, bool unlimited = false) {
    for (int attempt = 0; attempt < 5 && pid_ <= 0; ++attempt) {
      port_ = free_loopback_port();
      write_file(dir_ / "nginx.conf",
                 nginx_test_config(deployed_nginx_config(), upstream_ports, port_,
                                   (dir_ / "").string() + ".", unlimited));
      launch();
      if (!wait_listening()) stop();
    }
    if (pid_ <= 0) throw std::runtime_error("nginx did not start:\n" + log());
  }
  NginxProxy(const NginxProxy&) = delete;
  NginxProxy& operator=(const NginxProxy&) = delete;
  ~NginxProxy() { stop(); }

  [[nodiscard]] int port() const { return port_; }
  [[nodiscard]] std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  [[nodiscard]] httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_connection_timeout(5, 0);
    c.set_read_timeout(60, 0);
    return c;
  }
  /// nginx's stderr (error log) and stdout (access log: ... upstream=<address> ...).
  [[nodiscard]] std::string log() const {
    return read_file(dir_ / "stderr") + read_file(dir_ / "stdout");
  }

  /// Stops nginx: SIGTERM (fast shutdown) to the group, SIGKILL after 10 s.
  void stop() {
    if (pid_ <= 0) return;
    ::kill(-pid_, SIGTERM);
    Child child(pid_);
    if (!child.wait_for(std::chrono::seconds(10))) ::kill(-pid_, SIGKILL);
    pid_ = -1;  // `child` reaps it
  }

 private:
  void launch() {
    const std::string conf = (dir_ / "nginx.conf").string();
    const std::string prefix = (dir_ / "").string();
    const std::string error_log = (dir_ / "error.log").string();
    pid_ = ::fork();
    if (pid_ == 0) {
      ::setpgid(0, 0);  // its own group: the workers are stopped with the master
      const int out = ::open((dir_ / "stdout").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      const int err = ::open((dir_ / "stderr").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      ::dup2(out, STDOUT_FILENO);
      ::dup2(err, STDERR_FILENO);
      ::execl(kNginx, kNginx, "-p", prefix.c_str(), "-e", error_log.c_str(), "-c", conf.c_str(),
              "-g", "daemon off;", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    if (pid_ > 0) ::setpgid(pid_, pid_);
  }

  bool wait_listening() {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return false;
      }
      httplib::Client c("127.0.0.1", port_);
      c.set_connection_timeout(0, 200000);
      if (c.Get("/nginx-probe")) return true;  // any answer: nginx listens
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

  TempDir dir_;
  int port_{0};
  pid_t pid_{-1};
};

}  // namespace slosh::test
