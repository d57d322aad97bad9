#pragma once
// The HTTP library's server with a deeper listen backlog and connections served through
// ConnectionStream (fewer system calls per request than the library's own stream).

#include <httplib.h>

#include <memory>

#include "config/server_config.hpp"
#include "http/connection_pool.hpp"

namespace slosh::service {

class ListeningServer : public httplib::Server {
 public:
  /// The connection threads (ConnectionPool, up to `config.http_threads`, made now: throws
  /// std::system_error when the system refuses its first thread), the read, write and
  /// keep-alive timeouts and the socket options of `config`.
  void configure(const ServerConfig& config);
  /// The library listens with a backlog of 5: a burst of more simultaneous connections than that
  /// loses SYNs and stalls those clients for a second or more. Listening again with the system's
  /// maximum only raises the backlog (Linux).
  bool raise_backlog();

 private:
  // The library's keep-alive loop (requests until the count, the keep-alive timeout or the
  // server's stop; the socket shut down and closed at the end) over a ConnectionStream.
  bool process_and_close_socket(socket_t sock) override;

  std::unique_ptr<ConnectionPool> pool_;  // until the accept loop takes it
};

}  // namespace slosh::service
