#include "slosh/api/text_preview.hpp"

#include <nlohmann/json.hpp>

#include "slosh/api/fields.hpp"

namespace slosh::api {

std::string show_text(std::string_view text) {
  return show(nlohmann::json(std::string(text)));
}

}  // namespace slosh::api
