#pragma once
// POST /v1/calibrations and GET /v1/calibrations/{name} without the HTTP library:
// parse, fit on the solve pool within the solve budget, store under the request's name; and the
// resolution of options.model = "<name>" in plan, simulate and min-time bodies.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "calibration/calibration_store.hpp"
#include "config/server_config.hpp"
#include "engine/worker_pool.hpp"
#include "http/plan_service.hpp"

namespace slosh::service {

class CalibrationService {
 public:
  /// Opens the store next to config.cache_path (calibration_store_path); in memory when that
  /// file cannot be opened (store_error() says why).
  CalibrationService(const ServerConfig& config, WorkerPool& pool);

  /// The fit as JSON (api::run_calibration), stored when the body has a "name"; 422 on bad input,
  /// 503 when the pool's queue is full, 504 when the fit does not finish in the solve budget plus
  /// the queue wait (the fit itself stops at the budget with status time_limit). `abandoned`
  /// (optional) tells whether the client has gone away: the fit stops then (between two solver
  /// steps) and is neither answered nor stored.
  Reply post_calibration(const std::string& body, const std::function<bool()>& abandoned = {});
  /// The stored calibration; 422 for an invalid name, 404 for an unknown one.
  Reply get_calibration(const std::string& name) const;
  /// `body` with options.model = "<name>" replaced by the stored model (unchanged text when the
  /// body names none); throws api::ApiError (422 bad name, 404 unknown name, both on
  /// options.model).
  [[nodiscard]] std::string resolve_model_names(const std::string& body) const;
  /// A POST /v1/plans/batch body with the stored model put in for every request whose
  /// options.model names a stored calibration (a request naming an invalid or unknown one is left
  /// as it is: its own item answers 422 on options.model).
  [[nodiscard]] std::string resolve_batch_model_names(const std::string& body) const;
  /// Shares the stored calibrations through the plan cache's Redis (null: not shared).
  void share_through(std::shared_ptr<RedisClient> redis) {
    if (redis) store_->share_through(std::move(redis));
  }
  /// Why the store is in memory instead of its file; empty when it is not.
  [[nodiscard]] const std::string& store_error() const { return store_error_; }
  /// Fits stopped because their client had gone.
  [[nodiscard]] std::uint64_t cancelled() const { return cancelled_; }

 private:
  const ServerConfig& config_;
  WorkerPool& pool_;
  std::string store_error_;
  std::unique_ptr<CalibrationStore> store_;
  std::atomic<std::uint64_t> cancelled_{0};
};

}  // namespace slosh::service
