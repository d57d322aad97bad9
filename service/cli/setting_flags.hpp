#pragma once
// Command-line flags that set an entry of the settings table (config/config.cpp): the range a
// flag checks, and the environment variable and default its help names, come from that table, so
// a flag, the config file and the environment accept the same values.

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

#include "config/config.hpp"

namespace slosh::service {

/// The help of the flag of setting `key`: `lead` (what it does, with its unit) then
/// " [default D; env E]", D being `default_text` or, when that is empty, the value of `key` in
/// `defaults` ("[env E]" alone when that is empty too).
[[nodiscard]] std::string setting_help(const std::string& lead, std::string_view key,
                                       const ServerConfig& defaults,
                                       const std::string& default_text = "");

/// Adds `flag` (e.g. "--workers") for the setting `key` (e.g. "workers") storing into `into`; an
/// integer setting checks the table's range at parse time (CLI11's message: "--workers: Value 2000
/// not in range 0 to 1024").
template <typename T>
CLI::Option* add_setting_option(CLI::App& app, const std::string& flag, std::string_view key,
                                std::optional<T>& into, const std::string& help) {
  CLI::Option* option = app.add_option(flag, into, help);
  if constexpr (std::is_integral_v<T>) {
    const SettingLimits limits = setting_limits(key);
    option->check(CLI::Range(static_cast<T>(limits.lo), static_cast<T>(limits.hi)));
  }
  return option;
}

}  // namespace slosh::service
