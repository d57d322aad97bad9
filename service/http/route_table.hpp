#pragma once
// The service's routes (api::routes()) as the HTTP layer matches paths against them: one table
// that the registration, the 404/405 answers and the route label of every request (metrics and
// access log) all read, so that a path is labelled the same way whichever part answers it.

#include <regex>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "slosh/api/routes.hpp"

namespace slosh::service {

/// "/v1/plans/{key}" -> "/v1/plans/([^/]+)": the regular expression of a route's path template.
[[nodiscard]] std::string path_pattern(std::string_view path);

class RouteTable {
 public:
  /// What the table says about a path, whatever the method.
  struct Match {
    /// The path template of the route the path belongs to: the most literal of those whose
    /// pattern it matches ("/v1/plans/batch" over "/v1/plans/{key}"); "other" for none.
    std::string label{"other"};
    /// The methods the matching routes answer, in table order (GET adds HEAD): 405's Allow.
    std::vector<std::string> allowed;
  };

  /// A route of the table with the regular expression its path is registered under.
  struct Entry {
    const api::Route* route;
    std::string pattern;  // path_pattern(route->path)
  };

  /// The table of `routes` (kept by reference: they must outlive the table).
  explicit RouteTable(std::span<const api::Route> routes);

  [[nodiscard]] Match match(std::string_view path) const;
  /// Every route, in table order: what the server registers, one handler per entry.
  [[nodiscard]] const std::vector<Entry>& entries() const { return entries_; }

 private:
  std::vector<Entry> entries_;
  // One per path template, with every method the routes of that template answer.
  struct Path {
    std::regex pattern;
    std::string source;  // the pattern's text
    std::string label;
    std::vector<std::string> methods;
  };
  std::vector<Path> paths_;
};

/// "GET, HEAD, DELETE": an Allow header's value.
[[nodiscard]] std::string allow_header(const std::vector<std::string>& methods);

}  // namespace slosh::service
