#pragma once
// A TCP relay on a free loopback port in front of a real server (a redis-server), which can be
// told to hold the requests that contain a given text (e.g. "HMGET", the job store's read of
// result rows) for a while before passing them on: a store that stalls during one kind of
// command only, so that a test can make a replica's read of a job's rows time out while its read
// of the job's record answers. Everything else is passed on untouched, both ways.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace slosh::test {

class StallingRelay {
 public:
  /// Listens on a free loopback port and relays every connection to 127.0.0.1:`target_port`.
  explicit StallingRelay(int target_port) : target_port_(target_port) {
    listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
    const int yes = 1;
    ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    if (::bind(listener_, reinterpret_cast<sockaddr*>(&addr), len) != 0 ||
        ::listen(listener_, 64) != 0 ||
        ::getsockname(listener_, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
      throw std::runtime_error("StallingRelay: cannot listen on loopback");
    }
    port_ = ntohs(addr.sin_port);
    acceptor_ = std::thread([this] { accept_loop(); });
  }
  StallingRelay(const StallingRelay&) = delete;
  StallingRelay& operator=(const StallingRelay&) = delete;
  ~StallingRelay() {
    stopping_ = true;
    ::shutdown(listener_, SHUT_RDWR);
    ::close(listener_);
    acceptor_.join();
    {
      const std::lock_guard lock(mutex_);
      for (const int fd : sockets_) ::shutdown(fd, SHUT_RDWR);
    }
    for (std::thread& t : pumps_) t.join();
    for (const int fd : sockets_) ::close(fd);
  }

  /// From now on, a request (a chunk a client sends) containing `text` is held for `hold` before
  /// it is passed on; an empty `text` holds nothing.
  void stall_on(const std::string& text, std::chrono::milliseconds hold) {
    const std::lock_guard lock(mutex_);
    stall_text_ = text;
    hold_ = hold;
  }
  /// How many requests were held so far.
  [[nodiscard]] int stalled() const { return stalled_; }

  [[nodiscard]] int port() const { return port_; }
  [[nodiscard]] std::string url(int db = 0) const {
    return "redis://127.0.0.1:" + std::to_string(port_) + "/" + std::to_string(db);
  }

 private:
  void accept_loop() {
    while (!stopping_) {
      const int client = ::accept(listener_, nullptr, nullptr);
      if (client < 0) return;
      const int server = ::socket(AF_INET, SOCK_STREAM, 0);
      sockaddr_in addr{};
      addr.sin_family = AF_INET;
      addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      addr.sin_port = htons(static_cast<std::uint16_t>(target_port_));
      if (::connect(server, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        ::close(client);
        ::close(server);
        continue;
      }
      const std::lock_guard lock(mutex_);
      sockets_.push_back(client);
      sockets_.push_back(server);
      pumps_.emplace_back([this, client, server] { pump(client, server, true); });
      pumps_.emplace_back([this, client, server] { pump(server, client, false); });
    }
  }

  // Copies `from` to `to` until either closes; requests (`requests`: client to server) that
  // contain the stall text are held first.
  void pump(int from, int to, bool requests) {
    std::vector<char> buffer(1 << 16);
    for (;;) {
      const ssize_t n = ::recv(from, buffer.data(), buffer.size(), 0);
      if (n <= 0) break;
      if (requests) hold_if_asked(std::string(buffer.data(), static_cast<std::size_t>(n)));
      for (ssize_t sent = 0; sent < n;) {
        const ssize_t k =
            ::send(to, buffer.data() + sent, static_cast<std::size_t>(n - sent), MSG_NOSIGNAL);
        if (k <= 0) {
          ::shutdown(from, SHUT_RDWR);
          return;
        }
        sent += k;
      }
    }
    ::shutdown(to, SHUT_RDWR);  // the other direction ends too
  }

  void hold_if_asked(const std::string& chunk) {
    std::chrono::milliseconds hold{0};
    {
      const std::lock_guard lock(mutex_);
      if (stall_text_.empty() || chunk.find(stall_text_) == std::string::npos) return;
      hold = hold_;
    }
    ++stalled_;
    std::this_thread::sleep_for(hold);
  }

  const int target_port_;
  int listener_{-1};
  int port_{0};
  std::atomic<bool> stopping_{false};
  std::atomic<int> stalled_{0};
  std::mutex mutex_;
  std::string stall_text_;
  std::chrono::milliseconds hold_{0};
  std::vector<int> sockets_;
  std::vector<std::thread> pumps_;
  std::thread acceptor_;
};

}  // namespace slosh::test
