#pragma once
// One name table per enum: the names an enum value has in the API, the CLI, the recipe tables and
// the messages. Each enum declares its table next to itself as a specialisation of EnumNames; the
// functions below are the only way names are read, so a value is named in exactly one place.

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace slosh {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

/// Specialise with `static constexpr std::array<EnumName<E>, N> table{...}`, in the order the API
/// lists the names.
template <class E>
struct EnumNames;

/// The name of `value` (empty for a value outside the table).
template <class E>
[[nodiscard]] constexpr std::string_view name_of(E value) {
  for (const auto& entry : EnumNames<E>::table) {
    if (entry.value == value) return entry.name;
  }
  return {};
}

/// The value named `name`; nullopt when no value has that name.
template <class E>
[[nodiscard]] constexpr std::optional<E> enum_from_name(std::string_view name) {
  for (const auto& entry : EnumNames<E>::table) {
    if (entry.name == name) return entry.value;
  }
  return std::nullopt;
}

/// Every name, in table order.
template <class E>
[[nodiscard]] std::vector<std::string> enum_names() {
  std::vector<std::string> names;
  for (const auto& entry : EnumNames<E>::table) names.emplace_back(entry.name);
  return names;
}

/// Every value, in table order.
template <class E>
[[nodiscard]] std::vector<E> enum_values() {
  std::vector<E> values;
  for (const auto& entry : EnumNames<E>::table) values.push_back(entry.value);
  return values;
}

}  // namespace slosh
