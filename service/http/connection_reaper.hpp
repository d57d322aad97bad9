#pragma once
// Closes the connections that hold a thread without sending a request: a client that trickles its
// request line and headers a byte at a time defeats per-read timeouts, and would keep a thread
// (and a shutdown) waiting for ever. The HTTP library does not expose its connection sockets, so
// the reaper finds them itself: every connected TCP socket of the process whose local port is the
// service's.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace slosh::service {

class ConnectionReaper {
 public:
  using Clock = std::chrono::steady_clock;

  /// Watches the connections to local `port`: one that has not delivered a complete request
  /// within `deadline` of connecting (or of its previous answer) and is not being answered is
  /// shut down. Scans every `interval`.
  ConnectionReaper(int port, Clock::duration deadline,
                   Clock::duration interval = std::chrono::milliseconds(500));
  /// Stops the watcher thread.
  ~ConnectionReaper();
  ConnectionReaper(const ConnectionReaper&) = delete;
  ConnectionReaper& operator=(const ConnectionReaper&) = delete;

  /// A request from `peer` ("address:port") is being handled: its connection is left alone.
  void begin_request(const std::string& peer);
  /// The answer to `peer` was written: its next request is due within the deadline.
  void end_request(const std::string& peer);
  /// Whether the client `peer` has closed its side of the connection (or the connection is gone):
  /// work queued for it can stop. One listing of the process's descriptors.
  [[nodiscard]] bool closed_by_peer(const std::string& peer) const;
  /// The socket of the connection from `peer`; -1 when there is none. One listing of the
  /// process's descriptors.
  [[nodiscard]] int socket_of(const std::string& peer) const;
  /// Whether the peer of socket `fd` has sent its FIN with nothing left unread before it: the
  /// HTTP library then writes nothing more to it (its writer refuses such a socket).
  [[nodiscard]] static bool peer_finished(int fd);
  /// From now on every connection that is not being answered is closed at once (shutdown).
  void close_idle_now();

  /// Connections closed so far.
  [[nodiscard]] std::uint64_t closed() const;

 private:
  struct Connection {
    std::string peer;
    Clock::time_point waiting_since;
    bool shut{false};
  };
  void watch();
  void scan();
  // Every TCP connection of the process accepted on port_: descriptor -> peer.
  [[nodiscard]] std::map<int, std::string> connections() const;

  const int port_;
  const Clock::duration deadline_;
  const Clock::duration interval_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_{false};
  bool closing_all_{false};
  std::map<int, Connection> connections_;              // by socket descriptor
  std::map<std::string, int> in_request_;              // peer -> requests being answered
  std::map<std::string, Clock::time_point> answered_;  // peer -> last answer written
  std::uint64_t closed_{0};
  std::thread thread_;
};

}  // namespace slosh::service
