#include "slosh/api/error.hpp"
#include "slosh/api/json_text.hpp"

namespace slosh::api {

namespace {

const ErrorCodeInfo& info(ErrorCode code) {
  for (const ErrorCodeInfo& row : kErrorCodes) {
    if (row.code == code) return row;
  }
  return kErrorCodes.back();  // unreachable: every code has a row (test_service_errors)
}

}  // namespace

int http_status(ErrorCode code) {
  return info(code).status;
}

std::string to_string(ErrorCode code) {
  return std::string(info(code).name);
}

ErrorCode error_code_of_status(int status) {
  for (const ErrorCodeInfo& row : kErrorCodes) {
    if (row.status == status) return row.code;
  }
  return status < 500 ? ErrorCode::kBadRequest : ErrorCode::kInternal;
}

std::string dump_json(const nlohmann::json& value, int indent) {
  return value.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

nlohmann::json json_value_of(std::string_view text) {
  nlohmann::json value = nlohmann::json::parse(text, nullptr, false);
  return value.is_discarded() ? nlohmann::json(nullptr) : value;
}

nlohmann::json error_envelope(const ApiError& error) {
  nlohmann::json e{{"code", to_string(error.code())}, {"message", error.what()}};
  e["field"] = error.field().empty() ? nlohmann::json(nullptr) : nlohmann::json(error.field());
  return {{"error", e}};
}

std::string error_body(ErrorCode code, const std::string& message, const std::string& field) {
  return error_body(ApiError(code, field, message));
}

ApiError error_from_json(const nlohmann::json& error) {
  ErrorCode code = ErrorCode::kInternal;
  std::string field;
  std::string message = "an error without a message";
  if (error.is_object()) {
    const auto c = error.find("code");
    if (c != error.end() && c->is_string()) {
      for (const ErrorCodeInfo& row : kErrorCodes) {
        if (row.name == c->get<std::string>()) code = row.code;
      }
    }
    const auto f = error.find("field");
    if (f != error.end() && f->is_string()) field = f->get<std::string>();
    const auto m = error.find("message");
    if (m != error.end() && m->is_string()) message = m->get<std::string>();
  }
  return ApiError(code, field, message);
}

ApiError error_from_text(std::string_view envelope) {
  const nlohmann::json parsed = nlohmann::json::parse(envelope, nullptr, false);
  if (parsed.is_discarded() || !parsed.is_object() || !parsed.contains("error")) {
    return ApiError(ErrorCode::kInternal, "", "an answer that is not an error envelope");
  }
  return error_from_json(parsed["error"]);
}

std::string error_body(const ApiError& error) {
  return dump_json(error_envelope(error));
}

}  // namespace slosh::api
