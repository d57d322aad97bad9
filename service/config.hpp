#pragma once
// Service configuration: embedded defaults < config file < environment < command-line flags.

#include <map>
#include <optional>
#include <string>

#include "http_server.hpp"

namespace slosh::service {

/// Reads a JSON config file ({"host": "...", "port": 8080}) over `config`; throws
/// std::runtime_error naming the file, the key, the value and the allowed values.
void apply_config_file(const std::string& path, ServerConfig& config);

/// Applies SLOSH_HOST and SLOSH_PORT from `environment` (name -> value) over `config`; throws
/// std::runtime_error on an invalid value.
void apply_environment(const std::map<std::string, std::string>& environment, ServerConfig& config);

/// The SLOSH_* variables of the process environment.
[[nodiscard]] std::map<std::string, std::string> slosh_environment();

}  // namespace slosh::service
