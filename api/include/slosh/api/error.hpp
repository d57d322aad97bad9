#pragma once
// The one error type of the API surface, rendered as {"error": {"code", "message", "field"}}.

#include <array>
#include <stdexcept>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "slosh/core/enum_names.hpp"

namespace slosh::api {

/// Error classes of the API surface; each has one name and one HTTP status (kErrorCodes).
enum class ErrorCode {
  kMalformedJson,         ///< 400: the body is not JSON
  kBadRequest,            ///< 400: the request is not a valid HTTP request for this service
  kInvalidValue,          ///< 422: a field is missing, of the wrong type or out of range
  kNotFound,              ///< 404
  kMethodNotAllowed,      ///< 405
  kConflict,              ///< 409: the resource is not in a state for this (a batch job running)
  kRequestTimeout,        ///< 408: the request was not received in time
  kPayloadTooLarge,       ///< 413
  kUriTooLong,            ///< 414
  kUnsupportedMediaType,  ///< 415
  kRangeNotSatisfiable,   ///< 416
  kHeadersTooLarge,       ///< 431
  kCancelled,             ///< 499: not done because the client went away (batch items)
  kInternal,              ///< 500
  kNotImplemented,        ///< 501: an HTTP method the service does not know
  kOverloaded,            ///< 503
  kUnavailable,           ///< 503: a store the answer lives in cannot be read (shared job store)
  kTimeout,               ///< 504
};

/// One row of the error table: the code, its name in the JSON envelope, its HTTP status.
struct ErrorCodeInfo {
  ErrorCode code;
  std::string_view name;
  int status;
};

inline constexpr std::array<ErrorCodeInfo, 18> kErrorCodes{{
    {ErrorCode::kBadRequest, "bad_request", 400},
    {ErrorCode::kMalformedJson, "malformed_json", 400},
    {ErrorCode::kInvalidValue, "invalid_value", 422},
    {ErrorCode::kNotFound, "not_found", 404},
    {ErrorCode::kMethodNotAllowed, "method_not_allowed", 405},
    {ErrorCode::kConflict, "conflict", 409},
    {ErrorCode::kRequestTimeout, "request_timeout", 408},
    {ErrorCode::kPayloadTooLarge, "payload_too_large", 413},
    {ErrorCode::kUriTooLong, "uri_too_long", 414},
    {ErrorCode::kUnsupportedMediaType, "unsupported_media_type", 415},
    {ErrorCode::kRangeNotSatisfiable, "range_not_satisfiable", 416},
    {ErrorCode::kHeadersTooLarge, "headers_too_large", 431},
    {ErrorCode::kCancelled, "cancelled", 499},
    {ErrorCode::kInternal, "internal", 500},
    {ErrorCode::kNotImplemented, "not_implemented", 501},
    {ErrorCode::kOverloaded, "overloaded", 503},
    {ErrorCode::kUnavailable, "unavailable", 503},
    {ErrorCode::kTimeout, "timeout", 504},
}};

}  // namespace slosh::api

namespace slosh {
/// The "code" of an error envelope: the names of kErrorCodes.
template <>
struct EnumNames<api::ErrorCode> {
  static constexpr std::array<EnumName<api::ErrorCode>, api::kErrorCodes.size()> table = [] {
    std::array<EnumName<api::ErrorCode>, api::kErrorCodes.size()> t{};
    for (std::size_t i = 0; i < t.size(); ++i)
      t[i] = {api::kErrorCodes[i].code, api::kErrorCodes[i].name};
    return t;
  }();
};
}  // namespace slosh

namespace slosh::api {

[[nodiscard]] int http_status(ErrorCode code);
[[nodiscard]] std::string to_string(ErrorCode code);
/// The code of an HTTP error status the service answers without a handler (the HTTP library's
/// own 400, 404, 408, 413, ...): the first code with that status; kBadRequest for another 4xx,
/// kInternal for a 5xx.
[[nodiscard]] ErrorCode error_code_of_status(int status);

/// Thrown by parsing and validation; carries the JSON path of the offending field.
class ApiError : public std::runtime_error {
 public:
  ApiError(ErrorCode code, std::string field, const std::string& message)
      : std::runtime_error(printable(message)), code_(code), field_(std::move(field)) {}
  [[nodiscard]] ErrorCode code() const { return code_; }
  [[nodiscard]] const std::string& field() const { return field_; }
  [[nodiscard]] int status() const { return http_status(code_); }

 private:
  // what() is a C string: a NUL quoted from the request (e.g. in an unknown key) would cut the
  // message short, so it is written as \u0000.
  static std::string printable(const std::string& message) {
    std::string out;
    out.reserve(message.size());
    for (const char c : message) {
      if (c == '\0') {
        out += "\\u0000";
      } else {
        out += c;
      }
    }
    return out;
  }

  ErrorCode code_;
  std::string field_;
};

/// {"error": {"code": "invalid_value", "message": "...", "field": "format.radius_mm"}}
[[nodiscard]] nlohmann::json error_envelope(const ApiError& error);

/// The envelope of `code` as JSON text; `field` empty renders as null.
[[nodiscard]] std::string error_body(ErrorCode code, const std::string& message,
                                     const std::string& field = {});
/// The envelope of `error` as JSON text.
[[nodiscard]] std::string error_body(const ApiError& error);

/// The error an envelope's {"code", "message", "field"} object describes (an unknown code is
/// kInternal; a missing message says so).
[[nodiscard]] ApiError error_from_json(const nlohmann::json& error);
/// The same from the text of an envelope {"error": {...}} (kInternal when it is not one).
[[nodiscard]] ApiError error_from_text(std::string_view envelope);

/// JSON text of a response; never throws on invalid UTF-8 (replaced by U+FFFD).
[[nodiscard]] std::string dump_json(const nlohmann::json& value, int indent = -1);

}  // namespace slosh::api
