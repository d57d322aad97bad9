#pragma once
// One accepted connection as the HTTP library reads and writes it, in fewer system calls than the
// library's own socket stream. On this service's hot path (a cached plan over keep-alive) the
// library's stream made about 15 calls per request: a poll before every read, a poll and a
// liveness poll before each of its two sends (head, then body), and getpeername and getsockname
// per request. Each call costs a few microseconds in a virtualised guest, more than the service's
// own work for a cached reply. Here a request costs a recv, one send of head and body together
// (sendmsg) and the half-close check of the reply's hook:
// - reads block in recv instead of polling first: the socket's receive timeout (SO_RCVTIMEO) is
//   a short slice, so that a connection waiting for its next request reads it in the same call
//   that waits for it and still looks every slice whether the server stops; a read inside a
//   request waits slice after slice up to the read timeout;
// - small writes (a reply's head, a short first piece of its body) are gathered up to 16 kB and
//   leave with the next larger one; anything held is sent before the stream blocks on a read (an
//   interim "100 Continue") and when the reply ends;
// - writes block in send under the socket's send timeout (SO_SNDTIMEO);
// - the peer's and the local address are read once per connection.

#include <httplib.h>
#include <sys/time.h>

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace slosh::service {

class ConnectionStream final : public httplib::Stream {
 public:
  /// Serves socket `sock` (not owned: the caller closes it); sets its receive timeout to
  /// `receive_slice` and its send timeout to `write_timeout`. A read waits up to `read_timeout`.
  /// The stream is the current one of the constructing thread until it is destroyed.
  ConnectionStream(int sock, timeval read_timeout, timeval write_timeout,
                   std::chrono::milliseconds receive_slice);
  ~ConnectionStream() override;
  ConnectionStream(const ConnectionStream&) = delete;
  ConnectionStream& operator=(const ConnectionStream&) = delete;

  /// The connection this thread is serving; nullptr outside one.
  [[nodiscard]] static ConnectionStream* on_this_thread();

  /// Bytes are buffered, or the socket becomes readable within the read timeout.
  [[nodiscard]] bool is_readable() const override;
  /// False once a send failed or the reply was refused (refuse_if_peer_finished).
  [[nodiscard]] bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  [[nodiscard]] socket_t socket() const override { return sock_; }

  /// Waits until the next request can be read, receiving its first bytes: true when bytes are
  /// buffered or arrive, false when the peer closed or failed, after `timeout` of silence, or once
  /// `keep_waiting` says to stop (asked every receive slice).
  bool wait_for_request(std::chrono::milliseconds timeout,
                        const std::function<bool()>& keep_waiting);
  /// Sends what is held; false when a send failed (now or before) or the reply was refused.
  bool flush();
  /// When the peer has sent its FIN with nothing unread before it, the reply is not written
  /// (every later write fails) and true is returned. One non-blocking peek.
  bool refuse_if_peer_finished();
  /// Starts the next request: what was said of the previous one is forgotten.
  void begin_request();
  /// The request's line and headers have been read: what is read next (its body) does not count
  /// towards kMaxHeadBytes.
  void head_read() { in_head_ = false; }
  /// The request's line and headers as read so far (all of them once head_read()).
  [[nodiscard]] std::string_view head() const { return head_; }
  /// The request's line and headers passed kMaxHeadBytes: the read that would pass it failed.
  [[nodiscard]] bool head_overflowed() const { return head_overflowed_; }
  /// The connection ends after this reply (it said `Connection: close`).
  void end_after_reply() { ending_ = true; }
  [[nodiscard]] bool ending() const { return ending_; }

  /// The most a request's line and headers may take [bytes]. The library bounds each line
  /// (8 kB) but not their number.
  static constexpr std::size_t kMaxHeadBytes = std::size_t{64} << 10;

 private:
  ssize_t read_unbounded(char* ptr, size_t size);
  // One recv of at most `size` bytes into `ptr`; -1 with EAGAIN when a receive slice passed.
  ssize_t receive(char* ptr, std::size_t size);
  [[nodiscard]] bool poll_readable(int timeout_ms) const;
  bool send_all(const char* head, std::size_t head_size, const char* body, std::size_t body_size);

  int sock_;
  timeval read_timeout_;
  std::vector<char> in_;  // received, not yet read
  std::size_t in_begin_{0};
  std::size_t in_end_{0};
  std::string held_;  // written, not yet sent (a reply's head)
  bool failed_{false};
  bool refused_{false};
  bool ending_{false};
  bool in_head_{true};
  bool head_overflowed_{false};
  std::string head_;  // the request's line and headers, read so far
  std::string remote_ip_;
  int remote_port_{0};
  std::string local_ip_;
  int local_port_{0};
};

}  // namespace slosh::service
