#include "config/config.hpp"

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <variant>
#include <vector>

#include "slosh/api/config_file.hpp"
#include "storage/redis_client.hpp"

namespace slosh::service {

namespace {

long long parse_integer(const std::string& where, const std::string& text, long long lo,
                        long long hi, const std::string& what) {
  std::size_t used = 0;
  long long v = lo - 1;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  const bool parsed = used == text.size() && !text.empty();
  if (!parsed || v < lo || v > hi) {
    // A number of the right kind outside the range is out of range (as a request field is), not
    // "not a TCP port": only text that is no integer at all is not one.
    throw std::runtime_error(where + " = " + text +
                             (parsed ? " is out of range" : " is not " + what) + ": allowed " +
                             std::to_string(lo) + " to " + std::to_string(hi));
  }
  return v;
}

double parse_seconds(const std::string& where, const std::string& text, double lo, double hi) {
  std::size_t used = 0;
  double v = -1.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  const bool parsed = used == text.size() && !text.empty() && std::isfinite(v);
  if (!parsed || !(v > lo && v <= hi)) {
    // 1 s below the bound is a duration out of range; "abc" or "nan" is not a duration at all.
    throw std::runtime_error(
        where + " = " + text + (parsed ? " is out of range" : " is not a duration") +
        ": allowed > " + api::json_number_text(lo) + " and <= " + api::json_number_text(hi) + " s");
  }
  return v;
}

bool parse_bool(const std::string& where, const std::string& text) {
  if (text == "true" || text == "1") return true;
  if (text == "false" || text == "0") return false;
  throw std::runtime_error(where + " = " + text + " is not a boolean: allowed true, false, 1, 0");
}

// One setting, declared once: its config-file key, its environment variable, the field it sets
// and the values it accepts (integers: lo to hi; durations: > lo and <= hi seconds; text: any,
// non-empty unless `empty_ok`).
struct Setting {
  const char* key;
  const char* env;
  std::variant<std::string ServerConfig::*, int ServerConfig::*, std::size_t ServerConfig::*,
               double ServerConfig::*, bool ServerConfig::*>
      field;
  long long lo{0};
  long long hi{0};
  const char* what{""};  // "a TCP port", ...; for text: whether "" is allowed ("empty_ok")
  std::vector<std::string> choices{};  // text: the allowed values (empty: any)

  [[nodiscard]] bool is_text() const {
    return std::holds_alternative<std::string ServerConfig::*>(field);
  }
  [[nodiscard]] bool is_bool() const { return std::holds_alternative<bool ServerConfig::*>(field); }

