#include "storage/state_dir.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace slosh::service {

namespace fs = std::filesystem;

std::string state_home(const std::map<std::string, std::string>& environment) {
  if (auto it = environment.find("XDG_STATE_HOME");
      it != environment.end() && !it->second.empty() && it->second.front() == '/') {
    return it->second;
  }
  if (auto it = environment.find("HOME"); it != environment.end() && !it->second.empty()) {
    return it->second + "/.local/state";
  }
  throw std::runtime_error(
      "cache = " + std::string(kDefaultCachePath) +
      ": neither XDG_STATE_HOME (an absolute path) nor HOME is set; give --cache FILE, or "
      "--cache \"\" for a memory-only cache");
}

std::map<std::string, std::string> state_environment() {
  std::map<std::string, std::string> env;
  for (const char* name : {"XDG_STATE_HOME", "HOME"}) {
    if (const char* value = std::getenv(name)) env[name] = value;
  }
  return env;
}

std::string resolve_cache_path(const std::string& cache,
                               const std::map<std::string, std::string>& environment) {
  const std::string placeholder = kStateHomePlaceholder;
  if (!cache.starts_with(placeholder)) return cache;
  return state_home(environment) + cache.substr(placeholder.size());
}

void ensure_state_directory(const std::string& cache, const std::string& resolved) {
  if (!cache.starts_with(kStateHomePlaceholder)) return;
  const fs::path parent = fs::path(resolved).parent_path();
  // The missing directories, outermost first, each created with 0700.
  std::vector<fs::path> missing;
  for (fs::path p = parent; !p.empty() && !fs::exists(p); p = p.parent_path()) {
    missing.insert(missing.begin(), p);
    if (p == p.root_path()) break;
  }
  for (const fs::path& dir : missing) {
    if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) {
      throw std::runtime_error("cannot create the state directory " + dir.string() + ": " +
                               std::strerror(errno));
    }
  }
}

}  // namespace slosh::service
