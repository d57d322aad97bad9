#include "calibration/calibration_service.hpp"

#include <algorithm>
#include <chrono>
#include <future>
#include <memory>
#include <utility>

#include "http/client_wait.hpp"
#include "slosh/api/calibration_models.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"

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
    auto request = std::make_shared<api::CalibrationRequest>(api::parse_calibration_text(text));
    const auto deadline = after(config_.solve_budget_s);
    // Set when the client has gone: the fit stops at its next step.
    auto gone = std::make_shared<std::atomic<bool>>(false);
    request->settings.stop = [deadline, gone] {
      return gone->load() || std::chrono::steady_clock::now() >= deadline;
    };
    auto promise = std::make_shared<std::promise<std::string>>();
    std::future<std::string> result = promise->get_future();
    // Background priority: a fit (up to solve_budget_s on a long series) never goes ahead of an
    // HMI's plan (ten fits of 60 000 samples ahead of it would hold a plan for about 5 s).
    const bool queued = pool_.try_submit(
        [request, promise, gone] {
          try {
            if (gone->load())
              throw api::ApiError(api::ErrorCode::kCancelled, "",
                                  "not fitted: the client closed the connection");
            promise->set_value(api::run_calibration_text(*request));
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
    std::string fit = result.get();
    if (request->name) {
      bool storable = false;
      fit = api::named_fit_reply(fit, storable);
      if (storable && !store_->put(*request->name, fit)) {
        return PlanService::error_reply(api::ErrorCode::kInternal,
                                        "the calibration could not be stored", "name");
      }
    }
    Reply r;
    r.body = std::move(fit);
    return r;
  });
}

Reply CalibrationService::get_calibration(const std::string& name) const {
  return guarded_reply([&] {
    api::validate_calibration_name(name, "name");
    const std::optional<std::string> stored = store_->get(name);
    if (!stored) {
      return PlanService::error_reply(api::ErrorCode::kNotFound,
                                      "no stored calibration '" + name + "'", "name");
    }
    Reply r;
    r.body = api::stored_calibration_reply(*stored);
    return r;
  });
}

std::string CalibrationService::resolve_model_names(const std::string& body) const {
  return api::resolve_model_names(body,
                                  [this](const std::string& name) { return store_->get(name); });
}

std::string CalibrationService::resolve_batch_model_names(const std::string& body) const {
  return api::resolve_batch_model_names(
      body, [this](const std::string& name) { return store_->get(name); });
}

}  // namespace slosh::service