  void apply(const std::string& where, const std::string& text, ServerConfig& c) const {
    if (const auto* text_field = std::get_if<std::string ServerConfig::*>(&field)) {
      if (text.empty() && std::string_view(what) != "empty_ok") {
        throw std::runtime_error(where + " must be a non-empty text");
      }
      if (!choices.empty() && std::find(choices.begin(), choices.end(), text) == choices.end()) {
        std::string allowed;
        for (const std::string& v : choices) allowed += (allowed.empty() ? "" : ", ") + v;
        throw std::runtime_error(where + " = " + text + " is not " + what + ": allowed " + allowed);
      }
      if (*text_field == &ServerConfig::cache_path) check_cache(where, text);
      c.*(*text_field) = text;
    } else if (const auto* bool_field = std::get_if<bool ServerConfig::*>(&field)) {
      c.*(*bool_field) = parse_bool(where, text);
    } else if (const auto* int_field = std::get_if<int ServerConfig::*>(&field)) {
      c.*(*int_field) = static_cast<int>(parse_integer(where, text, lo, hi, what));
    } else if (const auto* size_field = std::get_if<std::size_t ServerConfig::*>(&field)) {
      c.*(*size_field) = static_cast<std::size_t>(parse_integer(where, text, lo, hi, what));
    } else {
      c.*std::get<double ServerConfig::*>(field) =
          parse_seconds(where, text, static_cast<double>(lo), static_cast<double>(hi));
    }
  }
};

using C = ServerConfig;
const std::vector<Setting>& settings() {
  static const std::vector<Setting> all{
      {"host", "SLOSH_HOST", &C::host},
      {"port", "SLOSH_PORT", &C::port, 0, 65535, "a TCP port"},
      {"workers", "SLOSH_WORKERS", &C::workers, 0, 1024, "a worker count (0 = the cores)"},
      {"queue", "SLOSH_QUEUE", &C::queue, 1, 100000, "a queue size"},
      {"cache", "SLOSH_CACHE", &C::cache_path, 0, 0, "empty_ok"},
      {"cache_local", "SLOSH_CACHE_LOCAL", &C::cache_local, 0, 0, "empty_ok"},
      {"cache_ttl_s", "SLOSH_CACHE_TTL_S", &C::cache_ttl_s, 0, 10LL * 365 * 86400,
       "a time to live in seconds (0 = none)"},
      {"redis_timeout_ms", "SLOSH_REDIS_TIMEOUT_MS", &C::redis_timeout_ms, 1, 60000,
       "a timeout in milliseconds"},
      {"redis_required", "SLOSH_REDIS_REQUIRED", &C::redis_required},
      {"cache_entries", "SLOSH_CACHE_ENTRIES", &C::cache_entries, 1, 10000000, "an entry count"},
      {"solve_budget_s", "SLOSH_SOLVE_BUDGET_S", &C::solve_budget_s, 0, 600},
      {"queue_wait_s", "SLOSH_QUEUE_WAIT_S", &C::queue_wait_s, 0, 3600},
      {"max_body_bytes", "SLOSH_MAX_BODY_BYTES", &C::max_body_bytes, 1024, 1LL << 30,
       "a body size in bytes"},
      {"batch_max", "SLOSH_BATCH_MAX", &C::batch_max, 1, 100000, "a batch size"},
      {"max_response_bytes", "SLOSH_MAX_RESPONSE_BYTES", &C::max_response_bytes, 1 << 20, 1LL << 40,
       "a response size in bytes"},
      {"http_threads", "SLOSH_HTTP_THREADS", &C::http_threads, 1, 4096, "a thread count"},
      {"read_timeout_s", "SLOSH_READ_TIMEOUT_S", &C::read_timeout_s, 0, 600},
      {"write_timeout_s", "SLOSH_WRITE_TIMEOUT_S", &C::write_timeout_s, 0, 600},
      {"keep_alive_timeout_s", "SLOSH_KEEP_ALIVE_TIMEOUT_S", &C::keep_alive_timeout_s, 0, 600},
      {"request_timeout_s", "SLOSH_REQUEST_TIMEOUT_S", &C::request_timeout_s, 0, 3600},
      {"cache_memory_bytes", "SLOSH_CACHE_MEMORY_BYTES", &C::cache_memory_bytes, 1 << 20, 1LL << 40,
       "a size in bytes"},
      {"cache_store_bytes", "SLOSH_CACHE_STORE_BYTES", &C::cache_store_bytes, 0, 1LL << 50,
       "a size in bytes (0 = unbounded)"},
      {"cache_min_time_store_bytes", "SLOSH_CACHE_MIN_TIME_STORE_BYTES",
       &C::cache_min_time_store_bytes, 0, 1LL << 50, "a size in bytes (0 = unbounded)"},
      {"cam_export_bytes", "SLOSH_CAM_EXPORT_BYTES", &C::cam_export_bytes, 1 << 20, 1LL << 40,
       "a size in bytes"},
      {"log_format", "SLOSH_LOG_FORMAT", &C::log_format, 0, 0, "a log format", {"text", "json"}},
      {"replica_id", "SLOSH_REPLICA_ID", &C::replica_id, 0, 0, "empty_ok"},
      {"batch_job_max", "SLOSH_BATCH_JOB_MAX", &C::batch_job_max, 1, 10000000, "a recipe count"},
      {"batch_jobs_max", "SLOSH_BATCH_JOBS_MAX", &C::batch_jobs_max, 1, 10000, "a job count"},
      {"batch_jobs_kept", "SLOSH_BATCH_JOBS_KEPT", &C::batch_jobs_kept, 1, 1000000, "a job count"},
      {"batch_jobs_bytes", "SLOSH_BATCH_JOBS_BYTES", &C::batch_jobs_bytes, 1 << 16, 1LL << 40,
       "a size in bytes"},
      {"batch_job_ttl_s", "SLOSH_BATCH_JOB_TTL_S", &C::batch_job_ttl_s, 1, 30 * 86400},
      {"batch_job_stale_s", "SLOSH_BATCH_JOB_STALE_S", &C::batch_job_stale_s, 1, 86400},
      {"batch_job_spread",
       "SLOSH_BATCH_JOB_SPREAD",
       &C::batch_job_spread,
       0,
       0,
       "a job spread",
       {"helpers", "owner", "replicas"}},
      {"batch_job_max_takes", "SLOSH_BATCH_JOB_MAX_TAKES", &C::batch_job_max_takes, 1, 100,
       "a take count"},
  };
  return all;
}

const Setting& setting_of(std::string_view key) {
  for (const Setting& s : settings()) {
    if (key == s.key) return s;
  }
  throw std::logic_error("no setting " + std::string(key));
}

std::string known_keys() {
  std::string keys;
  for (const Setting& s : settings()) keys += (keys.empty() ? "" : ", ") + std::string(s.key);
  return keys;
}

}  // namespace

void check_cache(const std::string& where, const std::string& cache) {
  if (is_redis_url(cache)) {
    try {
      (void)parse_redis_url(cache);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(where + " = " + e.what());
    }
  } else if (cache.find("://") != std::string::npos) {
    throw std::runtime_error(where + " = " + cache +
                             " is neither a SQLite file nor a Redis URL: the only URL scheme "
                             "supported is redis://");
  }
}

void check_cache_levels(const ServerConfig& config) {
  if (!config.cache_local.empty() && !is_redis_url(config.cache_path)) {
    throw std::runtime_error("cache_local = " + config.cache_local +
                             " needs a Redis cache (cache = redis://host:port/db), but cache = '" +
                             config.cache_path +
                             "': set the SQLite file as cache alone, or cache to a Redis URL");
  }
}

void apply_config_file(const std::string& path, ServerConfig& config) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read config file '" + path + "'");
  // A read error (a directory) throws from the stream buffer, naming the reason.
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  ServerConfig updated = config;  // all or nothing
  for (const api::ConfigMember& member : api::parse_config_file(path, text)) {
    using Type = api::ConfigMember::Type;
    const std::string where = path + ": " + member.key;
    const Setting* setting = nullptr;
    for (const Setting& s : settings()) {
      if (member.key == s.key) setting = &s;
    }
    if (setting == nullptr) {
      throw std::runtime_error(where + " is not a known setting; allowed: " + known_keys());
    }
    const bool text_setting = setting->is_text();
    if (setting->is_bool()) {
      if (member.type != Type::kBoolean) {
        throw std::runtime_error(where + " = " + member.json +
                                 " has the wrong type: allowed true or false");
      }
      setting->apply(where, member.json, updated);
      continue;
    }
    if (text_setting != (member.type == Type::kString) ||
        (!text_setting && member.type != Type::kNumber)) {
      // Numbers must be JSON numbers (a quoted "80" is rejected with the value shown).
      setting->apply(where, member.json, updated);
      throw std::runtime_error(where + " = " + member.json + " has the wrong type");
    }
    setting->apply(where, member.text, updated);
  }
  config = updated;
}

