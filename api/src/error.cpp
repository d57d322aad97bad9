#include "slosh/api/error.hpp"

namespace slosh::api {

int http_status(ErrorCode code) {
  switch (code) {
    case ErrorCode::kMalformedJson:
      return 400;
    case ErrorCode::kInvalidValue:
      return 422;
    case ErrorCode::kNotFound:
      return 404;
    case ErrorCode::kPayloadTooLarge:
      return 413;
    case ErrorCode::kOverloaded:
      return 503;
    case ErrorCode::kTimeout:
      return 504;
    case ErrorCode::kInternal:
      return 500;
  }
  return 500;
}

std::string to_string(ErrorCode code) {
  return std::string(name_of(code));
}

std::string dump_json(const nlohmann::json& value, int indent) {
  return value.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

nlohmann::json error_envelope(const ApiError& error) {
  nlohmann::json e{{"code", to_string(error.code())}, {"message", error.what()}};
  e["field"] = error.field().empty() ? nlohmann::json(nullptr) : nlohmann::json(error.field());
  return {{"error", e}};
}

}  // namespace slosh::api
