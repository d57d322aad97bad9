#pragma once
// Reading request bodies for the CLI: a file path or "-" for standard input.

#include <string>

namespace slosh::service {

/// Reads the whole file, or stdin for "-". Throws std::runtime_error naming the path.
/// `what` names the file in the refusal ("cannot read <what> file '<path>'").
[[nodiscard]] std::string read_request_text(const std::string& path,
                                            const std::string& what = "request");

}  // namespace slosh::service
