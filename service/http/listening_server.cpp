#include "http/listening_server.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "http/connection_pool.hpp"
#include "http/connection_stream.hpp"

namespace slosh::service {

namespace {

/// How often a connection waiting for its next request looks whether the server stopped, as the
/// library's own loop does.
constexpr std::chrono::milliseconds kStopCheck{10};

timeval to_timeval(double seconds) {
  const double whole = std::floor(seconds);
  return {static_cast<time_t>(whole), static_cast<suseconds_t>((seconds - whole) * 1e6)};
}

}  // namespace

void ListeningServer::configure(const ServerConfig& config) {
  // The connection threads' pool, with its refusing thread, is made here, before the port is
  // announced (the library makes it when its accept loop starts): a limit the system sets on the
  // process once it has announced its port (a thread limit, `ulimit -v`) cannot stop the server
  // then. The accept loop takes it over.
  pool_ = std::make_unique<ConnectionPool>(config.http_threads);
  new_task_queue = [this] { return pool_.release(); };
  // Bodies are read by the handlers themselves (read_body): the library's own limit does not hold
  // for chunked bodies.
  const timeval read_timeout = to_timeval(config.read_timeout_s);
  const timeval write_timeout = to_timeval(config.write_timeout_s);
  set_read_timeout(read_timeout.tv_sec, read_timeout.tv_usec);
  set_write_timeout(write_timeout.tv_sec, write_timeout.tv_usec);
  set_keep_alive_timeout(
      std::max<time_t>(1, static_cast<time_t>(std::lround(config.keep_alive_timeout_s))));
  set_keep_alive_max_count(100000);
  set_tcp_nodelay(true);  // no 40 ms Nagle + delayed-ACK stall between header and body
  // The library's default options add SO_REUSEPORT, which lets a second instance bind the same
  // port and take half of the connections: only SO_REUSEADDR here, so that second bind fails.
  set_socket_options([](socket_t sock) {
    const int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
}

bool ListeningServer::raise_backlog() {
  return ::listen(svr_sock_, SOMAXCONN) == 0;
}

bool ListeningServer::process_and_close_socket(socket_t sock) {
  bool ok = false;
  {
    ConnectionStream stream(
        sock, timeval{read_timeout_sec_, static_cast<suseconds_t>(read_timeout_usec_)},
        timeval{write_timeout_sec_, static_cast<suseconds_t>(write_timeout_usec_)}, kStopCheck);
    const auto running = [this] { return svr_sock_ != INVALID_SOCKET; };
    for (std::size_t left = keep_alive_max_count_; left > 0; --left) {
      if (!stream.wait_for_request(std::chrono::seconds(keep_alive_timeout_sec_), running)) {
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
