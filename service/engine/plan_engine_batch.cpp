// PlanEngine's batches: the items of POST /v1/plans/batch, of a batch job and of `slosh batch`.

#include <chrono>
#include <future>
#include <utility>

#include "engine/plan_engine.hpp"
#include "slosh/api/plan_reply.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service {

std::size_t PendingBatch::finished() const {
  std::size_t n = 0;
  for (const auto& p : pending_) {
    if (!p.valid() || p.wait_for(std::chrono::seconds(0)) == std::future_status::ready) ++n;
  }
  return n;
}

bool PendingBatch::wait_for(std::size_t i, std::chrono::milliseconds timeout) const {
  return !pending_[i].valid() || pending_[i].wait_for(timeout) == std::future_status::ready;
}

namespace {

// The batch result of a finished solve.
BatchResult batch_result(const SolveOutcome& o) {
  BatchResult r;
  if (o.error) {
    r.error = o.error;
  } else {
    r.plan = api::render_plan_reply(o.body, false);
  }
  return r;
}

}  // namespace

BatchResult PendingBatch::get(std::size_t i) const {
  if (!pending_[i].valid()) return results_[i];
  return batch_result(pending_[i].get());
}

BatchResult StartedItem::get() const {
  return pending.valid() ? batch_result(pending.get()) : result;
}

StartedItem PlanEngine::start_batch_item(const api::BatchItem& item, TaskPriority priority,
                                         std::shared_ptr<FlightWaiters>* waiter,
                                         std::string* flight) {
  StartedItem started;
  BatchResult& result = started.result;
  if (item.error) {
    result.error = item.error;
    return started;
  }
  try {
    const api::PlanRequest& request = *item.request;
    const std::string key = api::recipe_key(request);
    CacheLevel level{};
    if (const auto hit = cache_.find(key, &level)) {
      metrics_.count_cache_hit(level);
      result.plan = api::render_plan_reply(hit->value(), true);
      result.cached = true;
      return started;
    }
    bool refused = false;
    started.pending = solve(key, request, true, &refused, priority, waiter);
    if (refused) result.error = overloaded_error();
    if (flight != nullptr) *flight = flight_name(key, request.options.time_limit);
  } catch (const api::ApiError& e) {
    result.error = e;
  } catch (const std::exception& e) {
    result.error = api::ApiError(api::ErrorCode::kInternal, "", e.what());
  }
  return started;
}

BatchResult PlanEngine::abandoned_item(const api::BatchItem& item) {
  BatchResult result;
  if (item.error) {
    result.error = item.error;
    return result;
  }
  try {
    const api::PlanRequest& request = *item.request;
    CacheLevel level{};
    if (const auto hit = cache_.find(api::recipe_key(request), &level)) {
      metrics_.count_cache_hit(level);
      result.plan = api::render_plan_reply(hit->value(), true);
      result.cached = true;
    } else {
      result.error = api::ApiError(api::ErrorCode::kCancelled, "",
                                   "not solved: the client closed the connection");
    }
  } catch (const api::ApiError& e) {
    result.error = e;
  }
  return result;
}

PendingBatch PlanEngine::start_batch(const std::vector<api::BatchItem>& requests,
                                     const std::function<bool()>& abandoned) {
  PendingBatch batch;
  const std::size_t n = requests.size();
  batch.results_.resize(n);
  batch.pending_.resize(n);
  if (abandoned) {
    batch.flights_.resize(n);
    batch.waiters_.resize(n);
  }
  bool gone = false;
  for (std::size_t i = 0; i < n; ++i) {
    // A client that went away gets no more solves queued for it (leave_batch stops the queued
    // ones); cache hits and invalid items are still answered.
    gone = gone || (abandoned && abandoned());
    if (gone) {
      batch.results_[i] = abandoned_item(requests[i]);
      continue;
    }
    // Below interactive plans (as batch jobs' items): a batch of up to batch_max recipes fills
    // the background queue as it drains, and an HMI's plan must still overtake it instead of
    // finding the queue full for the whole batch.
    StartedItem started = abandoned ? start_batch_item(requests[i], TaskPriority::kBackground,
                                                       &batch.waiters_[i], &batch.flights_[i])
                                    : start_batch_item(requests[i], TaskPriority::kBackground);
    batch.results_[i] = std::move(started.result);
    batch.pending_[i] = std::move(started.pending);
  }
  return batch;
}

void PlanEngine::leave_batch(const PendingBatch& batch) {
  for (std::size_t i = 0; i < batch.waiters_.size(); ++i) {
    if (!batch.waiters_[i] || batch.wait_for(i, std::chrono::milliseconds(0))) continue;
    if (leave_flight(inflight_, batch.flights_[i], batch.waiters_[i], true)) ++cancelled_plans_;
  }
}

}  // namespace slosh::service
