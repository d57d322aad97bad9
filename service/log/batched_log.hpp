#pragma once
// The server's access log written in batches: a request's access-log line is added to a buffer,
// and a writer thread sends what gathered a few milliseconds after the first line of a batch in
// one write. Under load that is one write for a hundred requests instead of one per request, and
// no request thread waits on the log's stream (or on another thread writing to it). Every other
// line (start, stop, a job's or a store's events, warnings, errors) is written at once, with every
// line before it, as a synchronous log would. A crash loses at most the access-log lines of the
// last batch interval.

#include <spdlog/logger.h>
#include <spdlog/sinks/sink.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace slosh::service {

/// A spdlog sink writing to a file descriptor in batches.
class BatchedSink final : public spdlog::sinks::sink {
 public:
  /// Writes to `fd` (not owned) `linger` after the first line of each batch, or at once when a
  /// batch reaches kBatchLimit bytes (the logging thread then writes it itself).
  BatchedSink(int fd, std::chrono::milliseconds linger);
  /// Stops the writer thread and writes what is left.
  ~BatchedSink() override;
  BatchedSink(const BatchedSink&) = delete;
  BatchedSink& operator=(const BatchedSink&) = delete;

  /// Lines logged on this thread while one is alive may wait for their batch (the access log's);
  /// every other line is written at once, with the lines before it.
  class Batchable {
   public:
    Batchable();
    ~Batchable();
    Batchable(const Batchable&) = delete;
    Batchable& operator=(const Batchable&) = delete;

   private:
    bool was_;
  };

  void log(const spdlog::details::log_msg& msg) override;
  /// Writes every line logged so far.
  void flush() override;
  void set_pattern(const std::string& pattern) override;
  void set_formatter(std::unique_ptr<spdlog::formatter> formatter) override;

  /// Bytes after which a batch is written by the thread that logs [bytes].
  static constexpr std::size_t kBatchLimit = std::size_t{1} << 20;

 private:
  void write_batches();

  const int fd_;
  const std::chrono::milliseconds linger_;
  std::mutex mutex_;  // pending_, formatter_, stopping_
  std::condition_variable wake_;
  std::string pending_;
  std::unique_ptr<spdlog::formatter> formatter_;
  bool stopping_{false};
  std::atomic<bool> ending_{false};  // the last batch: a stream that takes nothing is given up
  std::mutex write_mutex_;           // one batch written at a time, in the order they were taken
  std::thread writer_;
};

/// While alive, the default logger writes to standard output through a BatchedSink; the logger it
/// replaced is restored, every line written, at the end.
class BatchedLog {
 public:
  /// How long a batch gathers lines after its first [ms].
  static constexpr std::chrono::milliseconds kLinger{5};

  BatchedLog();
  ~BatchedLog();
  BatchedLog(const BatchedLog&) = delete;
  BatchedLog& operator=(const BatchedLog&) = delete;

 private:
  std::shared_ptr<spdlog::logger> previous_;
  std::shared_ptr<spdlog::logger> batched_;
};

}  // namespace slosh::service
