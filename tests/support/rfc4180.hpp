#pragma once
// An RFC 4180 reader of the tests' own (quoted cells, doubled quotes, line breaks inside quotes,
// CRLF), independent of the CSV writer under test. Strict: a quote inside an unquoted cell, text
// after a closing quote or an unterminated quote throws std::runtime_error.

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace slosh::test {

struct Cell {
  std::string text;
  bool quoted{false};
};
using Record = std::vector<Cell>;

inline std::vector<Record> parse_rfc4180(const std::string& text) {
  std::vector<Record> records;
  Record record;
  Cell cell;
  bool in_quotes = false;
  bool after_closing_quote = false;
  auto end_cell = [&] {
    record.push_back(cell);
    cell = Cell{};
    after_closing_quote = false;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_quotes) {
      if (c != '"') {
        cell.text += c;
      } else if (i + 1 < text.size() && text[i + 1] == '"') {
        cell.text += '"';
        ++i;
      } else {
        in_quotes = false;
        after_closing_quote = true;
      }
      continue;
    }
    if (c == '"') {
      if (!cell.text.empty() || cell.quoted) throw std::runtime_error("quote inside a cell");
      cell.quoted = true;
      in_quotes = true;
    } else if (c == ',') {
      end_cell();
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      end_cell();
      records.push_back(std::move(record));
      record.clear();
    } else {
      if (after_closing_quote) throw std::runtime_error("text after a closing quote");
      cell.text += c;
    }
  }
  if (in_quotes) throw std::runtime_error("unterminated quote");
  if (!cell.text.empty() || cell.quoted || !record.empty()) {
    end_cell();
    records.push_back(std::move(record));
  }
  return records;
}

/// The records of `text` as the cells' texts (parse_rfc4180 without the quoting flags).
inline std::vector<std::vector<std::string>> csv_texts(const std::string& text) {
  std::vector<std::vector<std::string>> out;
  for (const Record& record : parse_rfc4180(text)) {
    std::vector<std::string>& row = out.emplace_back();
    for (const Cell& cell : record) row.push_back(cell.text);
  }
  return out;
}

}  // namespace slosh::test
