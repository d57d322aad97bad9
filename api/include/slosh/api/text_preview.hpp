#pragma once
// A piece of text as error messages show it, for code that handles text and not JSON values.

#include <string>
#include <string_view>

namespace slosh::api {

/// `text` as messages show a JSON string value (api::show): in double quotes with JSON escapes,
/// cut with "..." when long.
[[nodiscard]] std::string show_text(std::string_view text);

}  // namespace slosh::api
