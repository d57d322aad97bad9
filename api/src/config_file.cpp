#include "slosh/api/config_file.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "slosh/api/error.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::api {

std::vector<ConfigMember> parse_config_file(const std::string& path, const std::string& text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error("config file '" + path + "' is not valid JSON: " + e.what());
  }
  try {
    (void)parse_json_body(text);  // refuses a member given twice, which the parse above keeps last
  } catch (const ApiError& e) {
    throw std::runtime_error("config file '" + path + "': " + e.what());
  }
  if (!j.is_object()) throw std::runtime_error("config file '" + path + "' must hold an object");
  std::vector<ConfigMember> members;
  for (const auto& [key, value] : j.items()) {
    ConfigMember m;
    m.key = key;
    m.type = value.is_string()    ? ConfigMember::Type::kString
             : value.is_number()  ? ConfigMember::Type::kNumber
             : value.is_boolean() ? ConfigMember::Type::kBoolean
                                  : ConfigMember::Type::kOther;
    m.json = value.dump();
    m.text = value.is_string() ? value.get<std::string>() : m.json;
    members.push_back(std::move(m));
  }
  return members;
}

std::string json_number_text(double v) {
  return nlohmann::json(v).dump();
}

}  // namespace slosh::api
