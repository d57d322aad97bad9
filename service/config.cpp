#include "config.hpp"

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace slosh::service {

namespace {

int parse_port(const std::string& where, const std::string& text) {
  std::size_t used = 0;
  int port = -1;
  try {
    port = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || port < 0 || port > 65535) {
    throw std::runtime_error(where + " = " + text + " is not a TCP port: allowed 0 to 65535");
  }
  return port;
}

}  // namespace

void apply_config_file(const std::string& path, ServerConfig& config) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read config file '" + path + "'");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error("config file '" + path + "' is not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw std::runtime_error("config file '" + path + "' must hold an object");
  for (const auto& [key, value] : j.items()) {
    const std::string where = path + ": " + key;
    if (key == "host") {
      if (!value.is_string() || value.get<std::string>().empty()) {
        throw std::runtime_error(where + " = " + value.dump() + " must be a non-empty text");
      }
      config.host = value.get<std::string>();
    } else if (key == "port") {
      if (!value.is_number_integer()) {
        throw std::runtime_error(where + " = " + value.dump() +
                                 " is not a TCP port: allowed 0 to 65535");
      }
      config.port = parse_port(where, value.dump());
    } else {
      throw std::runtime_error(where + " is not a known setting; allowed: host, port");
    }
  }
}

void apply_environment(const std::map<std::string, std::string>& environment,
                       ServerConfig& config) {
  if (auto it = environment.find("SLOSH_HOST"); it != environment.end() && !it->second.empty()) {
    config.host = it->second;
  }
  if (auto it = environment.find("SLOSH_PORT"); it != environment.end() && !it->second.empty()) {
    config.port = parse_port("SLOSH_PORT", it->second);
  }
}

std::map<std::string, std::string> slosh_environment() {
  std::map<std::string, std::string> env;
  for (const char* name : {"SLOSH_HOST", "SLOSH_PORT"}) {
    if (const char* value = std::getenv(name)) env[name] = value;
  }
  return env;
}

}  // namespace slosh::service
