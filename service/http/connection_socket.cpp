#include "http/connection_socket.hpp"

#include <sys/socket.h>

#include <cstring>

namespace slosh::service {

namespace {

struct KnownSocket {
  int fd{-1};
  sockaddr_storage peer{};
  socklen_t length{0};
};
thread_local KnownSocket known_socket;

// Whether `fd` is still connected to the peer it was found with.
bool same_peer(int fd, const KnownSocket& known) {
  sockaddr_storage peer{};
  socklen_t length = sizeof peer;
  return fd >= 0 && getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &length) == 0 &&
         length == known.length && std::memcmp(&peer, &known.peer, length) == 0;
}

}  // namespace

int connection_socket(const ConnectionReaper& reaper, const std::string& peer) {
  KnownSocket& known = known_socket;
  if (same_peer(known.fd, known)) return known.fd;
  known = KnownSocket{};
  const int fd = reaper.socket_of(peer);
  if (fd < 0) return -1;
  known.length = sizeof known.peer;
  if (getpeername(fd, reinterpret_cast<sockaddr*>(&known.peer), &known.length) != 0) return -1;
  known.fd = fd;
  return fd;
}

}  // namespace slosh::service
