#pragma once
// A minimal HTTP client for the CLI's --server mode. The HTTP library stays behind this interface
// (like http_server.hpp on the serving side).

#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>

namespace slosh::service {

struct HttpReply {
  int status{0};
  std::string body;
  std::string retry_after;  ///< the Retry-After header, empty when absent
  std::string location;     ///< the Location header, empty when absent
};

/// Transport failures: unreachable server, connection reset, timeout.
class HttpError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class HttpClient {
 public:
  /// `base_url` is http://host[:port][/prefix]; throws std::invalid_argument for anything else
  /// (https needs a TLS-terminating proxy in front of the service). `timeout` bounds connecting
  /// and each read/write.
  HttpClient(const std::string& base_url, std::chrono::seconds timeout);
  ~HttpClient();
  HttpClient(const HttpClient&) = delete;
  HttpClient& operator=(const HttpClient&) = delete;

  /// POSTs a JSON body to `path` (appended to the URL's prefix). Throws HttpError on a transport
  /// failure; HTTP error statuses are returned, not thrown.
  HttpReply post_json(const std::string& path, const std::string& body);
  /// GET and DELETE `path`, as post_json.
  HttpReply get(const std::string& path);
  HttpReply del(const std::string& path);

  /// Bounds connecting and each read/write of the calls from now on.
  void set_timeout(std::chrono::milliseconds timeout);

  /// How many times a call answered "not now" (503, and the like where the caller says so) is
  /// sent again by the retrying calls of batch_retry.hpp before its last answer is taken. >= 0;
  /// none until set (`slosh batch` sets its --retries).
  void set_retries(int retries) { retries_ = retries; }
  [[nodiscard]] int retries() const { return retries_; }

  [[nodiscard]] const std::string& base_url() const { return base_url_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string base_url_;
  std::string prefix_;
  int retries_{0};
};

}  // namespace slosh::service
