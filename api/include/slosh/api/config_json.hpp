#pragma once
// The config file of `slosh serve` (config/slosh.json), the JSON side: the file's members as typed
// values, and numbers written as JSON writes them. The service checks each value against its
// settings table.

#include <istream>
#include <string>
#include <vector>

namespace slosh::api {

/// One member of the config file's object.
struct ConfigMember {
  enum class Kind { boolean, string, number, other };
  std::string key;
  Kind kind{Kind::other};
  std::string json;  ///< the value as JSON text (true, 80, "text", [1], ...)
  std::string text;  ///< a string's value (unquoted); empty for other kinds
};

/// The members of a config file in key order; throws std::runtime_error "config file '<path>' is
/// not valid JSON: ..." or "... must hold an object".
[[nodiscard]] std::vector<ConfigMember> parse_config_file(std::istream& in,
                                                          const std::string& path);

/// `value` as JSON writes a number (shortest text that reads back the same: 0.5, 600.0).
[[nodiscard]] std::string json_number_text(double value);

}  // namespace slosh::api
