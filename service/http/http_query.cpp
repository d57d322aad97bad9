#include "http/http_query.hpp"

#include <httplib.h>

namespace slosh::service {

Query::Query(const std::string& target) {
  const std::size_t query = target.find('?');
  if (query == std::string::npos) return;
  const std::string text = target.substr(query + 1, target.find('#') - query - 1);
  httplib::detail::split(
      text.data(), text.data() + text.size(), '&', [&](const char* begin, const char* end) {
        const std::string pair(begin, end);
        const std::size_t equals = pair.find('=');
        pairs_.emplace_back(httplib::detail::decode_url(pair.substr(0, equals), true),
                            equals == std::string::npos
                                ? std::string()
                                : httplib::detail::decode_url(pair.substr(equals + 1), true));
      });
}

std::vector<std::string> Query::names() const {
  std::vector<std::string> out;
  for (const auto& pair : pairs_) out.push_back(pair.first);
  return out;
}

std::vector<std::string> Query::values(std::string_view name) const {
  std::vector<std::string> out;
  for (const auto& [n, value] : pairs_) {
    if (n == name) out.push_back(value);
  }
  return out;
}

}  // namespace slosh::service
