#include "calibration/calibration_service.hpp"

#include <algorithm>
#include <chrono>
#include <future>
#include <memory>

#include "http/client_wait.hpp"
#include "slosh/api/calibration_json.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::service {

CalibrationService::CalibrationService(const ServerConfig& config, WorkerPool& pool)
    : config_(config), pool_(pool) {
  try {
    store_ = std::make_unique<CalibrationStore>(calibration_store_path(local_cache_path(config)));
  } catch (const std::exception& e) {
    store_error_ = e.what();
    store_ = std::make_unique<CalibrationStore>(":memory:");
  }
}

Reply CalibrationService::post_calibration(const std::string& text,
                                           const std::function<bool()>& abandoned) {
  return guarded_reply([&] {
    auto request = std::make_shared<api::CalibrationRequest>(
        api::parse_calibration_request(api::parse_json_body(text)));
    const auto deadline = after(config_.solve_budget_s);
    // Set when the client has gone: the fit stops at its next step.
    auto gone = std::make_shared<std::atomic<bool>>(false);
    request->settings.stop = [deadline, gone] {
      return gone->load() || std::chrono::steady_clock::now() >= deadline;
    };
    auto promise = std::make_shared<std::promise<nlohmann::json>>();
    std::future<nlohmann::json> result = promise->get_future();
    // Background priority: a fit (up to solve_budget_s on a long series) never goes ahead of an
    // HMI's plan (ten fits of 60 000 samples ahead of it would hold a plan for about 5 s).
    const bool queued = pool_.try_submit(
        [request, promise, gone] {
          try {
            if (gone->load())
              throw api::ApiError(api::ErrorCode::kCancelled, "",
                                  "not fitted: the client closed the connection");
            promise->set_value(api::run_calibration(*request));
          } catch (...) {
            promise->set_exception(std::current_exception());
          }
        },
        TaskPriority::kBackground);
    if (!queued) {
      return PlanService::error_reply(api::ErrorCode::kOverloaded,
                                      "all solve workers are busy and the queue is full; retry "
                                      "the calibration later");
    }
    const WaitEnd end =
        wait_for_client(result, after(config_.solve_budget_s + config_.queue_wait_s), abandoned);
    if (end == WaitEnd::kTimeout) {
      return PlanService::error_reply(
          api::ErrorCode::kTimeout, "the calibration did not finish within the solve budget of " +
                                        api::number_text(config_.solve_budget_s) + " s plus " +
                                        api::number_text(config_.queue_wait_s) + " s of queueing");
    }
    if (end == WaitEnd::kGone) {
      gone->store(true);
      ++cancelled_;
      return PlanService::error_reply(api::ErrorCode::kCancelled,
                                      "not fitted: the client closed the connection");
    }
    const nlohmann::json fit = result.get();
    if (request->name && !store_->put(*request->name, fit)) {
      return PlanService::error_reply(api::ErrorCode::kInternal,
                                      "the calibration could not be stored", "name");
    }
    Reply r;
    r.body = api::dump_json(fit);
    return r;
  });
}

Reply CalibrationService::get_calibration(const std::string& name) const {
  return guarded_reply([&] {
    api::validate_calibration_name(name, "name");
    const std::optional<nlohmann::json> stored = store_->get(name);
    if (!stored) {
      return PlanService::error_reply(api::ErrorCode::kNotFound,
                                      "no stored calibration '" + name + "'", "name");
    }
    Reply r;
    r.body = api::dump_json(*stored);
    return r;
  });
}

std::string CalibrationService::resolve_model_names(const std::string& body) const {
  if (body.find("\"model\"") == std::string::npos) return body;
  const nlohmann::json parsed = nlohmann::json::parse(body, nullptr, false);
  if (parsed.is_discarded()) return body;  // the endpoint reports the malformed body itself
  const auto* options = parsed.is_object() ? api::given_member(parsed, "options") : nullptr;
  if (options == nullptr || !options->is_object()) return body;
  const auto* model = api::given_member(*options, "model");
  if (model == nullptr || !model->is_string()) return body;
  return api::dump_json(resolve_model_name(parsed, *store_));
}

std::string CalibrationService::resolve_batch_model_names(const std::string& body) const {
  if (body.find("\"model\"") == std::string::npos) return body;
  nlohmann::json parsed = nlohmann::json::parse(body, nullptr, false);
  if (parsed.is_discarded() || !parsed.is_object() || !parsed.contains("requests") ||
      !parsed["requests"].is_array()) {
    return body;  // the endpoint reports the body itself
  }
  bool changed = false;
  for (nlohmann::json& request : parsed["requests"]) {
    const auto* options = request.is_object() ? api::given_member(request, "options") : nullptr;
    if (options == nullptr || !options->is_object()) continue;
    const auto* model = api::given_member(*options, "model");
    if (model == nullptr || !model->is_string()) continue;
    try {
      request = resolve_model_name(request, *store_);
      changed = true;
    } catch (const api::ApiError&) {
      // left as given: the item's own parse names options.model
    }
  }
  return changed ? api::dump_json(parsed) : body;
}

}  // namespace slosh::service
