#include "export/cam_numbers.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <system_error>

namespace slosh::service {

namespace {

/// Significant digits of an ST real literal: the most that every decimal keeps through an LREAL
/// (IEEE double) and back, so k * period prints as 0.3, not 0.30000000000000004 [-].
constexpr int kStRealDigits = 15;

}  // namespace

std::string csv_number(double v) {
  if (v == 0.0) return "0";  // also -0
  // Decimal notation (0.0003, not 3e-04): controllers' CSV importers do not all read exponents.
  // Only a value whose decimal text is longer than kMaxCsvCell (a round-off residue such as
  // 1.2345678901234566e-13, far below any figure of a plan) keeps the exponent form.
  std::array<char, 64> buffer{};
  auto written =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), v, std::chars_format::fixed);
  if (written.ec != std::errc{} ||
      static_cast<std::size_t>(written.ptr - buffer.data()) > kMaxCsvCell) {
    written = std::to_chars(buffer.data(), buffer.data() + buffer.size(), v);
  }
  return {buffer.data(), written.ptr};
}

std::string st_real_literal(double v) {
  if (!std::isfinite(v)) {
    throw std::invalid_argument("a cam table value is not finite: IEC 61131-3 has no literal for " +
                                std::to_string(v));
  }
  if (v == 0.0) return "0.0";  // also -0
  std::array<char, 64> buffer{};
  const auto written = std::to_chars(buffer.data(), buffer.data() + buffer.size(), v,
                                     std::chars_format::general, kStRealDigits);
  const std::string text(buffer.data(), written.ptr);  // "1e-05", "0.3", "1.5e+20", "100"
  const std::size_t e = text.find('e');
  std::string mantissa = text.substr(0, e);
  if (mantissa.find('.') == std::string::npos) mantissa += ".0";
  if (e == std::string::npos) return mantissa;
  return mantissa + "E" + std::to_string(std::stoi(text.substr(e + 1)));
}

}  // namespace slosh::service
