#pragma once
// Query-string parameters as HTTP handlers receive them (every value of a parameter, in order) and
// the readers every route uses: a parameter given at most once, a decimal number read whole, a
// whole number in a range. Each refusal is an ApiError naming the parameter and its value.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace slosh::service {

/// Every value of one query parameter, in order (none: the parameter was not given).
using QueryValues = std::vector<std::string>;

/// The one value of the query parameter `name`: nullopt when it is not given; throws
/// ApiError(kInvalidValue, name) when it is given more than once ("master_period is given
/// twice (360 and 720): give each query parameter once"; a repeated parameter is never
/// resolved silently).
[[nodiscard]] std::optional<std::string> single_query_value(const QueryValues& values,
                                                            const std::string& name);

/// The number `text` of the query parameter `name`, read whole as a decimal number as a person
/// writes it (`-`, digits, an optional fraction and exponent: no `+`, spaces, hex, inf or nan);
/// a number beyond the range of a double (1e400, 1e-400) is refused, never rounded to inf or 0.
/// Throws ApiError(kInvalidValue, name), e.g. "master_start = 0x10 is not a decimal number
/// [master units]" (`unit` in the brackets).
[[nodiscard]] double query_decimal(const std::string& text, const std::string& name,
                                   std::string_view unit);

/// A whole number within [lo, hi] from the query parameter `name` given at most once; `fallback`
/// when it is absent. Throws ApiError(kInvalidValue, name) naming the value and the range.
[[nodiscard]] std::size_t query_count(const QueryValues& values, const std::string& name,
                                      std::size_t fallback, std::size_t lo, std::size_t hi);

}  // namespace slosh::service
