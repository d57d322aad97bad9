#pragma once
// Typed access to JSON request fields with validation messages that name the field path, the
// value and the allowed range: "format.radius_mm = -3 is out of range: allowed 1 to 2000 mm".

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace slosh::api {

/// Closed or open numeric range with a unit for messages.
struct Range {
  double lo;
  double hi;
  std::string_view unit;
  bool lo_open{false};  ///< lo excluded
  bool hi_open{false};  ///< hi excluded
  [[nodiscard]] bool contains(double v) const;
  [[nodiscard]] std::string describe() const;  ///< "1 to 2000 mm", "> 0 and <= 5000 mm"
};

/// The member `key` of `object`, or nullptr when absent; a null member is returned as it is.
[[nodiscard]] const nlohmann::json* find_member(const nlohmann::json& object, std::string_view key);

/// Whether position `at` of a message lies inside a quoted JSON string (a value the message
/// echoes, as show() writes it): the rewriting of the paths a message names leaves those alone.
[[nodiscard]] bool inside_json_string(std::string_view text, std::size_t at);

/// The member `key` of `object`, or nullptr when absent or null: null counts as absent (the
/// request convention for optional members).
[[nodiscard]] const nlohmann::json* given_member(const nlohmann::json& object,
                                                 std::string_view key);

/// "a.b" + "c" -> "a.b.c"
[[nodiscard]] std::string join_path(std::string_view parent, std::string_view key);

/// A number as messages print it (10 significant digits, no trailing zeros).
[[nodiscard]] std::string number_text(double v);

/// Millimetres of a length that the API received in millimetres and keeps in metres (read as
/// mm * 1e-3): the shortest decimal whose conversion gives `metres` back. A length given as 51 mm
/// echoes as 51, not as metres * 1e3 = 51.00000000000001; the echo is exact (read again, it is
/// `metres`), so it is the number of every request of the same recipe. A value that no millimetre
/// value converts to (a computed length), and a non-finite one, is returned as metres * 1e3.
[[nodiscard]] double mm_of(double metres);

/// Percent of a fraction that the API received in percent and keeps as a fraction (read as
/// pct * 0.01), as mm_of does for millimetres: 5 % echoes as 5, not as 5.000000000000001.
[[nodiscard]] double pct_of(double fraction);

/// Degrees of an angle that the API received in degrees and keeps in radians (read as
/// deg * pi / 180), as mm_of does for millimetres: 90 deg echoes as 90.
[[nodiscard]] double deg_of(double radians);

/// Compact JSON text of a value for messages, cut to 60 bytes on a UTF-8 boundary.
[[nodiscard]] std::string show(const nlohmann::json& value);

/// Throws ApiError(kInternal) naming the first member path of `value` that holds a NaN or an
/// infinity (JSON has no such numbers: they would go out as null). The last guard of every
/// response the service renders.
void require_finite(const nlohmann::json& value);

/// Throws ApiError(kInvalidValue) unless `object` is a JSON object.
void require_object(const nlohmann::json& object, const std::string& path);

/// Rejects members of `object` not in `allowed` (catches typos such as "radius" for "radius_mm").
void reject_unknown_fields(const nlohmann::json& object, const std::string& path,
                           const std::vector<std::string_view>& allowed);

/// A required number within `range`.
[[nodiscard]] double required_number(const nlohmann::json& object, const std::string& path,
                                     std::string_view key, const Range& range);

/// The number `value` (null when absent) named `field` within `range`; `below_range_hint` is
/// appended to the message when the value is below the range.
[[nodiscard]] double checked_number(const nlohmann::json* value, const std::string& field,
                                    const Range& range, std::string_view below_range_hint = {});

/// An optional number within `range`; `fallback` when absent.
[[nodiscard]] double optional_number(const nlohmann::json& object, const std::string& path,
                                     std::string_view key, const Range& range, double fallback);

/// An optional integer within [lo, hi].
[[nodiscard]] int optional_integer(const nlohmann::json& object, const std::string& path,
                                   std::string_view key, int lo, int hi, int fallback);

/// An optional boolean.
[[nodiscard]] bool optional_bool(const nlohmann::json& object, const std::string& path,
                                 std::string_view key, bool fallback);

/// "\"a\", \"b\", \"c\"": the names a message offers.
[[nodiscard]] std::string quoted_names(const std::vector<std::string>& names);

/// Throws ApiError(kInvalidValue) for `path` with `message`.
[[noreturn]] void invalid(const std::string& path, const std::string& message);

}  // namespace slosh::api
