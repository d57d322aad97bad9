#include "http/plan_facts.hpp"

namespace slosh::service {

namespace {

// The string value of the last member `"name": "value"` in `text` (whitespace allowed around the
// colon, as pretty-printed); a quote preceded by a backslash is inside a string, not a member.
std::string last_string_member(std::string_view text, std::string_view name) {
  const std::string needle = "\"" + std::string(name) + "\"";
  std::size_t at = text.rfind(needle);
  while (at != std::string_view::npos) {
    std::size_t i = at + needle.size();
    while (i < text.size() && (text[i] == ' ' || text[i] == '\n')) ++i;
    if (i < text.size() && text[i] == ':' && (at == 0 || text[at - 1] != '\\')) {
      ++i;
      while (i < text.size() && (text[i] == ' ' || text[i] == '\n')) ++i;
      if (i >= text.size() || text[i] != '"') return {};
      const std::size_t end = text.find('"', i + 1);
      return end == std::string_view::npos ? std::string()
                                           : std::string(text.substr(i + 1, end - i - 1));
    }
    if (at == 0) break;
    at = text.rfind(needle, at - 1);
  }
  return {};
}

}  // namespace

PlanFacts plan_facts_of(const std::string& key, std::string_view plan, bool cached) {
  return PlanFacts{key, last_string_member(plan, "strategy"), last_string_member(plan, "status"),
                   cached};
}

}  // namespace slosh::service
