#pragma once
// The query string of a request target as the handlers read it.

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace slosh::service {

/// The decoded query parameters of a request target, in order, repeats included (the HTTP
/// library's parameters drop a repeated identical "name=value" pair, so a repeat of the same
/// value would go unnoticed there). Parsed once per request.
class Query {
 public:
  explicit Query(const std::string& target);
  /// Every name, in order.
  [[nodiscard]] std::vector<std::string> names() const;
  /// Every value of `name`, in order (none when it is not given).
  [[nodiscard]] std::vector<std::string> values(std::string_view name) const;

 private:
  std::vector<std::pair<std::string, std::string>> pairs_;
};

}  // namespace slosh::service
