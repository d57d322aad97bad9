#include "http/connection_reaper.hpp"

#include <dirent.h>
#include <netdb.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <optional>
#include <set>

namespace slosh::service {

namespace {

// "address:port" of a socket address, as the HTTP library names a request's peer.
std::optional<std::string> peer_name(const sockaddr_storage& address, socklen_t length) {
  char host[NI_MAXHOST];
  char service[NI_MAXSERV];
  if (getnameinfo(reinterpret_cast<const sockaddr*>(&address), length, host, sizeof host, service,
                  sizeof service, NI_NUMERICHOST | NI_NUMERICSERV) != 0) {
    return std::nullopt;
  }
  return std::string(host) + ":" + service;
}

int local_port(const sockaddr_storage& address) {
  if (address.ss_family == AF_INET) {
    return ntohs(reinterpret_cast<const sockaddr_in&>(address).sin_port);
  }
  if (address.ss_family == AF_INET6) {
    return ntohs(reinterpret_cast<const sockaddr_in6&>(address).sin6_port);
  }
  return -1;
}

// The peer of `fd` when it is a TCP connection accepted on local `port`.
std::optional<std::string> connection_peer(int fd, int port) {
  struct stat st {};
  if (fstat(fd, &st) != 0 || !S_ISSOCK(st.st_mode)) return std::nullopt;
  sockaddr_storage local{};
  socklen_t length = sizeof local;
  if (getsockname(fd, reinterpret_cast<sockaddr*>(&local), &length) != 0 ||
      local_port(local) != port) {
    return std::nullopt;
  }
  sockaddr_storage remote{};
  length = sizeof remote;
  if (getpeername(fd, reinterpret_cast<sockaddr*>(&remote), &length) != 0) return std::nullopt;
  return peer_name(remote, length);  // the listening socket has no peer
}

}  // namespace

ConnectionReaper::ConnectionReaper(int port, Clock::duration deadline, Clock::duration interval)
    : port_(port), deadline_(deadline), interval_(interval), thread_([this] { watch(); }) {}

ConnectionReaper::~ConnectionReaper() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void ConnectionReaper::begin_request(const std::string& peer) {
  std::lock_guard lock(mutex_);
  ++in_request_[peer];
}

void ConnectionReaper::end_request(const std::string& peer) {
  std::lock_guard lock(mutex_);
  if (auto it = in_request_.find(peer); it != in_request_.end() && --it->second <= 0) {
    in_request_.erase(it);
  }
  answered_[peer] = Clock::now();
}

void ConnectionReaper::close_idle_now() {
  {
    std::lock_guard lock(mutex_);
    closing_all_ = true;
  }
  wake_.notify_all();
}

std::uint64_t ConnectionReaper::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

void ConnectionReaper::watch() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    lock.unlock();
    scan();
    lock.lock();
    wake_.wait_for(lock, closing_all_ ? std::chrono::milliseconds(50) : interval_,
                   [this] { return stopping_; });
  }
}

std::map<int, std::string> ConnectionReaper::connections() const {
  std::map<int, std::string> live;
  if (DIR* dir = opendir("/proc/self/fd")) {
    while (const dirent* entry = readdir(dir)) {
      char* end = nullptr;
      const long fd = std::strtol(entry->d_name, &end, 10);
      if (end == entry->d_name || *end != '\0' || fd == dirfd(dir)) continue;
      if (auto peer = connection_peer(static_cast<int>(fd), port_)) {
        live.emplace(static_cast<int>(fd), *peer);
      }
    }
    closedir(dir);
  }
  return live;
}

bool ConnectionReaper::peer_finished(int fd) {
  char byte = 0;
  // 0: the peer sent its FIN (nothing more will come); -1 with EAGAIN: still connected.
  return ::recv(fd, &byte, 1, MSG_PEEK | MSG_DONTWAIT) == 0;
}

bool ConnectionReaper::closed_by_peer(const std::string& peer) const {
  const int fd = socket_of(peer);
  return fd < 0 || peer_finished(fd);  // its socket is gone, or the peer sent its FIN
}

int ConnectionReaper::socket_of(const std::string& peer) const {
  for (const auto& [fd, name] : connections()) {
    if (name == peer) return fd;
  }
  return -1;
}

void ConnectionReaper::scan() {
  const std::map<int, std::string> live = connections();
  const Clock::time_point now = Clock::now();
  std::lock_guard lock(mutex_);
  for (auto it = connections_.begin(); it != connections_.end();) {
    const auto found = live.find(it->first);
    it = found == live.end() || found->second != it->second.peer ? connections_.erase(it)
                                                                 : std::next(it);
  }
  std::set<std::string> peers;
  for (const auto& [fd, peer] : live) {
    peers.insert(peer);
    const auto it = connections_.try_emplace(fd, Connection{peer, now}).first;
    if (it->second.shut || in_request_.contains(peer)) continue;
    Clock::time_point since = it->second.waiting_since;
    if (auto answered = answered_.find(peer); answered != answered_.end()) {
      since = std::max(since, answered->second);
    }
    if (!closing_all_ && now - since <= deadline_) continue;
    // The descriptor may have been closed and reused since the listing: same peer or leave it.
    if (connection_peer(fd, port_) != peer) continue;
    ::shutdown(fd, SHUT_RDWR);  // the library's blocked read returns and it closes the socket
    it->second.shut = true;
    if (!closing_all_) {
      spdlog::warn("{}: no complete request within {} s: connection closed", peer,
                   std::chrono::duration<double>(deadline_).count());
    }
    ++closed_;
  }
  for (auto it = answered_.begin(); it != answered_.end();) {
    it = peers.contains(it->first) ? std::next(it) : answered_.erase(it);
  }
}

}  // namespace slosh::service
