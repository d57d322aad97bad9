#include "http/query_params.hpp"

#include <charconv>
#include <system_error>

#include "slosh/api/error.hpp"

namespace slosh::service {
namespace {

api::ApiError invalid(const std::string& field, const std::string& message) {
  return api::ApiError(api::ErrorCode::kInvalidValue, field, message);
}

// Whether `text` is a decimal number as a person writes it: an optional "-", digits with an
// optional fraction (or a fraction alone, ".5"), an optional exponent ("e-3", "E+5"). No "+"
// sign, spaces, hex, inf or nan.
bool decimal_number(std::string_view text) {
  std::size_t at = text.starts_with('-') ? 1 : 0;
  std::size_t digits = 0;
  const auto skip_digits = [&] {
    std::size_t n = 0;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9') ++at, ++n;
    return n;
  };
  digits += skip_digits();
  if (at < text.size() && text[at] == '.') {
    ++at;
    digits += skip_digits();
  }
  if (digits == 0) return false;
  if (at < text.size() && (text[at] == 'e' || text[at] == 'E')) {
    ++at;
    if (at < text.size() && (text[at] == '+' || text[at] == '-')) ++at;
    if (skip_digits() == 0) return false;
  }
  return at == text.size();
}

}  // namespace

std::optional<std::string> single_query_value(const QueryValues& values, const std::string& name) {
  if (values.empty()) return std::nullopt;
  if (values.size() == 1) return values.front();
  const std::string count = values.size() == 2 ? "twice" : std::to_string(values.size()) + " times";
  std::string given;
  for (std::size_t i = 0; i < values.size() && i < 3; ++i) {
    if (i > 0) given += i + 1 == values.size() ? " and " : ", ";
    given += values[i].substr(0, 32);
  }
  if (values.size() > 3) given += ", ...";
  throw invalid(name,
                name + " is given " + count + " (" + given + "): give each query parameter once");
}

double query_decimal(const std::string& text, const std::string& name, std::string_view unit) {
  const std::string shown = text.empty() ? "(empty)" : text.substr(0, 32);
  const std::string tail = " [" + std::string(unit) + "]";
  if (!decimal_number(text)) {
    throw invalid(name, name + " = " + shown + " is not a decimal number" + tail);
  }
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error == std::errc::result_out_of_range) {
    throw invalid(name, name + " = " + shown +
                            " is beyond the range of a double: a number is 0 or of a magnitude "
                            "from 4.9e-324 to 1.8e+308" +
                            tail);
  }
  if (error != std::errc() || end != text.data() + text.size()) {
    throw invalid(name, name + " = " + shown + " is not a decimal number" + tail);
  }
  return value;
}

std::size_t query_count(const QueryValues& values, const std::string& name, std::size_t fallback,
                        std::size_t lo, std::size_t hi) {
  const std::optional<std::string> text = single_query_value(values, name);
  if (!text) return fallback;
  const bool digits = !text->empty() && text->size() <= 12 &&
                      text->find_first_not_of("0123456789") == std::string::npos;
  const std::size_t value = digits ? std::stoull(*text) : 0;
  if (!digits || value < lo || value > hi) {
    throw invalid(name, name + " = " + (text->empty() ? "(empty)" : text->substr(0, 32)) +
                            " is not allowed: a whole number from " + std::to_string(lo) + " to " +
                            std::to_string(hi));
  }
  return value;
}

}  // namespace slosh::service
