#pragma once
// A real `redis-server` on a free loopback port for the tests (and benchmarks) of the shared cache
// and the job store: no persistence (--save "" --appendonly no), its own temporary directory,
// killed on scope exit. It can be stopped (SIGSTOP: commands then time out), continued, killed
// and restarted on the same port.
//
// Without a redis-server binary the constructor throws: the tests that need one FAIL with that
// message (scripts/install-deps.sh installs Debian's redis-server), they are not skipped.

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace slosh::test {

class RedisServer {
 public:
  /// Starts redis-server on a free loopback port (`extra`: more arguments, e.g. --requirepass);
  /// throws std::runtime_error when there is no redis-server binary or it does not answer PING
  /// within 10 s.
  explicit RedisServer(std::vector<std::string> extra = {})
      : binary_(find_binary()), extra_(std::move(extra)) {
    std::string pattern = (std::filesystem::temp_directory_path() / "slosh_redis_XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    dir_ = pattern;
    port_ = free_port();
    start();
  }
  ~RedisServer() {
    kill();
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  RedisServer(const RedisServer&) = delete;
  RedisServer& operator=(const RedisServer&) = delete;

  [[nodiscard]] int port() const { return port_; }
  /// redis://127.0.0.1:<port>/<db>
  [[nodiscard]] std::string url(int db = 0) const {
    return "redis://127.0.0.1:" + std::to_string(port_) + "/" + std::to_string(db);
  }
  [[nodiscard]] pid_t pid() const { return pid_; }

  /// (Re)starts the server on the same port (empty: nothing is persisted) and waits for PING.
  void start() {
    if (pid_ > 0) return;
    const std::string log = (dir_ / "redis.log").string();
    std::vector<std::string> args{binary_,  "--port",       std::to_string(port_),
                                  "--bind", "127.0.0.1",    "--save",
                                  "",       "--appendonly", "no",
                                  "--dir",  dir_.string(),  "--daemonize",
                                  "no",     "--logfile",    log};
    args.insert(args.end(), extra_.begin(), extra_.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_ = ::fork();
    if (pid_ == 0) {
      const int null = ::open("/dev/null", O_RDWR);
      if (null >= 0) {
        ::dup2(null, STDIN_FILENO);
        ::dup2(null, STDOUT_FILENO);
        ::dup2(null, STDERR_FILENO);
      }
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!ping()) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        throw std::runtime_error("redis-server exited at start; its log:\n" + read_log());
      }
      if (std::chrono::steady_clock::now() > deadline) {
        throw std::runtime_error("redis-server on port " + std::to_string(port_) +
                                 " does not answer PING after 10 s; its log:\n" + read_log());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  /// SIGKILL (a crash: connections are reset) and reap.
  void kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGCONT);  // a stopped server must be able to die
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }
  /// SIGSTOP: the server keeps its connections but answers nothing (commands time out).
  void pause() const { ::kill(pid_, SIGSTOP); }
  /// SIGCONT after pause().
  void resume() const { ::kill(pid_, SIGCONT); }

  /// Whether the server answers PING within 200 ms (a raw RESP exchange, independent of the
  /// client under test).
  [[nodiscard]] bool ping() const {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return false;
    timeval tv{0, 200000};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port_));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bool ok = false;
    if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
        ::send(fd, "PING\r\n", 6, MSG_NOSIGNAL) == 6) {
      char buffer[16] = {};
      const ssize_t n = ::recv(fd, buffer, sizeof buffer - 1, 0);
      // +PONG, or -NOAUTH from a server with a password: it is up either way.
      ok = n >= 5 && (std::string(buffer, 5) == "+PONG" || std::string(buffer, 5) == "-NOAU");
    }
    ::close(fd);
    return ok;
  }

  [[nodiscard]] std::string read_log() const {
    std::ifstream in(dir_ / "redis.log");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

 private:
  static std::string find_binary() {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(std::string(path != nullptr ? path : "") + ":/usr/bin:/usr/sbin");
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
      const std::string candidate = dir + "/redis-server";
      if (!dir.empty() && ::access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    throw std::runtime_error(
        "redis-server was not found on PATH or in /usr/bin: the Redis tests need a real server "
        "(Debian package redis-server; scripts/install-deps.sh installs it)");
  }

  static int free_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof addr;
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &length) != 0) {
      if (fd >= 0) ::close(fd);
      throw std::runtime_error("no free loopback port for redis-server");
    }
    ::close(fd);
    return ntohs(addr.sin_port);
  }

  std::string binary_;
  std::vector<std::string> extra_;
  std::filesystem::path dir_;
  int port_{0};
  pid_t pid_{-1};
};

}  // namespace slosh::test
