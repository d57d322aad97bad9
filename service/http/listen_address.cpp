#include "http/listen_address.hpp"

#include <netdb.h>
#include <sys/socket.h>

namespace slosh::service {

std::string bind_failure_message(const std::string& host, int port) {
  const std::string where = "cannot bind " + host + ":" + std::to_string(port);
  // The resolution the HTTP library binds with (getaddrinfo, passive), asked again: when it
  // fails, the address is the problem, not the port.
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  const int error = getaddrinfo(host.c_str(), nullptr, &hints, &found);
  if (found != nullptr) freeaddrinfo(found);
  if (error != 0) {
    return where + ": the host " + host +
           " is not an address (an IPv4 or IPv6 address, or a name that resolves): " +
           gai_strerror(error);
  }
  return where + " (is another slosh or another service using the port?)";
}

}  // namespace slosh::service
