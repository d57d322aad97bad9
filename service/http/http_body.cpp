#include "http/http_body.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>

#include "slosh/api/format_json.hpp"

namespace slosh::service {

bool json_content_type(const std::string& value) {
  if (value.empty()) return true;
  std::string type = value.substr(0, value.find(';'));
  type.erase(std::remove_if(type.begin(), type.end(), [](char c) { return c == ' ' || c == '\t'; }),
             type.end());
  std::transform(type.begin(), type.end(), type.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return type == "application/json" ||
         (type.starts_with("application/") && type.ends_with("+json"));
}

Reply too_large_reply(const ServerConfig& config) {
  return error_reply(
      api::ErrorCode::kPayloadTooLarge,
      "the body is larger than the limit of " + std::to_string(config.max_body_bytes) +
          " bytes (max_body_bytes); a trajectory of more samples than a body holds (about 30 000 "
          "t, x, y samples in 1 MiB) is simulated from a CSV file by slosh simulate --trajectory, "
          "up to 200000 samples");
}

Reply not_json_reply(const httplib::Request& req) {
  return error_reply(api::ErrorCode::kUnsupportedMediaType,
                     "the body is declared as '" +
                         req.get_header_value("Content-Type").substr(0, 80) +
                         "'; send the JSON request with Content-Type: application/json");
}

std::optional<std::string> read_body(const httplib::Request& req,
                                     const httplib::ContentReader& reader,
                                     const ServerConfig& config, Reply& error) {
  if (!json_content_type(req.get_header_value("Content-Type"))) {
    error = not_json_reply(req);
    return std::nullopt;
  }
  std::string body;
  // A request has a body only with Content-Length or chunked transfer coding (RFC 9112 6.3); the
  // library would otherwise read "until the connection closes" and hold the thread.
  if (!req.has_header("Content-Length") &&
      req.get_header_value("Transfer-Encoding").find("chunked") == std::string::npos) {
    return body;
  }
  if (std::optional<Reply> refusal = declared_length_refusal(req, config)) {
    error = std::move(*refusal);
    return std::nullopt;
  }
  bool too_large = false;
  bool too_slow = false;
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                    std::chrono::duration<double>(config.request_timeout_s));
  const bool complete = reader([&](const char* data, std::size_t length) {
    too_large = body.size() + length > config.max_body_bytes;
    too_slow = std::chrono::steady_clock::now() > deadline;
    if (too_large || too_slow) return false;
    body.append(data, length);
    return true;
  });
  if (too_large) {
    error = too_large_reply(config);
  } else if (too_slow) {
    error = error_reply(
        api::ErrorCode::kRequestTimeout,
        "the body did not arrive within " + api::number_text(config.request_timeout_s) + " s");
  } else if (!complete && config.read_timeout_s > 0 &&
             std::chrono::steady_clock::now() - start >=
                 std::chrono::duration<double>(config.read_timeout_s)) {
    // The socket read timed out: the body stopped arriving (a closed connection or bad chunks
    // fail at once).
    error = error_reply(api::ErrorCode::kRequestTimeout,
                        "the body stopped arriving: nothing came for read_timeout_s = " +
                            api::number_text(config.read_timeout_s) + " s");
  } else if (!complete) {
    error = error_reply(api::ErrorCode::kBadRequest,
                        "the body could not be read (connection closed or invalid chunks)");
  } else {
    return body;
  }
  return std::nullopt;
}

std::optional<Reply> declared_length_refusal(const httplib::Request& req,
                                             const ServerConfig& config) {
  if (!req.has_header("Content-Length")) return std::nullopt;
  const std::string length = req.get_header_value("Content-Length");
  if (req.has_header("Transfer-Encoding")) {
    // Two framings of one body: a proxy and this service could split the stream differently.
    return error_reply(api::ErrorCode::kBadRequest,
                       "the request declares both Content-Length and Transfer-Encoding: send "
                       "one of them (RFC 9112 6.3)");
  }
  if (length.empty() || length.size() > 18 ||
      length.find_first_not_of("0123456789") != std::string::npos) {
    return error_reply(api::ErrorCode::kBadRequest,
                       "Content-Length = \"" + length.substr(0, 32) +
                           "\" is not a length: a whole number of bytes, at most " +
                           std::to_string(config.max_body_bytes));
  }
  if (std::stoull(length) > config.max_body_bytes) return too_large_reply(config);
  return std::nullopt;
}

int expect_continue_status(const httplib::Request& req, const ServerConfig& config) {
  const std::string length = req.get_header_value("Content-Length");
  const bool digits = !length.empty() && length.size() <= 18 &&
                      length.find_first_not_of("0123456789") == std::string::npos;
  if (!json_content_type(req.get_header_value("Content-Type"))) return 415;
  if (!length.empty() && (!digits || std::stoull(length) > config.max_body_bytes)) return 413;
  return 100;
}

}  // namespace slosh::service
