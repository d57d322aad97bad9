#include "slosh/api/service_bodies.hpp"

#include <algorithm>
#include <cctype>

#include "slosh/api/error.hpp"
#include "slosh/api/exact_number.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::api {

ApiError with_server_range(const ApiError& e, double budget) {
  // The API's range, (0, 600] s, read with this server's most, its budget.
  const std::string api_most = "<= " + number_text(plan_ranges::kTimeLimit.hi) + " s";
  const std::string message = e.what();
  if (e.field() != "options.time_limit_s" || !(budget < plan_ranges::kTimeLimit.hi) ||
      message.size() < api_most.size() ||
      message.compare(message.size() - api_most.size(), api_most.size(), api_most) != 0) {
    return e;
  }
  return ApiError(e.code(), e.field(),
                  message.substr(0, message.size() - api_most.size()) +
                      "<= " + number_text(budget) + " s (this server's budget)");
}

PlanRequest parse_plan_with_budget(const nlohmann::json& body, double budget) {
  PlanRequest request;
  try {
    request = parse_plan_request(body);
  } catch (const ApiError& e) {
    throw with_server_range(e, budget);
  }
  const nlohmann::json* options =
      body.contains("options") && body["options"].is_object() ? &body["options"] : nullptr;
  if (options == nullptr || !options->contains("time_limit_s") ||
      (*options)["time_limit_s"].is_null()) {
    request.options.time_limit = budget;
  } else if (request.options.time_limit > budget) {
    throw ApiError(ErrorCode::kInvalidValue, "options.time_limit_s",
                   "options.time_limit_s = " + exact_number_text(request.options.time_limit) +
                       " is out of range: this server allows at most " + number_text(budget) +
                       " s");
  }
  return request;
}

PlanRequest parse_plan_text(std::string_view text, double budget) {
  return parse_plan_with_budget(parse_json_body(text), budget);
}

BatchBody parse_batch_body(std::string_view text, std::size_t batch_max) {
  nlohmann::json body = parse_json_body(text);
  if (!body.is_object()) {
    throw ApiError(ErrorCode::kInvalidValue, "",
                   "the body must be an object {\"requests\": [plan requests]}");
  }
  reject_unknown_fields(body, "", {"requests", "view"});
  const auto it = body.find("requests");
  if (it == body.end() || !it->is_array() || it->empty() || it->size() > batch_max) {
    throw ApiError(ErrorCode::kInvalidValue, "requests",
                   "requests must be an array of 1 to " + std::to_string(batch_max) +
                       " plan requests, got " +
                       (it == body.end() ? std::string("nothing") : show(*it)));
  }
  BatchBody out;
  out.requests.reserve(it->size());
  for (nlohmann::json& request : *it) out.requests.push_back(std::move(request));
  if (const nlohmann::json* view = given_member(body, "view")) out.view = *view;
  return out;
}

std::vector<nlohmann::json> parse_batch_text(std::string_view text, std::size_t batch_max) {
  return parse_batch_body(text, batch_max).requests;
}

PlanRequest parse_batch_item(const nlohmann::json& item, double budget) {
  PlanRequest request = parse_plan_with_budget(item, budget);
  if (request.sample_period) {
    // A batch answers with plans; a thousand series would be gigabytes.
    throw ApiError(ErrorCode::kInvalidValue, "sample_period_s",
                   "sample_period_s is not allowed in a batch (plans only): ask POST "
                   "/v1/plans or /v1/simulate for the series of one law");
  }
  return request;
}

BatchItem read_batch_item(const nlohmann::json& item, double budget) {
  BatchItem read;
  try {
    read.request = parse_batch_item(item, budget);
  } catch (const ApiError& e) {
    read.error = e;
  } catch (const std::exception& e) {
    read.error = ApiError(ErrorCode::kInternal, "", e.what());
  }
  return read;
}

std::vector<BatchItem> read_batch_items(const std::vector<nlohmann::json>& items, double budget) {
  std::vector<BatchItem> read;
  read.reserve(items.size());
  for (const nlohmann::json& item : items) read.push_back(read_batch_item(item, budget));
  return read;
}

void BatchReplyWriter::open_item(std::size_t index, std::size_t extra_bytes) {
  if (out_.size() + extra_bytes > max_bytes_) {
    throw ApiError(ErrorCode::kInvalidValue, "requests",
                   "the plans of this batch exceed the response limit of " +
                       std::to_string(max_bytes_) + " bytes at requests[" + std::to_string(index) +
                       "]; the plans are cached: send fewer requests per batch");
  }
  if (items_++ > 0) out_ += ',';
  out_ += "{\"index\":" + std::to_string(index);
}

void BatchReplyWriter::add_plan(std::size_t index, const std::string& plan) {
  open_item(index, plan.size());
  out_ += ",\"plan\":" + plan + '}';
}

namespace {

bool member_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '.' || c == ']';
}

