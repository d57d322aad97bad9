#include "slosh/api/fields.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include "slosh/api/control_characters.hpp"

#include "slosh/api/error.hpp"
#include "slosh/api/exact_number.hpp"
#include "slosh/core/constants.hpp"

namespace slosh::api {

const nlohmann::json* find_member(const nlohmann::json& object, std::string_view key) {
  if (!object.is_object()) return nullptr;
  auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

const nlohmann::json* given_member(const nlohmann::json& object, std::string_view key) {
  const nlohmann::json* value = find_member(object, key);
  return value == nullptr || value->is_null() ? nullptr : value;
}

bool inside_json_string(std::string_view text, std::size_t at) {
  bool quoted = false;
  for (std::size_t i = 0; i < at && i < text.size(); ++i) {
    if (quoted && text[i] == '\\') {
      ++i;  // an escaped character, a quote included
    } else if (text[i] == '"') {
      quoted = !quoted;
    }
  }
  return quoted;
}

std::string number_text(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

std::string exact_number_text(double v) {
  if (!std::isfinite(v)) return number_text(v);
  for (int digits = 10; digits < 17; ++digits) {
    std::ostringstream os;
    os.precision(digits);
    os << v;
    if (std::strtod(os.str().c_str(), nullptr) == v) return os.str();
  }
  std::ostringstream os;
  os.precision(17);  // every double reads back from 17 significant digits
  os << v;
  return os.str();
}

namespace {

/// The shortest decimal near `start` whose conversion (x * scale) gives `si` back; `start` when
/// none is found (a computed value no user value converts to).
double shortest_decimal(double start, double si, double scale) {
  if (!std::isfinite(start)) return start;
  // The shortest decimal near the product that converts back (a value typed with up to 15
  // significant digits is found at its own digits).
  constexpr int kMaxDigits = 17;
  std::array<char, 40> text{};
  for (int digits = 1; digits <= kMaxDigits; ++digits) {
    const auto printed = std::to_chars(text.data(), text.data() + text.size(), start,
                                       std::chars_format::general, digits);
    double candidate = 0.0;
    std::from_chars(text.data(), printed.ptr, candidate);
    if (candidate * scale == si) return candidate;
  }
  // The product may miss every preimage by an ulp or two: the nearest double that converts back.
  constexpr int kNeighbourUlps = 4;
  double below = start;
  double above = start;
  for (int step = 0; step < kNeighbourUlps; ++step) {
    below = std::nextafter(below, -std::numeric_limits<double>::infinity());
    above = std::nextafter(above, std::numeric_limits<double>::infinity());
    if (below * scale == si) return below;
    if (above * scale == si) return above;
  }
  return start;
}

}  // namespace

double mm_of(double metres) {
  return shortest_decimal(metres * 1e3, metres, 1e-3);
}

double pct_of(double fraction) {
  return shortest_decimal(fraction * 100.0, fraction, 0.01);
}

double deg_of(double radians) {
  return shortest_decimal(radians / kRadPerDeg, radians, kRadPerDeg);
}

bool Range::contains(double v) const {
  const bool lo_ok = lo_open ? v > lo : v >= lo;
  const bool hi_ok = hi_open ? v < hi : v <= hi;
  return lo_ok && hi_ok;
}

std::string Range::describe() const {
  std::ostringstream os;
  if (!lo_open && !hi_open) {
    os << number_text(lo) << " to " << number_text(hi);
  } else {
    os << (lo_open ? "> " : ">= ") << number_text(lo) << " and " << (hi_open ? "< " : "<= ")
       << number_text(hi);
  }
  if (!unit.empty()) os << ' ' << unit;
  return os.str();
}

std::string join_path(std::string_view parent, std::string_view key) {
  if (parent.empty()) return std::string(key);
  return std::string(parent) + "." + std::string(key);
}

namespace {

constexpr std::size_t kPreviewChars = 60;

// Appends the JSON text of `value` to `out`, stopping once `out` holds more than kPreviewChars:
// an untrusted value is never dumped whole (its size and nesting are the sender's choice).
void preview(const nlohmann::json& value, std::string& out) {
  if (out.size() > kPreviewChars) return;
  if (value.is_array()) {
    out += '[';
    bool first = true;
    for (const auto& item : value) {
      if (out.size() > kPreviewChars) return;
      if (!first) out += ',';
      first = false;
      preview(item, out);
    }
    out += ']';
  } else if (value.is_object()) {
    out += '{';
    bool first = true;
    for (const auto& [key, item] : value.items()) {
      if (out.size() > kPreviewChars) return;
      if (!first) out += ',';
      first = false;
      out += nlohmann::json(key).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
      out += ':';
      preview(item, out);
    }
    out += '}';
  } else {
    out += value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  }
}

}  // namespace

std::string show(const nlohmann::json& value) {
  std::string s;
  preview(value, s);
  if (s.size() <= kPreviewChars) return s;
  // Cut at a UTF-8 character boundary so the message stays valid UTF-8.
  std::size_t cut = 57;
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
  return s.substr(0, cut) + "...";
}

namespace {

// Whether every number of `value` is finite: depth-first with an explicit stack (no recursion).
bool all_finite(const nlohmann::json& value) {
  std::vector<const nlohmann::json*> stack{&value};
  while (!stack.empty()) {
    const nlohmann::json* v = stack.back();
    stack.pop_back();
    if (v->is_number_float()) {
      if (!std::isfinite(v->get<double>())) return false;
    } else if (v->is_structured()) {
      for (const auto& item : *v) stack.push_back(&item);
    }
  }
  return true;
}

// The path of the first non-finite number (a second, slower walk once one is known to exist; the
// responses it walks are the service's own, a few levels deep).
std::string first_non_finite(const nlohmann::json& value, const std::string& path) {
  if (value.is_number_float())
    return std::isfinite(value.get<double>()) ? "" : path.empty() ? "(root)" : path;
  if (value.is_array()) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      std::string at = first_non_finite(value[i], path + "[" + std::to_string(i) + "]");
      if (!at.empty()) return at;
    }
  } else if (value.is_object()) {
    for (const auto& [key, item] : value.items()) {
      std::string at = first_non_finite(item, join_path(path, key));
      if (!at.empty()) return at;
    }
  }
  return "";
}

}  // namespace

void require_finite(const nlohmann::json& value) {
  if (all_finite(value)) return;
  const std::string path = first_non_finite(value, "");
  throw ApiError(
      ErrorCode::kInternal, "",
      "the response would carry a non-finite number at '" + path + "'; please report the request");
}

std::string quoted_names(const std::vector<std::string>& names) {
  std::string list;
  for (const auto& name : names) list += (list.empty() ? "\"" : ", \"") + name + "\"";
  return list;
}

void invalid(const std::string& path, const std::string& message) {
  throw ApiError(ErrorCode::kInvalidValue, path, message);
}

void refuse_control_characters(const std::string& path, std::string_view text) {
  const auto control = std::find_if(text.begin(), text.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
  });
  if (control != text.end()) {
    invalid(path, path + " must not hold control characters (NUL, tab, line breaks, ...), got " +
                      show(nlohmann::json(std::string(text))));
  }
}