void apply_environment(const std::map<std::string, std::string>& environment,
                       ServerConfig& config) {
  ServerConfig updated = config;
  for (const Setting& s : settings()) {
    if (auto it = environment.find(s.env); it != environment.end() && !it->second.empty()) {
      s.apply(s.env, it->second, updated);
    }
  }
  config = updated;
}

void apply_setting(const std::string& key, const std::string& where, const std::string& text,
                   ServerConfig& config) {
  ServerConfig updated = config;
  setting_of(key).apply(where, text, updated);
  config = updated;
}

SettingLimits setting_limits(std::string_view key) {
  const Setting& s = setting_of(key);
  return {s.env, s.lo, s.hi, s.what};
}

std::string setting_text(std::string_view key, const ServerConfig& config) {
  const Setting& s = setting_of(key);
  if (const auto* text_field = std::get_if<std::string ServerConfig::*>(&s.field)) {
    return config.*(*text_field);
  }
  if (const auto* bool_field = std::get_if<bool ServerConfig::*>(&s.field)) {
    return config.*(*bool_field) ? "true" : "false";
  }
  if (const auto* int_field = std::get_if<int ServerConfig::*>(&s.field)) {
    return std::to_string(config.*(*int_field));
  }
  if (const auto* size_field = std::get_if<std::size_t ServerConfig::*>(&s.field)) {
    return std::to_string(config.*(*size_field));
  }
  return api::json_number_text(config.*std::get<double ServerConfig::*>(s.field));
}

std::map<std::string, std::string> slosh_environment() {
  std::map<std::string, std::string> env;
  for (const Setting& s : settings()) {
    if (const char* value = std::getenv(s.env)) env[s.env] = value;
  }
  return env;
}

std::string replica_name(const ServerConfig& config) {
  if (!config.replica_id.empty()) return config.replica_id;
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) return "slosh";
  return host;
}

}  // namespace slosh::service
