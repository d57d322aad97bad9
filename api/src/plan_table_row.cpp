#include "slosh/api/plan_table_row.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "slosh/api/error.hpp"

namespace slosh::api {

PlanTableRow table_row_of(nlohmann::json document) {
  PlanTableRow row;
  const auto number = document.find("row");
  row.number_text = number == document.end() ? "null" : dump_json(*number);
  if (number != document.end() && number->is_number_unsigned()) {
    row.number = number->get<std::size_t>();
  }
  row.status = document.at("status").get<std::string>();
  row.failed = row.status == "error";
  const auto cached = document.find("cached");
  row.cached = cached != document.end() && cached->is_boolean() && cached->get<bool>();
  row.document = std::move(document);
  return row;
}

std::vector<PlanTableRow> parse_table_rows(std::string_view text) {
  std::vector<PlanTableRow> rows;
  std::size_t line = 0;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view cells = text.substr(at, end - at);
    at = end + 1;
    ++line;
    if (cells.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    nlohmann::json document = nlohmann::json::parse(cells, nullptr, false);
    if (document.is_discarded() || !document.is_object() || !document.contains("status") ||
        !document["status"].is_string()) {
      throw std::runtime_error("line " + std::to_string(line) +
                               " of the results is not a plan-table row");
    }
    rows.push_back(table_row_of(std::move(document)));
  }
  return rows;
}

}  // namespace slosh::api
