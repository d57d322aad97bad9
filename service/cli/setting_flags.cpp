#include "cli/setting_flags.hpp"

namespace slosh::service {

std::string setting_help(const std::string& lead, std::string_view key,
                         const ServerConfig& defaults, const std::string& default_text) {
  const std::string shown = default_text.empty() ? setting_text(key, defaults) : default_text;
  const std::string env = std::string("env ") + setting_limits(key).env;
  return lead + " [" + (shown.empty() ? env : "default " + shown + "; " + env) + "]";
}

}  // namespace slosh::service
