#pragma once
// The one error type of the API surface, rendered as {"error": {"code", "message", "field"}}.

#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "slosh/core/enum_names.hpp"

namespace slosh::api {

/// Error classes and their HTTP status.
enum class ErrorCode {
  kMalformedJson,    ///< 400: the body is not JSON
  kInvalidValue,     ///< 422: a field is missing, of the wrong type or out of range
  kNotFound,         ///< 404
  kPayloadTooLarge,  ///< 413
  kOverloaded,       ///< 503
  kTimeout,          ///< 504
  kInternal,         ///< 500
};

}  // namespace slosh::api

namespace slosh {
/// The "code" of an error envelope.
template <>
struct EnumNames<api::ErrorCode> {
  static constexpr std::array<EnumName<api::ErrorCode>, 7> table{{
      {api::ErrorCode::kMalformedJson, "malformed_json"},
      {api::ErrorCode::kInvalidValue, "invalid_value"},
      {api::ErrorCode::kNotFound, "not_found"},
      {api::ErrorCode::kPayloadTooLarge, "payload_too_large"},
      {api::ErrorCode::kOverloaded, "overloaded"},
      {api::ErrorCode::kTimeout, "timeout"},
      {api::ErrorCode::kInternal, "internal"},
  }};
};
}  // namespace slosh

namespace slosh::api {

[[nodiscard]] int http_status(ErrorCode code);
[[nodiscard]] std::string to_string(ErrorCode code);

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

/// JSON text of a response; never throws on invalid UTF-8 (replaced by U+FFFD).
[[nodiscard]] std::string dump_json(const nlohmann::json& value, int indent = -1);

}  // namespace slosh::api
