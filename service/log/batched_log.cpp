#include "log/batched_log.hpp"

#include <poll.h>
#include <spdlog/pattern_formatter.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>

namespace slosh::service {

namespace {

/// How long a stream may take nothing before the last batch is given up at exit [ms]: the
/// process ends even when nobody reads its log.
constexpr int kStuckAtExitMs = 10000;

// Writes all of `text` to `fd`; what the stream refuses (closed, full disk) is dropped, as a
// logger cannot report its own failure anywhere else. A stream with no room (a full non-blocking
// pipe) is waited for, up to `stuck_ms` of no progress (-1: for ever, as a blocking one would).
void write_all(int fd, const std::string& text, int stuck_ms) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      // A non-blocking stream (a pipe the reader drains slowly): wait for room rather than cut a
      // line.
      pollfd p{fd, POLLOUT, 0};
      if (::poll(&p, 1, stuck_ms) == 0) return;
      continue;
    }
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

thread_local bool batchable = false;

}  // namespace

BatchedSink::Batchable::Batchable() : was_(batchable) {
  batchable = true;
}

BatchedSink::Batchable::~Batchable() {
  batchable = was_;
}

BatchedSink::BatchedSink(int fd, std::chrono::milliseconds linger)
    : fd_(fd), linger_(linger), formatter_(std::make_unique<spdlog::pattern_formatter>()) {
  writer_ = std::thread([this] { write_batches(); });
}

BatchedSink::~BatchedSink() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  writer_.join();
  ending_ = true;
  flush();
}

void BatchedSink::log(const spdlog::details::log_msg& msg) {
  if (!should_log(msg.level)) return;
  bool first = false;
  bool full = false;
  {
    const std::lock_guard lock(mutex_);
    spdlog::memory_buf_t line;
    formatter_->format(msg, line);
    first = pending_.empty();
    pending_.append(line.data(), line.size());
    full = pending_.size() >= kBatchLimit;
  }
  if (full || !batchable) {
    // A line that may not wait, or the stream slower than the lines: the logging thread writes.
    flush();
  } else if (first) {
    wake_.notify_one();
  }
}

void BatchedSink::flush() {
  const std::lock_guard write_lock(write_mutex_);
  std::string batch;
  {
    const std::lock_guard lock(mutex_);
    batch.swap(pending_);
  }
  write_all(fd_, batch, ending_ ? kStuckAtExitMs : -1);
}

void BatchedSink::set_pattern(const std::string& pattern) {
  set_formatter(std::make_unique<spdlog::pattern_formatter>(pattern));
}

void BatchedSink::set_formatter(std::unique_ptr<spdlog::formatter> formatter) {
  const std::lock_guard lock(mutex_);
  formatter_ = std::move(formatter);
}

void BatchedSink::write_batches() {
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stopping_ || !pending_.empty(); });
    if (stopping_) return;
    // The lines that follow join this batch.
    wake_.wait_for(lock, linger_, [this] { return stopping_; });
    lock.unlock();
    flush();
    lock.lock();
  }
}

BatchedLog::BatchedLog() : previous_(spdlog::default_logger()) {
  auto sink = std::make_shared<BatchedSink>(STDOUT_FILENO, kLinger);
  batched_ = std::make_shared<spdlog::logger>(previous_->name(), std::move(sink));
  batched_->set_level(previous_->level());
  batched_->flush_on(spdlog::level::warn);
  spdlog::set_default_logger(batched_);
}

BatchedLog::~BatchedLog() {
  batched_->flush();
  spdlog::set_default_logger(previous_);
}

}  // namespace slosh::service
