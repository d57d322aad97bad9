#include "engine/plan_engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <future>
#include <memory>
#include <optional>
#include <thread>
#include <utility>

#include "cache/redis_cache.hpp"
#include "engine/engine_errors.hpp"
#include "export/plan_cam_file.hpp"
#include "http/client_wait.hpp"
#include "slosh/api/exact_number.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/plan_reply.hpp"

namespace slosh::service {

namespace {

std::shared_ptr<RedisClient> make_redis(const ServerConfig& config) {
  const std::string url = redis_cache_url(config);
  if (url.empty()) return nullptr;
  return std::make_shared<RedisClient>(RedisOptions{
      .url = parse_redis_url(url), .timeout = std::chrono::milliseconds(config.redis_timeout_ms)});
}

// A stored plan that depended on a time budget running out is never served: its key holds no
// time_limit_s, so it would answer every budget (such plans are not stored; an older build's may
// be in the store or the shared Redis).
bool plan_servable(std::string_view body) {
  return !api::budget_limited(body);
}

CacheConfig cache_config(const ServerConfig& config, std::shared_ptr<RedisClient> redis,
                         CacheTable table) {
  return CacheConfig{.path = local_cache_path(config),
                     .memory_entries = config.cache_entries,
                     .memory_bytes = config.cache_memory_bytes,
                     .store_bytes = table == CacheTable::kMinTime
                                        ? config.cache_min_time_store_bytes
                                        : config.cache_store_bytes,
                     .table = table,
                     .redis = std::move(redis),
                     .redis_ttl = std::chrono::seconds(config.cache_ttl_s),
                     .servable = table == CacheTable::kPlans ? plan_servable : nullptr};
}

double seconds_since(std::chrono::steady_clock::time_point started) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

}  // namespace

PlanEngine::PlanEngine(const ServerConfig& config)
    : config_(config),
      redis_(make_redis(config)),
      cache_(cache_config(config, redis_, CacheTable::kPlans)),
      min_time_cache_(cache_config(config, redis_, CacheTable::kMinTime)),
      export_budget_(config.cam_export_bytes),
      pool_(
          config.workers == 0 ? std::max(1u, std::thread::hardware_concurrency()) : config.workers,
          config.queue) {}

PlanEngine::~PlanEngine() = default;

std::optional<std::string> PlanEngine::remembered_key(const std::string& text) {
  if (text.size() > kRequestKeyTextBytes) return std::nullopt;
  const std::lock_guard lock(request_keys_mutex_);
  const auto it = request_keys_.find(text);
  if (it == request_keys_.end()) return std::nullopt;
  return it->second;
}

void PlanEngine::remember_key(const std::string& text, const std::string& key) {
  if (text.size() > kRequestKeyTextBytes) return;
  const std::lock_guard lock(request_keys_mutex_);
  if (request_keys_.size() >= kRequestKeys) request_keys_.clear();
  request_keys_.emplace(text, key);
}

std::optional<PlanAnswer> PlanEngine::cached_plan(const std::string& key, api::PlanView view) {
  CacheLevel level{};
  auto plan = cache_.find(key, &level);
  if (!plan) return std::nullopt;
  metrics_.count_cache_hit(level);
  PlanAnswer answer;
  answer.key = plan->key();
  answer.cached = true;
  answer.hit = std::move(plan);
  answer.view = view;
  return answer;
}

HitBody PlanEngine::plan_body(const PlanAnswer& answer, bool gzip) {
  if (answer.hit) return hit_body(cache_, answer.hit, answer.view, gzip);
  return HitBody{api::render_plan_reply(answer.body, answer.cached,
                                        answer.request ? &*answer.request : nullptr,
                                        answer.sample_period, answer.view),
                 false};
}

PlanFacts PlanEngine::plan_facts(const PlanAnswer& answer) {
  if (answer.hit) return hit_facts(cache_, answer.hit);
  return plan_facts_of(answer.key, answer.body, answer.cached);
}

void PlanEngine::count_plan(const PlanFacts& facts) {
  metrics_.count_plan(facts.strategy, facts.status);
}

void PlanEngine::join_locked(FlightWaiters& waiters, bool cancellable) {
  if (cancellable) {
    ++waiters.waiters;
  } else {
    waiters.pinned = true;
  }
}

bool PlanEngine::leave_flight(std::unordered_map<std::string, Flight>& flights,
                              const std::string& key, const std::shared_ptr<FlightWaiters>& waiters,
                              bool gone) {
  if (!waiters) return false;
  const std::lock_guard lock(inflight_mutex_);
  --waiters->waiters;
  if (!gone || waiters->waiters > 0 || waiters->pinned) return false;
  // Only a flight still running (in the map) is stopped: a finished one has forgotten itself.
  const auto it = flights.find(key);
  if (it == flights.end() || it->second.waiters != waiters) return false;
  waiters->stop = true;
  flights.erase(it);  // a new request for the key starts afresh, never joins a stopped solve
  return true;
}

void PlanEngine::forget_flight(std::unordered_map<std::string, Flight>& flights,
                               const std::string& key, std::uint64_t id) {
  const std::lock_guard lock(inflight_mutex_);
  if (auto it = flights.find(key); it != flights.end() && it->second.id == id) flights.erase(it);
}

std::string PlanEngine::flight_name(const std::string& key, double budget) {
  // The budget's exact bits: two budgets share a flight only when they are the same double.
  return key + "@" + api::exact_number_text(budget);
}

std::optional<std::shared_future<PlanEngine::Outcome>> PlanEngine::join_or_add_flight(
    const std::string& key, double budget, const std::shared_future<Outcome>& future,
    const std::shared_ptr<FlightWaiters>& waiters, std::shared_ptr<FlightWaiters>* waiter,
    std::uint64_t& flight, bool* refused) {
  // Single flight: a request for a recipe already being solved with its budget waits for that
  // solve (flight_name). The lock covers only the map, never the queueing (workers take it to
  // finish their task).
  const std::string name = flight_name(key, budget);
  const std::lock_guard lock(inflight_mutex_);
  if (auto it = inflight_.find(name); it != inflight_.end()) {
    metrics_.count_singleflight_join();
    join_locked(*it->second.waiters, waiter != nullptr);
    if (waiter != nullptr) *waiter = it->second.waiters;
    return it->second.future;
  }
  if (!ready_) {
    *refused = true;
    return std::nullopt;
  }
  flight = ++flights_;
  join_locked(*waiters, waiter != nullptr);
  inflight_[name] = Flight{future, budget, flight, waiters};
  return std::nullopt;
}

std::shared_future<PlanEngine::Outcome> PlanEngine::solve(
    const std::string& key, const api::PlanRequest& request, bool wait_for_room, bool* refused,
    TaskPriority priority, std::shared_ptr<FlightWaiters>* waiter, HitView hit) {
  *refused = false;
  auto promise = std::make_shared<std::promise<Outcome>>();
  auto waiters = std::make_shared<FlightWaiters>();
  std::shared_future<Outcome> future = promise->get_future().share();
  std::uint64_t flight = 0;
  if (auto joined = join_or_add_flight(key, request.options.time_limit, future, waiters, waiter,
                                       flight, refused)) {
    return *joined;
  }
  if (*refused) return {};
  if (waiter != nullptr) *waiter = waiters;
  // The solve stops (between its starts) once nobody waits for it: see leave_flight.
  api::PlanRequest solving = request;
  solving.options.stop = &waiters->stop;
  metrics_.count_cache_miss();
  auto task = [this, key, request = std::move(solving), promise, flight, waiters, hit] {
    run_solve(key, request, promise, flight, waiters, hit);
  };
  const bool queued =
      wait_for_room ? pool_.submit_wait(task, priority) : pool_.try_submit(task, priority);
  if (!queued) {
    // Whoever joined this solve meanwhile gets the refusal too (never a future that hangs).
    forget_flight(inflight_, flight_name(key, request.options.time_limit), flight);
    promise->set_value(Outcome{{}, overloaded_error()});
    *refused = true;
    return {};
  }
  return future;
}

void PlanEngine::run_solve(const std::string& key, const api::PlanRequest& request,
                           const std::shared_ptr<std::promise<Outcome>>& promise,
                           std::uint64_t flight, const std::shared_ptr<FlightWaiters>& waiters,
                           HitView hit) {
  Outcome outcome;
  std::shared_ptr<const CachedValue> stored;
  const auto started = std::chrono::steady_clock::now();
  if (!ready_) {
    // Shutting down: what is still queued is answered at once, only running solves finish.
    outcome.error = overloaded_error();
  } else if (waiters->stop) {
    outcome.error = cancelled_error();  // its clients left while it was queued
  } else {
    try {
      stored = solve_once_across_replicas(key, request, outcome, started);
    } catch (const api::ApiError& e) {
      outcome.error = e;
    } catch (const std::exception& e) {
      outcome.error = api::ApiError(api::ErrorCode::kInternal, "", e.what());
    } catch (...) {
      outcome.error =
          api::ApiError(api::ErrorCode::kInternal, "", "the solve failed with an unknown error");
    }
  }
  forget_flight(inflight_, flight_name(key, request.options.time_limit), flight);
  promise->set_value(std::move(outcome));
  // A client that asked for a plan is likely to ask again in the same view: what that hit
  // answers is rendered now, after the answer is out (only that view: a client rarely asks for
  // both, and a view nobody asks for is never rendered).
  if (stored) {
    try {
      prepare_hit_body(cache_, stored, hit.view, hit.gzip);
    } catch (const std::exception&) {
      // The hit renders it again (and answers the error then).
    }
  }
}

api::ApiError PlanEngine::overloaded_error() const {
  return api::ApiError(
      api::ErrorCode::kOverloaded, "",
      ready_ ? "all " + std::to_string(pool_.workers()) + " workers are busy and the queue of " +
                   std::to_string(pool_.capacity()) + " solves is full; retry after " +
                   std::to_string(kRetryAfterSeconds) + " s"
             : "the service is shutting down");
}

PlanAnswer PlanEngine::answer_plan(const std::string& text, api::PlanView view, bool gzip,
                                   const std::function<bool()>& abandoned) {
  // A request text seen before (without series) needs no parsing to be answered from the cache.
  if (auto key = remembered_key(text)) {
    if (auto hit = cached_plan(*key, view)) return std::move(*hit);
  }
  api::PlanRequest request = api::parse_plan_text(text, config_.solve_budget_s);
  api::require_no_series(view, request.sample_period);
  const std::string key = api::recipe_key(request);
  // The plan is cached per recipe; the series are rendered per request (they are not part of
  // the recipe, and a cached plan must answer whatever period this request asks for).
  const std::optional<double> sample_period = std::exchange(request.sample_period, std::nullopt);
  if (!sample_period) {
    if (auto hit = cached_plan(key, view)) {
      remember_key(text, key);
      return std::move(*hit);
    }
  } else {
    CacheLevel level{};
    if (const auto hit = cache_.find(key, &level)) {
      metrics_.count_cache_hit(level);
      return PlanAnswer{key, true, nullptr, hit->value(), std::move(request), sample_period, view};
    }
  }
  bool refused = false;
  std::shared_ptr<FlightWaiters> waiters;
  auto future = solve(key, request, false, &refused, TaskPriority::kInteractive,
                      abandoned ? &waiters : nullptr, HitView{view, gzip});
  if (refused) throw overloaded_error();
  Outcome outcome = wait_for_plan(key, request, future, waiters, abandoned);
  return PlanAnswer{
      key,           false, nullptr,        std::move(outcome.body), std::move(request),
      sample_period, view,  outcome.partial};
}

PlanEngine::Outcome PlanEngine::wait_for_plan(const std::string& key,
                                              const api::PlanRequest& request,
                                              const std::shared_future<Outcome>& future,
                                              const std::shared_ptr<FlightWaiters>& waiters,
                                              const std::function<bool()>& abandoned) {
  const WaitEnd end =
      wait_for_client(future, after(request.options.time_limit + config_.queue_wait_s), abandoned);
  // A request answered 504 waits no more either: its solve is stopped as for a client that hung
  // up (unless another request still waits for it), never run to its budget for nobody.
  if (leave_flight(inflight_, flight_name(key, request.options.time_limit), waiters,
                   end != WaitEnd::kReady)) {
    ++(end == WaitEnd::kTimeout ? timed_out_plans_ : cancelled_plans_);
  }
  if (end == WaitEnd::kGone) throw cancelled_error();
  if (end == WaitEnd::kTimeout) {
    throw api::ApiError(api::ErrorCode::kTimeout, "",
                        "the plan did not finish within its budget of " +
                            api::number_text(request.options.time_limit) + " s plus " +
                            api::number_text(config_.queue_wait_s) + " s of queueing");
  }
  const Outcome& outcome = future.get();
  if (outcome.error) throw *outcome.error;
  return outcome;
}

std::shared_ptr<const CachedValue> PlanEngine::solve_once_across_replicas(
    const std::string& key, const api::PlanRequest& request, Outcome& outcome,
    std::chrono::steady_clock::time_point started) {
  RedisCache* shared = cache_.shared();
  std::string token;
  if (shared != nullptr) {
    // Another replica's solve is waited for at most its budget and a second; one that dies or is
    // paused holding the lock stops renewing it, and it expires within RedisCache::kLockLease.
    const auto hold = std::chrono::milliseconds(
        static_cast<long long>(std::ceil(request.options.time_limit * 1000.0)) + 1000);
    if (auto body = shared->lock_or_wait(key, hold, token)) {
      metrics_.count_singleflight_join();  // another replica's solve answered
      auto entry = cache_.put_local(key, *body);
      outcome.body = std::move(*body);
      return entry;
    }
  }
  std::shared_ptr<const CachedValue> stored;
  try {
    api::StoredPlan plan = api::solve_for_storing(request);
    // A solve stopped because nobody waits is cut short: never kept, whatever its status says.
    const bool stopped = request.options.stop != nullptr && request.options.stop->load();
    outcome.partial = !api::is_cacheable(plan) || stopped;
    if (!outcome.partial) stored = cache_.put(key, plan.body);
    outcome.body = std::move(plan.body);
  } catch (...) {
    metrics_.observe_solve(to_string(request.strategy), seconds_since(started));
    if (shared != nullptr) shared->unlock(key, token);
    throw;
  }
  metrics_.observe_solve(to_string(request.strategy), seconds_since(started));
  if (shared != nullptr) shared->unlock(key, token);
  return stored;
}

CamExport PlanEngine::cam_export(const std::string& key, const CamOptions& options,
                                 bool allow_infeasible) {
  CacheLevel level{};
  const auto hit = cache_.find(key, &level);
  if (!hit) throw plan_not_found(key);
  metrics_.count_cache_hit(level);
  CamExport out;
  out.file = plan_cam_file(api::render_plan_reply(hit->value(), true), options, allow_infeasible,
                           [&](std::size_t bytes) { out.hold = reserve_export(bytes); });
  return out;
}

std::shared_ptr<const void> PlanEngine::reserve_export(std::size_t bytes) {
  auto ticket = export_budget_.try_reserve(bytes);
  if (ticket) return ticket;
  metrics_.count_export_refusal();
  throw api::ApiError(
      api::ErrorCode::kOverloaded, "",
      "the cam exports in flight hold " + std::to_string(export_budget_.in_flight()) + " of the " +
          std::to_string(export_budget_.capacity()) + " bytes allowed (cam_export_bytes); this " +
          "table needs up to " + std::to_string(bytes) + ": retry later");
}

}  // namespace slosh::service
