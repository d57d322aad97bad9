#pragma once
// The service's JSON config file (config/slosh.json): read here into typed members that the
// service's settings table checks (the service sees no JSON).

#include <string>
#include <vector>

namespace slosh::api {

/// One member of a config file's top-level object.
struct ConfigMember {
  enum class Type { kString, kNumber, kBoolean, kOther };
  std::string key;
  Type type{Type::kOther};
  /// A string's content; any other value's JSON text (80, 1.5, true, [1]).
  std::string text;
  /// The value's JSON text (a string with its quotes), for messages.
  std::string json;
};

/// The members of the config file `path` whose contents are `text`, in key order. Throws
/// std::runtime_error "config file '<path>' is not valid JSON: <parser's reason>" or "config
/// file '<path>' must hold an object".
[[nodiscard]] std::vector<ConfigMember> parse_config_file(const std::string& path,
                                                          const std::string& text);

/// A number as JSON writes it (the shortest text that reads back the same double, "600.0" for a
/// whole one): the bounds of a duration setting in messages.
[[nodiscard]] std::string json_number_text(double v);

}  // namespace slosh::api