/// `message` with the request paths it names read inside the batch: the item's own field where
/// the message begins with it, and every "format." or "options." path, each after `prefix`.
std::string paths_inside(const std::string& prefix, const std::string& field,
                         const std::string& message) {
  std::string out;
  std::size_t at = 0;
  if (!field.empty() && message.rfind(field, 0) == 0 &&
      (message.size() == field.size() || !member_char(message[field.size()]))) {
    out = prefix + "." + field;
    at = field.size();
  }
  while (at < message.size()) {
    std::size_t next = std::string::npos;
    for (std::string_view root : {"format.", "options."}) {
      for (std::size_t p = message.find(root, at); p != std::string::npos;
           p = message.find(root, p + 1)) {
        const std::size_t after = p + root.size();
        const bool path = after < message.size() &&
                          (std::isalpha(static_cast<unsigned char>(message[after])) != 0 ||
                           message[after] == '_');
        if (path && (p == 0 || !member_char(message[p - 1])) && !inside_json_string(message, p)) {
          next = std::min(next, p);
          break;
        }
      }
    }
    if (next == std::string::npos) break;
    out.append(message, at, next - at).append(prefix).append(".");
    at = next;
    // Past the path, so that none of its own members is taken for another root.
    while (at < message.size() && member_char(message[at])) out += message[at++];
  }
  return out.append(message, std::min(at, message.size()));
}

}  // namespace

void BatchReplyWriter::add_error(std::size_t index, const ApiError& error) {
  open_item(index, 0);
  // Paths inside the batch: requests[i].format..., in the field and in the message alike.
  const std::string prefix = "requests[" + std::to_string(index) + "]";
  const ApiError inside(error.code(), error.field().empty() ? prefix : prefix + "." + error.field(),
                        paths_inside(prefix, error.field(), error.what()));
  out_ += ",\"error\":" + dump_json(error_envelope(inside)["error"]) + '}';
}

std::string BatchReplyWriter::finish() {
  return out_ + "]}";
}

std::string batch_body_text(const std::vector<nlohmann::json>& requests) {
  return dump_json(nlohmann::json{{"requests", requests}});
}

std::optional<std::vector<BatchItemReply>> parse_batch_reply(std::string_view text) {
  const nlohmann::json parsed = nlohmann::json::parse(text, nullptr, false);
  if (parsed.is_discarded() || !parsed.is_object() || !parsed.contains("results") ||
      !parsed["results"].is_array()) {
    return std::nullopt;
  }
  std::vector<BatchItemReply> items;
  for (const nlohmann::json& item : parsed["results"]) {
    BatchItemReply reply;
    if (item.is_object() && item.contains("plan")) {
      reply.plan = dump_json(item["plan"]);
      reply.cached = item["plan"].is_object() && item["plan"].value("cached", false);
    } else {
      const ApiError error = error_from_json(
          item.is_object() && item.contains("error")
              ? item["error"]
              : nlohmann::json{{"code", "internal"}, {"message", "the service sent no result"}});
      // The service reads paths inside the batch (requests[k].); the row's own are wanted.
      std::string field = error.field();
      const std::size_t dot = field.find("].");
      std::string message = error.what();
      if (field.rfind("requests[", 0) == 0) {
        const std::string prefix =
            dot == std::string::npos ? field + "." : field.substr(0, dot + 2);
        field = dot == std::string::npos ? "" : field.substr(dot + 2);
        for (std::size_t p = message.find(prefix); p != std::string::npos;
             p = message.find(prefix, p)) {
          if (inside_json_string(message, p)) {
            p += prefix.size();  // a value the message echoes, as it was sent
          } else {
            message.erase(p, prefix.size());
          }
        }
      }
      reply.error = ApiError(error.code(), field, message);
    }
    items.push_back(std::move(reply));
  }
  return items;
}

std::string envelope_message(std::string_view text) {
  const nlohmann::json parsed = nlohmann::json::parse(text, nullptr, false);
  if (parsed.is_discarded() || !parsed.is_object() || !parsed.contains("error") ||
      !parsed["error"].is_object()) {
    return {};
  }
  return parsed["error"].value("message", std::string());
}

std::string health_body(std::string_view version) {
  return nlohmann::json{{"status", "ok"}, {"version", version}}.dump();
}

std::string ready_body(const ReadyReport& r) {
  nlohmann::json body{{"workers", r.workers},
                      {"busy_workers", r.busy_workers},
                      {"queue_depth", r.queue_depth},
                      {"cache",
                       {{"persistent", r.cache_persistent},
                        {"memory_entries", r.cache_memory_entries},
                        {"memory_bytes", r.cache_memory_bytes}}}};
  if (!r.reason.empty()) body["reason"] = r.reason;
  if (!r.cache_storage_error.empty()) body["cache"]["storage_error"] = r.cache_storage_error;
  if (r.redis_configured) {
    nlohmann::json redis{{"url", r.redis_url}, {"up", r.redis_up}, {"required", r.redis_required}};
    if (!r.redis_error.empty()) redis["error"] = r.redis_error;
    body["cache"]["redis"] = redis;
  }
  if (!r.job_store_warning.empty()) body["jobs"] = {{"store_warning", r.job_store_warning}};
  body["status"] = r.status;
  return dump_json(body);
}

}  // namespace slosh::api
