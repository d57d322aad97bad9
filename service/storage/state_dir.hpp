#pragma once
// The per-user state directory of the plan store (XDG Base Directory specification): the default
// `cache` is "${XDG_STATE_HOME}/slosh/plans.sqlite", so `serve`, `batch` and `export` never write
// a SQLite file into whatever directory they are started from.

#include <map>
#include <string>

namespace slosh::service {

/// The placeholder a `cache` setting may start with; it stands for the state home.
inline constexpr const char* kStateHomePlaceholder = "${XDG_STATE_HOME}";

/// The default `cache` setting (config/slosh.json holds the same text).
inline constexpr const char* kDefaultCachePath = "${XDG_STATE_HOME}/slosh/plans.sqlite";

/// The state home: $XDG_STATE_HOME when set to an absolute path, else $HOME/.local/state (the
/// specification's default; a relative XDG_STATE_HOME is ignored, as the specification says).
/// Throws std::runtime_error when neither is usable. `environment` holds XDG_STATE_HOME and HOME.
[[nodiscard]] std::string state_home(const std::map<std::string, std::string>& environment);

/// XDG_STATE_HOME and HOME of the process environment (absent ones are left out).
[[nodiscard]] std::map<std::string, std::string> state_environment();

/// `cache` with a leading ${XDG_STATE_HOME} replaced by the state home; any other path (and "",
/// memory only) unchanged. Throws as state_home does.
[[nodiscard]] std::string resolve_cache_path(const std::string& cache,
                                             const std::map<std::string, std::string>& environment);

/// Creates the directories of a resolved path below the state home that do not exist yet, each
/// with mode 0700 (the specification's mode); paths outside the state home are left alone. Throws
/// std::runtime_error naming the directory when one cannot be created.
void ensure_state_directory(const std::string& cache, const std::string& resolved);

}  // namespace slosh::service
