#include "slosh/api/config_json.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>

namespace slosh::api {

namespace {

ConfigMember::Kind kind_of(const nlohmann::json& value) {
  if (value.is_boolean()) return ConfigMember::Kind::boolean;
  if (value.is_string()) return ConfigMember::Kind::string;
  if (value.is_number()) return ConfigMember::Kind::number;
  return ConfigMember::Kind::other;
}

}  // namespace

std::vector<ConfigMember> parse_config_file(std::istream& in, const std::string& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error("config file '" + path + "' is not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw std::runtime_error("config file '" + path + "' must hold an object");
  std::vector<ConfigMember> members;
  for (const auto& [key, value] : j.items()) {
    ConfigMember m{key, kind_of(value), value.dump(), {}};
    if (value.is_string()) m.text = value.get<std::string>();
    members.push_back(std::move(m));
  }
  return members;
}

std::string json_number_text(double value) {
  return nlohmann::json(value).dump();
}

}  // namespace slosh::api
