#include "config.hpp"

#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

namespace slosh::service {

namespace {

// One setting: its config-file key, its environment variable, and how to read it from text.
struct Setting {
  const char* key;
  const char* env;
  std::function<void(const std::string& where, const std::string& text, ServerConfig&)> apply;
};

long long parse_integer(const std::string& where, const std::string& text, long long lo,
                        long long hi, const std::string& what) {
  std::size_t used = 0;
  long long v = lo - 1;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || v < lo || v > hi) {
    throw std::runtime_error(where + " = " + text + " is not " + what + ": allowed " +
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
  if (used != text.size() || text.empty() || !(v > lo && v <= hi)) {
    throw std::runtime_error(where + " = " + text + " is not a duration: allowed > " +
                             nlohmann::json(lo).dump() + " and <= " + nlohmann::json(hi).dump() +
                             " s");
  }
  return v;
}

const std::vector<Setting>& settings() {
  static const std::vector<Setting> all{
      {"host", "SLOSH_HOST",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         if (text.empty()) throw std::runtime_error(where + " must be a non-empty text");
         c.host = text;
       }},
      {"port", "SLOSH_PORT",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.port = static_cast<int>(parse_integer(where, text, 0, 65535, "a TCP port"));
       }},
      {"workers", "SLOSH_WORKERS",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.workers = static_cast<std::size_t>(
             parse_integer(where, text, 0, 1024, "a worker count (0 = the cores)"));
       }},
      {"queue", "SLOSH_QUEUE",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.queue = static_cast<std::size_t>(parse_integer(where, text, 1, 100000, "a queue size"));
       }},
      {"cache", "SLOSH_CACHE",
       [](const std::string&, const std::string& text, ServerConfig& c) { c.cache_path = text; }},
      {"cache_entries", "SLOSH_CACHE_ENTRIES",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.cache_entries =
             static_cast<std::size_t>(parse_integer(where, text, 1, 10000000, "an entry count"));
       }},
      {"solve_budget_s", "SLOSH_SOLVE_BUDGET_S",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.solve_budget_s = parse_seconds(where, text, 0.0, 600.0);
       }},
      {"queue_wait_s", "SLOSH_QUEUE_WAIT_S",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.queue_wait_s = parse_seconds(where, text, 0.0, 3600.0);
       }},
      {"max_body_bytes", "SLOSH_MAX_BODY_BYTES",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.max_body_bytes = static_cast<std::size_t>(
             parse_integer(where, text, 1024, 1LL << 30, "a body size in bytes"));
       }},
      {"batch_max", "SLOSH_BATCH_MAX",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.batch_max =
             static_cast<std::size_t>(parse_integer(where, text, 1, 100000, "a batch size"));
       }},
      {"max_response_bytes", "SLOSH_MAX_RESPONSE_BYTES",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.max_response_bytes = static_cast<std::size_t>(
             parse_integer(where, text, 1 << 20, 1LL << 40, "a response size in bytes"));
       }},
      {"http_threads", "SLOSH_HTTP_THREADS",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.http_threads =
             static_cast<std::size_t>(parse_integer(where, text, 1, 4096, "a thread count"));
       }},
      {"read_timeout_s", "SLOSH_READ_TIMEOUT_S",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.read_timeout_s = parse_seconds(where, text, 0.0, 600.0);
       }},
      {"write_timeout_s", "SLOSH_WRITE_TIMEOUT_S",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.write_timeout_s = parse_seconds(where, text, 0.0, 600.0);
       }},
      {"keep_alive_timeout_s", "SLOSH_KEEP_ALIVE_TIMEOUT_S",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.keep_alive_timeout_s = parse_seconds(where, text, 0.0, 600.0);
       }},
      {"request_timeout_s", "SLOSH_REQUEST_TIMEOUT_S",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.request_timeout_s = parse_seconds(where, text, 0.0, 3600.0);
       }},
      {"cache_memory_bytes", "SLOSH_CACHE_MEMORY_BYTES",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.cache_memory_bytes = static_cast<std::size_t>(
             parse_integer(where, text, 1 << 20, 1LL << 40, "a size in bytes"));
       }},
      {"cache_store_bytes", "SLOSH_CACHE_STORE_BYTES",
       [](const std::string& where, const std::string& text, ServerConfig& c) {
         c.cache_store_bytes = static_cast<std::size_t>(
             parse_integer(where, text, 0, 1LL << 50, "a size in bytes (0 = unbounded)"));
       }},
  };
  return all;
}

std::string known_keys() {
  std::string keys;
  for (const Setting& s : settings()) keys += (keys.empty() ? "" : ", ") + std::string(s.key);
  return keys;
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
  ServerConfig updated = config;  // all or nothing
  for (const auto& [key, value] : j.items()) {
    const std::string where = path + ": " + key;
    const Setting* setting = nullptr;
    for (const Setting& s : settings()) {
      if (key == s.key) setting = &s;
    }
    if (setting == nullptr) {
      throw std::runtime_error(where + " is not a known setting; allowed: " + known_keys());
    }
    const bool text_setting = key == "host" || key == "cache";
    if (text_setting != value.is_string() || (!text_setting && !value.is_number())) {
      // Numbers must be JSON numbers (a quoted "80" is rejected with the value shown).
      setting->apply(where, value.dump(), updated);
      throw std::runtime_error(where + " = " + value.dump() + " has the wrong type");
    }
    setting->apply(where, text_setting ? value.get<std::string>() : value.dump(), updated);
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

std::map<std::string, std::string> slosh_environment() {
  std::map<std::string, std::string> env;
  for (const Setting& s : settings()) {
    if (const char* value = std::getenv(s.env)) env[s.env] = value;
  }
  return env;
}

}  // namespace slosh::service
