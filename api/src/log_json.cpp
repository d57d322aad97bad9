#include "slosh/api/log_json.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace slosh::api {

std::string json_quoted(std::string_view text) {
  return nlohmann::json(std::string(text))
      .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string request_log_object(const LoggedRequest& e) {
  nlohmann::json j = {
      {"msg", "request"}, {"request_id", e.request_id}, {"method", e.method}, {"route", e.route},
      {"path", e.path},   {"status", e.status},         {"bytes", e.bytes}};
  j["ms"] = e.ms ? nlohmann::json(std::round(*e.ms * 1000.0) / 1000.0) : nlohmann::json(nullptr);
  if (!e.cache.empty()) j["cache"] = e.cache;
  if (e.plan) {
    j["plan_key"] = e.plan->key;
    j["strategy"] = e.plan->strategy;
    j["plan_status"] = e.plan->status;
    j["cached"] = e.plan->cached;
  }
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace slosh::api
