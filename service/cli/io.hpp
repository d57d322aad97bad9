#pragma once
// Reading request bodies for the CLI: a file path or "-" for standard input.

#include <string>

namespace slosh::service {

/// Reads the whole file, or stdin for "-". Throws std::runtime_error naming the path.
[[nodiscard]] std::string read_request_text(const std::string& path);

}  // namespace slosh::service
