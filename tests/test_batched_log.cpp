// The server's log sink (service/log/batched_log): lines written in batches by a writer thread,
// warnings at once with every line before them, nothing lost or torn between threads, everything
// written when the sink ends. In process, writing to a real file.

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "log/batched_log.hpp"
#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_batched_log {

using service::BatchedSink;

// A logger writing bare messages ("%v") through a BatchedSink into a file of its own.
class LogFile {
 public:
  explicit LogFile(std::chrono::milliseconds linger)
      : path_(dir_ / "log"), fd_(::open(path_.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0600)) {
    sink_ = std::make_shared<BatchedSink>(fd_, linger);
    logger_ = std::make_shared<spdlog::logger>("batched", sink_);
    logger_->set_pattern("%v");
    logger_->flush_on(spdlog::level::warn);
  }
  ~LogFile() {
    end();
    ::close(fd_);
  }
  LogFile(const LogFile&) = delete;
  LogFile& operator=(const LogFile&) = delete;

  spdlog::logger& logger() { return *logger_; }
  [[nodiscard]] std::string text() const { return test::read_file(path_); }
  // Ends the logger and its sink (the last batch written).
  void end() {
    logger_.reset();
    sink_.reset();
  }

 private:
  test::TempDir dir_;  // first: the members after it are made in it
  std::filesystem::path path_;
  int fd_;
  std::shared_ptr<BatchedSink> sink_;
  std::shared_ptr<spdlog::logger> logger_;
};

TEST(BatchedLog, LinesFromManyThreadsArriveWholeAndInEachThreadsOrder) {
  LogFile file(std::chrono::milliseconds(2));
  constexpr int kThreads = 8;
  constexpr int kLines = 2000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&file, t] {
      const BatchedSink::Batchable batchable;
      for (int i = 0; i < kLines; ++i) {
        file.logger().info("thread {} line {} {}", t, i,
                           std::string(static_cast<std::size_t>(i % 97), 'x'));
      }
    });
  }
  for (auto& t : threads) t.join();
  file.end();
  std::istringstream in(file.text());
  std::map<int, int> next;  // thread -> its next line
  std::string line;
  int count = 0;
  while (std::getline(in, line)) {
    int t = -1;
    int i = -1;
    char tail[256] = {};
    ASSERT_EQ(std::sscanf(line.c_str(), "thread %d line %d %255s", &t, &i, tail) >= 2, true)
        << line;
    ASSERT_EQ(i, next[t]) << line;
    ASSERT_EQ(line, "thread " + std::to_string(t) + " line " + std::to_string(i) + " " +
                        std::string(static_cast<std::size_t>(i % 97), 'x'));
    ++next[t];
    ++count;
  }
  EXPECT_EQ(count, kThreads * kLines);
}

// With a batch interval far longer than the test, an access-log line waits for its batch, and a
// warning is written at once together with it.
TEST(BatchedLog, AWarningIsWrittenAtOnceWithTheLinesBeforeIt) {
  LogFile file(std::chrono::seconds(60));
  const BatchedSink::Batchable batchable;
  file.logger().info("first");
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(file.text(), "");
  file.logger().warn("second");
  EXPECT_EQ(file.text(), "first\nsecond\n");
  file.logger().info("third");
  const auto t0 = std::chrono::steady_clock::now();
  file.end();  // the writer waiting for its batch interval stops at once
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10.0);
  EXPECT_EQ(file.text(), "first\nsecond\nthird\n");
}

// A line that is not the access log's (a start, a job's event) is written at once, with the
// access-log lines before it.
TEST(BatchedLog, AnEventLineIsWrittenAtOnceWithTheLinesBeforeIt) {
  LogFile file(std::chrono::seconds(60));
  {
    const BatchedSink::Batchable batchable;
    file.logger().info("request");
  }
  EXPECT_EQ(file.text(), "");
  file.logger().info("event");
  EXPECT_EQ(file.text(), "request\nevent\n");
}

TEST(BatchedLog, ALineIsWrittenWithinTheBatchInterval) {
  LogFile file(std::chrono::milliseconds(5));
  const BatchedSink::Batchable batchable;
  file.logger().info("soon");
  EXPECT_TRUE(test::wait_until([&] { return file.text() == "soon\n"; }, std::chrono::seconds(10)));
}

// Lines faster than the stream: past kBatchLimit the logging thread writes the batch itself.
TEST(BatchedLog, ABatchPastItsLimitIsWrittenByTheLoggingThread) {
  LogFile file(std::chrono::seconds(60));
  const BatchedSink::Batchable batchable;
  const std::string line(1000, 'y');
  const std::size_t lines = BatchedSink::kBatchLimit / (line.size() + 1) + 1;
  for (std::size_t i = 0; i < lines; ++i) file.logger().info("{}", line);
  EXPECT_GE(file.text().size(), BatchedSink::kBatchLimit);
  file.end();
  EXPECT_EQ(file.text().size(), lines * (line.size() + 1));
}

// A non-blocking stream that a slow reader drains (a pipe set O_NONBLOCK by whoever reads the
// log): the writer waits for room; no line is lost or cut.
TEST(BatchedLog, ANonBlockingStreamReadSlowlyLosesNoLine) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ASSERT_EQ(::fcntl(fds[1], F_SETFL, ::fcntl(fds[1], F_GETFL) | O_NONBLOCK), 0);
  std::string received;
  std::thread reader([&received, fd = fds[0]] {
    char buf[4096];
    for (;;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      const ssize_t n = ::read(fd, buf, sizeof buf);
      if (n <= 0) return;
      received.append(buf, static_cast<std::size_t>(n));
    }
  });
  constexpr int kLines = 3000;
  {
    auto sink = std::make_shared<BatchedSink>(fds[1], std::chrono::milliseconds(2));
    spdlog::logger logger("pipe", sink);
    logger.set_pattern("%v");
    const BatchedSink::Batchable batchable;
    for (int i = 0; i < kLines; ++i) logger.info("line {} {}", i, std::string(100, 'z'));
  }
  ::close(fds[1]);
  reader.join();
  ::close(fds[0]);
  std::istringstream in(received);
  std::string line;
  int i = 0;
  while (std::getline(in, line)) {
    ASSERT_EQ(line, "line " + std::to_string(i) + " " + std::string(100, 'z'));
    ++i;
  }
  EXPECT_EQ(i, kLines);
}

// The server's lines are batched, and its last lines are written when it stops.
TEST(BatchedLog, TheServersLastLinesAreWrittenWhenItStops) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  ASSERT_TRUE(server.client().Get("/healthz"));
  const std::optional<int> code = server.stop();
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0);
  const std::string log = server.log();
  EXPECT_NE(log.find("path=/healthz status=200"), std::string::npos) << log;
  EXPECT_NE(log.find("slosh stopped"), std::string::npos) << log;
}

}  // namespace test_batched_log
}  // namespace slosh