void require_object(const nlohmann::json& object, const std::string& path) {
  if (!object.is_object()) {
    invalid(path, (path.empty() ? std::string("the request") : path) +
                      " must be a JSON object, got " + show(object));
  }
}

void reject_unknown_fields(const nlohmann::json& object, const std::string& path,
                           const std::vector<std::string_view>& allowed) {
  for (const auto& [key, value] : object.items()) {
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    invalid(join_path(path, key),
            join_path(path, key) + " is not a known field; allowed here: " + list);
  }
}

double required_number(const nlohmann::json& object, const std::string& path, std::string_view key,
                       const Range& range) {
  return checked_number(find_member(object, key), join_path(path, key), range);
}

double checked_number(const nlohmann::json* v, const std::string& field, const Range& range,
                      std::string_view below_range_hint) {
  if (v == nullptr || v->is_null()) {
    invalid(field, field + " is required: a number, allowed " + range.describe());
  }
  if (!v->is_number()) {
    invalid(field, field + " must be a number, got " + show(*v) + "; allowed " + range.describe());
  }
  const double x = v->get<double>();
  if (!std::isfinite(x) || !range.contains(x)) {
    std::string message =
        field + " = " + exact_number_text(x) + " is out of range: allowed " + range.describe();
    if (x < range.lo) message += below_range_hint;
    invalid(field, message);
  }
  return x;
}

double optional_number(const nlohmann::json& object, const std::string& path, std::string_view key,
                       const Range& range, double fallback) {
  const nlohmann::json* v = given_member(object, key);
  if (v == nullptr) return fallback;
  return required_number(object, path, key, range);
}

int optional_integer(const nlohmann::json& object, const std::string& path, std::string_view key,
                     int lo, int hi, int fallback) {
  const std::string field = join_path(path, key);
  const nlohmann::json* v = given_member(object, key);
  if (v == nullptr) return fallback;
  const std::string allowed = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
  if (!v->is_number()) invalid(field, field + " must be " + allowed + ", got " + show(*v));
  const double x = v->get<double>();
  if (x != std::floor(x)) {
    invalid(field, field + " = " + exact_number_text(x) + " is not an integer: allowed " + allowed);
  }
  if (x < lo || x > hi) {
    invalid(field, field + " = " + exact_number_text(x) + " is out of range: allowed " + allowed);
  }
  return static_cast<int>(x);
}

bool optional_bool(const nlohmann::json& object, const std::string& path, std::string_view key,
                   bool fallback) {
  const nlohmann::json* v = given_member(object, key);
  if (v == nullptr) return fallback;
  if (!v->is_boolean()) {
    const std::string field = join_path(path, key);
    invalid(field, field + " must be true or false, got " + show(*v));
  }
  return v->get<bool>();
}

}  // namespace slosh::api
