#pragma once
// The body of a request, read by the service rather than by the HTTP library: the body limit
// holds for every transfer encoding (a chunked body is cut off at the limit, where the library
// reads it whole), it must arrive within the request timeout, and a body declared as something
// other than JSON is refused as such.

#include <httplib.h>

#include <optional>
#include <string>

#include "config/server_config.hpp"
#include "http/http_reply.hpp"

namespace slosh::service {

/// Media types a body may declare: JSON, or none at all.
[[nodiscard]] bool json_content_type(const std::string& value);

/// 413 naming the body limit (config max_body_bytes).
[[nodiscard]] Reply too_large_reply(const ServerConfig& config);

/// 415 naming the type the body of `req` is declared as.
[[nodiscard]] Reply not_json_reply(const httplib::Request& req);

/// The body of a POST read through `reader`; nullopt with `error` set when it is refused (415,
/// 413, 408 when it did not arrive within request_timeout_s, 400 when it could not be read).
[[nodiscard]] std::optional<std::string> read_body(const httplib::Request& req,
                                                   const httplib::ContentReader& reader,
                                                   const ServerConfig& config, Reply& error);

/// The refusal a request's framing earns before any of its body is read (nullopt when none): 413
/// for a Content-Length above max_body_bytes, 400 for one that is not a length (negative, not
/// digits, over 18 digits) or that comes with Transfer-Encoding. The body is then never read, so
/// the connection is closed after the answer.
[[nodiscard]] std::optional<Reply> declared_length_refusal(const httplib::Request& req,
                                                           const ServerConfig& config);

/// "Expect: 100-continue": 100, or the status (415, 413) a body that would be refused is refused
/// with before it is sent.
[[nodiscard]] int expect_continue_status(const httplib::Request& req, const ServerConfig& config);

}  // namespace slosh::service
