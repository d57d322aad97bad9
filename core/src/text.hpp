#pragma once
// Number formatting for the human messages of the core (internal).

#include <cstdio>
#include <sstream>
#include <string>

namespace slosh::detail {

/// v with `digits` decimals ("0.650").
inline std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

/// v with `digits` significant digits ("%g" style: "7.93", "0.0123", "3.600001081e-05").
inline std::string significant(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

/// v as an ostream prints it with 10 significant digits ("0.1", "1e-12"): input echoed in an
/// error message, close enough to what was sent to be recognised.
inline std::string precise(double v) {
  std::ostringstream out;
  out.precision(10);
  out << v;
  return out.str();
}

/// `ratio`, below `limit`, to 3 decimals or as many more as show it below the limit's text
/// (0.23992 against 0.24 reads "0.23992", not "0.240").
inline std::string fixed_below(double ratio, double limit) {
  int digits = 3;
  while (digits < 12 && std::stod(fixed(ratio, digits)) >= limit) ++digits;
  return fixed(ratio, digits);
}

/// `value`, above `limit`, to 2 decimals or as many more as show it above the limit's text
/// (0.6804 against 0.68 reads "0.6804", not "0.68").
inline std::string fixed_above(double value, double limit) {
  int digits = 2;
  while (digits < 12 && std::stod(fixed(value, digits)) <= limit) ++digits;
  return fixed(value, digits);
}

/// v with 3 significant digits ("7.93", "0.0123").
inline std::string sig3(double v) {
  return significant(v, 3);
}

/// `value`, above `limit`, to 3 significant digits or as many more as show it above the limit's
/// text (2.0004 against 2 reads "2.0004", not "2").
inline std::string sig_above(double value, double limit) {
  int digits = 3;
  while (digits < 15 && std::stod(significant(value, digits)) <= limit) ++digits;
  return significant(value, digits);
}

/// A fraction as a percentage with 3 significant digits ("12.5 %").
inline std::string percent(double fraction) {
  return sig3(100.0 * fraction) + " %";
}

}  // namespace slosh::detail
