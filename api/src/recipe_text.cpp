#include "slosh/api/error.hpp"
#include "slosh/api/json_text.hpp"
#include "slosh/api/recipe_row.hpp"

namespace slosh::api {

std::string recipe_request_text(const RecipeRequest& request) {
  return dump_json(request.body());
}

RecipeRequest recipe_request_of_text(std::string_view text) {
  return RecipeRequest(json_value_of(text));
}

std::string recipe_error_text(const std::optional<ApiError>& error) {
  return error ? error_body(*error) : std::string();
}

std::optional<ApiError> recipe_error_of_text(std::string_view text) {
  if (text.empty()) return std::nullopt;
  return error_from_text(text);
}

}  // namespace slosh::api
