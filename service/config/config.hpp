#pragma once
// Service configuration: embedded defaults < config file < environment < command-line flags.

#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "http/http_server.hpp"

namespace slosh::service {

/// Reads a JSON config file (keys: host, port, workers, queue, cache, cache_entries,
/// solve_budget_s, max_body_bytes, batch_max, http_threads; config/slosh.json lists the defaults)
/// over `config`, all or nothing; throws std::runtime_error naming the file, the key, the value
/// and the allowed values.
void apply_config_file(const std::string& path, ServerConfig& config);

/// Applies SLOSH_HOST, SLOSH_PORT, SLOSH_WORKERS, SLOSH_QUEUE, SLOSH_CACHE, SLOSH_CACHE_ENTRIES,
/// SLOSH_SOLVE_BUDGET_S, SLOSH_MAX_BODY_BYTES, SLOSH_BATCH_MAX, SLOSH_HTTP_THREADS from
/// `environment` (name -> value; empty values ignored) over `config`; throws std::runtime_error
/// on an invalid value.
void apply_environment(const std::map<std::string, std::string>& environment, ServerConfig& config);

/// Applies one setting given by its config-file `key` (e.g. from a command-line flag) with the same
/// checks as the file and the environment; `where` names the source in the message (e.g.
/// "--log-format"). Throws std::runtime_error on an invalid value.
void apply_setting(const std::string& key, const std::string& where, const std::string& text,
                   ServerConfig& config);
/// What the command line takes from one entry of the settings table, so that a flag checks the
/// same range and names the same environment variable as the config file and the environment.
struct SettingLimits {
  const char* env;   ///< the environment variable, e.g. "SLOSH_WORKERS"
  long long lo{0};   ///< integers: the smallest allowed value; durations: the exclusive bound [s]
  long long hi{0};   ///< integers: the largest allowed value; durations: the inclusive bound [s]
  const char* what;  ///< what the value is, e.g. "a worker count (0 = the cores)"
};

/// The settings-table entry of the config-file `key` (e.g. "workers"); std::logic_error when the
/// table has none (a programming error: every flag names an existing key).
[[nodiscard]] SettingLimits setting_limits(std::string_view key);

/// The value of the setting `key` in `config` as it would be written in the environment (e.g. the
/// default shown by a flag's help).
[[nodiscard]] std::string setting_text(std::string_view key, const ServerConfig& config);

/// Refuses a `cache` value (config key, env or flag, named by `where`) that is neither a SQLite
/// file nor a valid Redis URL: throws std::runtime_error "<where> = <value> is not a Redis URL:
/// ..." (parse_redis_url's reason) or "... is neither a SQLite file nor a Redis URL ...".
void check_cache(const std::string& where, const std::string& cache);

/// Refuses cache_local without a Redis cache (the layers combined; std::runtime_error).
void check_cache_levels(const ServerConfig& config);

/// The SLOSH_* variables of the process environment.
[[nodiscard]] std::map<std::string, std::string> slosh_environment();

}  // namespace slosh::service
