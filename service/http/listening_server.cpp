#include "http/listening_server.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <chrono>

#include "http/connection_stream.hpp"

namespace slosh::service {

namespace {

/// How often a connection waiting for its next request looks whether the server stopped, as the
/// library's own loop does.
constexpr std::chrono::milliseconds kStopCheck{10};

}  // namespace

bool ListeningServer::raise_backlog() {
  return ::listen(svr_sock_, SOMAXCONN) == 0;
}

bool ListeningServer::process_and_close_socket(socket_t sock) {
  bool ok = false;
  {
    ConnectionStream stream(
        sock, timeval{read_timeout_sec_, static_cast<suseconds_t>(read_timeout_usec_)},
        timeval{write_timeout_sec_, static_cast<suseconds_t>(write_timeout_usec_)});
    const auto running = [this] { return svr_sock_ != INVALID_SOCKET; };
    for (std::size_t left = keep_alive_max_count_; left > 0; --left) {
      if (!stream.wait_for_request(std::chrono::seconds(keep_alive_timeout_sec_), kStopCheck,
                                   running)) {
        break;
      }
      stream.begin_request();
      bool closed = false;
      ok = process_request(stream, left == 1, closed, nullptr);
      ok = stream.flush() && ok;
      // The library reads on after a reply that said `Connection: close` (the service's, after a
      // body it did not read): what follows would be parsed as a request.
      if (!ok || closed || stream.ending()) break;
    }
  }
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
  return ok;
}

}  // namespace slosh::service
