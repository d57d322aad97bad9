#include "http/connection_stream.hpp"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/uio.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <optional>

namespace slosh::service {

namespace {

/// Bytes received per recv: a request's line, headers and a typical body in one call [bytes].
constexpr std::size_t kReceiveBuffer = std::size_t{16} << 10;
/// Writes are gathered up to this size and sent with the next larger one or when the reply ends
/// (a reply's head is a few hundred bytes) [bytes].
constexpr std::size_t kHoldAtMost = std::size_t{16} << 10;

thread_local ConnectionStream* current_stream = nullptr;

// The numeric address and port of `addr` ("" and 0 when the system cannot say).
void numeric_address(const sockaddr_storage& addr, socklen_t length, std::string& ip, int& port) {
  char host[NI_MAXHOST] = {};
  char service[NI_MAXSERV] = {};
  if (getnameinfo(reinterpret_cast<const sockaddr*>(&addr), length, host, sizeof host, service,
                  sizeof service, NI_NUMERICHOST | NI_NUMERICSERV) != 0) {
    ip.clear();
    port = 0;
    return;
  }
  ip = host;
  port = std::atoi(service);
}

}  // namespace

ConnectionStream::ConnectionStream(int sock, timeval read_timeout, timeval write_timeout,
                                   std::chrono::milliseconds receive_slice)
    : sock_(sock), read_timeout_(read_timeout), in_(kReceiveBuffer) {
  const auto slice_us = std::chrono::duration_cast<std::chrono::microseconds>(receive_slice);
  const timeval slice{static_cast<time_t>(slice_us.count() / 1000000),
                      static_cast<suseconds_t>(slice_us.count() % 1000000)};
  setsockopt(sock_, SOL_SOCKET, SO_RCVTIMEO, &slice, sizeof slice);
  setsockopt(sock_, SOL_SOCKET, SO_SNDTIMEO, &write_timeout, sizeof write_timeout);
  sockaddr_storage addr{};
  socklen_t length = sizeof addr;
  if (getpeername(sock_, reinterpret_cast<sockaddr*>(&addr), &length) == 0) {
    numeric_address(addr, length, remote_ip_, remote_port_);
  }
  length = sizeof addr;
  if (getsockname(sock_, reinterpret_cast<sockaddr*>(&addr), &length) == 0) {
    numeric_address(addr, length, local_ip_, local_port_);
  }
  current_stream = this;
}

ConnectionStream::~ConnectionStream() {
  if (current_stream == this) current_stream = nullptr;
}

ConnectionStream* ConnectionStream::on_this_thread() {
  return current_stream;
}

bool ConnectionStream::poll_readable(int timeout_ms) const {
  pollfd p{sock_, POLLIN, 0};
  int n = 0;
  do {
    n = ::poll(&p, 1, timeout_ms);
  } while (n < 0 && errno == EINTR);
  return n > 0;
}

bool ConnectionStream::is_readable() const {
  if (in_begin_ < in_end_) return true;
  const long ms = read_timeout_.tv_sec * 1000L + read_timeout_.tv_usec / 1000L;
  return poll_readable(static_cast<int>(std::min<long>(ms, 1L << 30)));
}

bool ConnectionStream::is_writable() const {
  return !failed_ && !refused_;
}

void ConnectionStream::begin_request() {
  refused_ = false;
  in_head_ = true;
  head_overflowed_ = false;
  head_.clear();
}

ssize_t ConnectionStream::read(char* ptr, size_t size) {
  if (in_head_) {
    if (head_.size() >= kMaxHeadBytes) {
      head_overflowed_ = true;
      return -1;
    }
    size = std::min(size, kMaxHeadBytes - head_.size());
    const ssize_t n = read_unbounded(ptr, size);
    if (n > 0) head_.append(ptr, static_cast<std::size_t>(n));
    return n;
  }
  return read_unbounded(ptr, size);
}

ssize_t ConnectionStream::read_unbounded(char* ptr, size_t size) {
  if (in_begin_ < in_end_) {
    const std::size_t n = std::min(size, in_end_ - in_begin_);
    std::memcpy(ptr, in_.data() + in_begin_, n);
    in_begin_ += n;
    return static_cast<ssize_t>(n);
  }
  // Whatever the peer should see before it sends more (an interim reply) goes out first.
  if (!flush() && failed_) return -1;
  const bool direct = size >= in_.size();
  // The read timeout is counted from the first slice that passes (a clock read only then).
  std::optional<std::chrono::steady_clock::time_point> deadline;
  ssize_t n = 0;
  while ((n = receive(direct ? ptr : in_.data(), direct ? size : in_.size())) < 0 &&
         (errno == EAGAIN || errno == EWOULDBLOCK)) {
    const auto now = std::chrono::steady_clock::now();
    if (!deadline) {
      deadline = now + std::chrono::seconds(read_timeout_.tv_sec) +
                 std::chrono::microseconds(read_timeout_.tv_usec);
    } else if (now >= *deadline) {
      break;
    }
  }
  if (n <= 0 || direct) return n;
  in_begin_ = 0;
  in_end_ = static_cast<std::size_t>(n);
  return read_unbounded(ptr, size);
}

ssize_t ConnectionStream::write(const char* ptr, size_t size) {
  if (!is_writable()) return -1;
  if (held_.size() + size <= kHoldAtMost) {
    held_.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  const bool sent = send_all(held_.data(), held_.size(), ptr, size);
  held_.clear();
  return sent ? static_cast<ssize_t>(size) : -1;
}

bool ConnectionStream::flush() {
  if (refused_) {
    held_.clear();
    return false;
  }
  if (held_.empty() || failed_) return !failed_;
  const bool sent = send_all(held_.data(), held_.size(), nullptr, 0);
  held_.clear();
  return sent;
}

bool ConnectionStream::send_all(const char* head, std::size_t head_size, const char* body,
                                std::size_t body_size) {
  iovec parts[2] = {{const_cast<char*>(head), head_size}, {const_cast<char*>(body), body_size}};
  iovec* next = parts;
  int count = body_size > 0 ? 2 : 1;
  if (head_size == 0) ++next, --count;
  while (count > 0) {
    msghdr message{};
    message.msg_iov = next;
    message.msg_iovlen = static_cast<std::size_t>(count);
    const ssize_t n = ::sendmsg(sock_, &message, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {  // the send timeout passed, or the peer is gone
      failed_ = true;
      return false;
    }
    auto left = static_cast<std::size_t>(n);
    while (count > 0 && left >= next->iov_len) {
      left -= next->iov_len;
      ++next;
      --count;
    }
    if (count > 0) {
      next->iov_base = static_cast<char*>(next->iov_base) + left;
      next->iov_len -= left;
    }
  }
  return true;
}

ssize_t ConnectionStream::receive(char* ptr, std::size_t size) {
  ssize_t n = 0;
  do {
    n = ::recv(sock_, ptr, size, 0);
  } while (n < 0 && errno == EINTR);
  return n;
}

bool ConnectionStream::wait_for_request(std::chrono::milliseconds timeout,
                                        const std::function<bool()>& keep_waiting) {
  if (in_begin_ < in_end_) return true;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (keep_waiting()) {
    const ssize_t n = receive(in_.data(), in_.size());
    if (n > 0) {
      in_begin_ = 0;
      in_end_ = static_cast<std::size_t>(n);
      return true;
    }
    if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) return false;
    if (std::chrono::steady_clock::now() >= deadline) return false;
  }
  return false;
}

bool ConnectionStream::refuse_if_peer_finished() {
  if (in_begin_ < in_end_) return false;  // a pipelined request is unread: not finished
  char byte = 0;
  if (::recv(sock_, &byte, 1, MSG_PEEK | MSG_DONTWAIT) != 0) return false;
  refused_ = true;
  held_.clear();
  return true;
}

void ConnectionStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  ip = remote_ip_;
  port = remote_port_;
}

void ConnectionStream::get_local_ip_and_port(std::string& ip, int& port) const {
  ip = local_ip_;
  port = local_port_;
}

}  // namespace slosh::service
