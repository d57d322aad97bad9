// PlanEngine's state as others see it: readiness (GET /readyz), metrics, the cache levels in
// words, and the start of a shutdown.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "engine/plan_engine.hpp"
#include "slosh/api/format_json.hpp"

namespace slosh::service {

namespace {

/// Readiness turns "stalled" when the pool has work but finished nothing for max(this, 3 solve
/// budgets) [s].
constexpr double kMinStallSeconds = 30.0;

// What a replica says about itself, from best to worst (ReadyReport::status is its name).
enum class ReadyState { kReady, kDegraded, kStalled, kStopping };

const char* state_name(ReadyState state) {
  switch (state) {
    case ReadyState::kReady:
      return "ready";
    case ReadyState::kDegraded:
      return "degraded";
    case ReadyState::kStalled:
      return "stalled";
    case ReadyState::kStopping:
      return "stopping";
  }
  return "ready";
}

// Adds the shared level's state to `report`: Redis down makes a ready replica degraded (still
// ready: it answers from its local levels), or not ready when Redis is required.
void add_redis_state(api::ReadyReport& report, ReadyState& state, RedisClient& redis, bool required,
                     bool& unready) {
  redis.probe();  // a replica without traffic finds its Redis again through its probes
  const RedisClient::State redis_state = redis.state();
  report.redis_configured = true;
  report.redis_url = redis.options().url.display();
  report.redis_up = redis_state.up;
  report.redis_required = required;
  report.redis_error = redis_state.error;
  if (redis_state.up || (state != ReadyState::kReady && state != ReadyState::kDegraded)) return;
  const std::string why = "redis " + report.redis_url + " is down (" + redis_state.error + "); " +
                          (required ? "redis_required is set, so this replica is not ready"
                                    : "answering from the local cache levels");
  report.reason = report.reason.empty() ? why : why + "; " + report.reason;
  state = ReadyState::kDegraded;
  if (required) unready = true;
}

}  // namespace

std::string PlanEngine::store_error() const {
  std::string error = cache_.storage_error();
  return error.empty() ? min_time_cache_.storage_error() : error;
}

Readiness PlanEngine::readiness() const {
  const auto stats = cache_.stats();
  const std::string storage_error = store_error();
  const double stalled = std::chrono::duration<double>(pool_.stalled_for()).count();
  const double stall_limit = std::max(kMinStallSeconds, 3.0 * config_.solve_budget_s);
  api::ReadyReport report{.status = {},
                          .reason = {},
                          .workers = pool_.workers(),
                          .busy_workers = pool_.busy(),
                          .queue_depth = pool_.queue_depth(),
                          .cache_persistent = stats.persistent,
                          .cache_memory_entries = stats.memory_entries,
                          .cache_memory_bytes = stats.memory_bytes,
                          .cache_storage_error = storage_error};
  ReadyState state = ReadyState::kReady;
  if (!ready_) {
    state = ReadyState::kStopping;
  } else if (stalled > stall_limit) {
    // Every solve has a budget: a pool with work that finished nothing for 3 budgets is wedged.
    state = ReadyState::kStalled;
    report.reason = "no solve has finished for " + api::number_text(std::round(stalled)) +
                    " s (the limit is " + api::number_text(stall_limit) + " s) with " +
                    std::to_string(report.busy_workers) + " running and " +
                    std::to_string(report.queue_depth) + " queued";
  } else if (!storage_error.empty()) {
    // Still ready: plans (and min-time answers) are answered correctly (from memory), they are
    // only not kept across a restart. Taking the replica out of rotation would stop a line that
    // one replica serves; the failure is logged, said here and in slosh_cache_store_ok.
    state = ReadyState::kDegraded;
    report.reason = storage_error;
  }
  bool unready = false;
  if (redis_) add_redis_state(report, state, *redis_, config_.redis_required, unready);
  report.status = state_name(state);
  return Readiness{std::move(report),
                   !unready && (state == ReadyState::kReady || state == ReadyState::kDegraded)};
}

void PlanEngine::collect_metrics(MetricsText& out) const {
  metrics_.collect(out, pool_.queue_depth(), pool_.busy(), pool_.workers());
}

void PlanEngine::collect_store_metrics(MetricsText& out) const {
  out.family("slosh_cache_store_ok", "gauge",
             "0 while the plan store cannot be opened or written, else 1.");
  out.sample("slosh_cache_store_ok", "", std::uint64_t{store_error().empty() ? 1U : 0U});
  if (redis_) {
    out.family("slosh_redis_up", "gauge",
               "1 while the shared cache's Redis answers, 0 while it is down or slow (the "
               "replica answers from its local levels); absent without a Redis cache.");
    out.sample("slosh_redis_up", "", std::uint64_t{redis_->state().up ? 1U : 0U});
  }
  out.family("slosh_cam_export_bytes", "gauge",
             "Bytes reserved by the cam exports in flight (until their responses are written).");
  out.sample("slosh_cam_export_bytes", "", std::uint64_t{export_budget_.in_flight()});
  out.family("slosh_cam_export_budget_bytes", "gauge",
             "The budget of the cam exports in flight (cam_export_bytes).");
  out.sample("slosh_cam_export_budget_bytes", "", std::uint64_t{export_budget_.capacity()});
}

std::string PlanEngine::cache_description() const {
  std::string text = config_.cache_entries > 0 ? "memory" : "";
  if (const std::string path = local_cache_path(config_); !path.empty()) {
    text += (text.empty() ? "" : " + ") + std::string("sqlite ") + path;
  }
  if (redis_)
    text += (text.empty() ? "" : " + ") + std::string("redis ") + redis_->options().url.display();
  return text.empty() ? "none" : text;
}

void PlanEngine::begin_shutdown() {
  ready_ = false;
  pool_.stop_accepting();
  // A min-time search is many plans (up to a budget per strategy): it stops between two of them
  // and answers the shutdown's 503 at once, instead of holding the exit for a budget whose answer
  // would be thrown away. A plan solve is one budget at most and its answer is kept: it finishes.
  const std::lock_guard lock(inflight_mutex_);
  for (auto& [key, flight] : min_time_inflight_) flight.waiters->stop = true;
}

}  // namespace slosh::service
