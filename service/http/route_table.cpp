#include "http/route_table.hpp"

#include <algorithm>

namespace slosh::service {

std::string path_pattern(std::string_view path) {
  std::string out;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (path[i] == '{') {
      out += "([^/]+)";
      i = path.find('}', i);
    } else {
      out += path[i];
    }
  }
  return out;
}

RouteTable::RouteTable(std::span<const api::Route> routes) {
  for (const api::Route& route : routes) {
    const std::string source = path_pattern(route.path);
    entries_.push_back({&route, source});
    auto it = std::find_if(paths_.begin(), paths_.end(),
                           [&](const Path& p) { return p.source == source; });
    if (it == paths_.end()) {
      paths_.push_back({std::regex(source), source, std::string(route.path), {}});
      it = std::prev(paths_.end());
    }
    it->methods.emplace_back(route.method);
    if (route.method == "GET") it->methods.emplace_back("HEAD");  // the library answers HEAD
  }
}

RouteTable::Match RouteTable::match(std::string_view path) const {
  Match m;
  const Path* best = nullptr;
  const auto parameters = [](const std::string& label) {
    return std::count(label.begin(), label.end(), '{');
  };
  for (const Path& p : paths_) {
    if (!std::regex_match(path.begin(), path.end(), p.pattern)) continue;
    m.allowed.insert(m.allowed.end(), p.methods.begin(), p.methods.end());
    if (!best || parameters(p.label) < parameters(best->label)) best = &p;
  }
  if (best) m.label = best->label;
  return m;
}

std::string allow_header(const std::vector<std::string>& methods) {
  std::string allow;
  for (const std::string& m : methods) allow += (allow.empty() ? "" : ", ") + m;
  return allow;
}

}  // namespace slosh::service
