#include "slosh/api/csv_cell.hpp"

namespace slosh::api {

bool formula_leading(std::string_view text) {
  return !text.empty() && std::string_view("=+-@\t\r").find(text.front()) != std::string_view::npos;
}

std::string csv_text_cell(std::string_view text, bool always_quote) {
  const bool neutralise = formula_leading(text);
  const bool quote =
      always_quote || neutralise || text.find_first_of(",\"\r\n") != std::string_view::npos;
  std::string out;
  out.reserve(text.size() + 3);
  if (quote) out += '"';
  if (neutralise) out += '\'';
  for (const char c : text) {
    out += c;
    if (c == '"' && quote) out += '"';
  }
  if (quote) out += '"';
  return out;
}

}  // namespace slosh::api
