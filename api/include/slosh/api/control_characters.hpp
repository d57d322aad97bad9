#pragma once
// Texts of a request that are echoed into plans, tables and logs (fluid names, recipe ids): a
// control character would cut or forge their lines (a NUL ends a C string, a line break starts a
// new CSV or log record), so such a text is refused, never cleaned.

#include <string>
#include <string_view>

namespace slosh::api {

/// Throws ApiError(kInvalidValue) naming `path` when `text` holds a control character (U+0000 to
/// U+001F, U+007F): "<path> must not hold control characters (NUL, tab, line breaks, ...), got
/// <text as JSON>".
void refuse_control_characters(const std::string& path, std::string_view text);

}  // namespace slosh::api
