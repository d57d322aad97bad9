#pragma once
// Text cells of the CSV tables the service writes (plan tables, min-time tables): RFC 4180
// quoting, and text that a spreadsheet would run as a formula neutralised.
//
// A cell whose text begins with '=', '+', '-', '@', a tab or a carriage return is a formula to
// Excel, LibreOffice Calc and Google Sheets (=HYPERLINK(...) sends data away, =cmd|... runs a
// program). Such a text is written with a single quote in front and quoted ("'=HYPERLINK(...)"),
// as OWASP's "CSV injection" guidance and the established CSV writers do: a spreadsheet shows the
// text and never runs it. Only text cells are changed: numbers are written bare (a negative
// number is data), and recipe ids, messages and names are texts.

#include <string>
#include <string_view>

namespace slosh::api {

/// Whether a spreadsheet would read `text` as a formula (its first character is '=', '+', '-',
/// '@', a tab or a carriage return).
[[nodiscard]] bool formula_leading(std::string_view text);

/// The CSV cell of a text: neutralised with a single quote when formula_leading, then quoted
/// (inner quotes doubled) when `always_quote`, when it holds a comma, a quote or a line break,
/// or when it was neutralised.
[[nodiscard]] std::string csv_text_cell(std::string_view text, bool always_quote);

}  // namespace slosh::api
