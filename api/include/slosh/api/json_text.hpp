#pragma once
// JSON values kept as text by the service (e.g. a recipe's request in a Redis stream entry).

#include <string_view>

#include <nlohmann/json.hpp>

namespace slosh::api {

/// The value of JSON text written by dump_json (slosh/api/error.hpp); null when `text` is not
/// JSON.
[[nodiscard]] nlohmann::json json_value_of(std::string_view text);

}  // namespace slosh::api
