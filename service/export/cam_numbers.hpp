#pragma once
// The numbers of a cam table file: a CSV cell and an IEC 61131-3 real literal.

#include <cstddef>
#include <string>

namespace slosh::service {

/// Longest CSV cell: csv_number's decimal text up to it, else the shortest round trip of a
/// double ("-2.2250738585072014e-308") [characters].
inline constexpr std::size_t kMaxCsvCell = 24;
/// Longest ST real literal (15 digits, sign, point, "E-308") [characters].
inline constexpr std::size_t kMaxStLiteral = 22;

/// `v` as a CSV cell: the shortest decimal text that reads back as `v` exactly ("800", "0.1",
/// "0.0003", "0.000012345678901234567"; std::to_chars, fixed), never "-0" (12 significant digits
/// did not hold a stroke of many digits exactly in the last row). Controllers' CSV importers do
/// not all read exponents: only a value whose decimal text is longer than kMaxCsvCell, a round-off
/// residue far below any figure of a plan, keeps the shortest exponent form.
[[nodiscard]] std::string csv_number(double v);

/// `v` as an IEC 61131-3 real literal with 15 significant digits (trailing zeros dropped), always
/// a digit on each side of the point and an upper-case exponent without "+" or leading zeros
/// ("0.0", "-12.5", "0.3", "1.25E-3", "6.02E23"). Throws std::invalid_argument for a non-finite
/// value (IEC 61131-3 has no literal for it).
[[nodiscard]] std::string st_real_literal(double v);

}  // namespace slosh::service
