#include "plan_service.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <thread>
#include <utility>

#include "client_wait.hpp"
#include "export_command.hpp"
#include "gzip.hpp"
#include "redis_cache.hpp"
#include "slosh/api/core_input.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/openapi.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_reply.hpp"
#include "slosh/api/service_bodies.hpp"
#include "slosh/api/simulate.hpp"
#include "version.hpp"
#include "web_assets.hpp"

namespace slosh::service {

namespace {

using nlohmann::json;

/// Seconds a client is told to wait after a 503.
constexpr int kRetryAfterSeconds = 1;
/// /readyz turns 503 when the pool has work but finished nothing for max(this, 3 solve budgets).
constexpr double kMinStallSeconds = 30.0;

std::string etag(const std::string& key) {
  return "\"" + key + "\"";
}

// The ETag of a plan reply names the body: the same plan with series of another period, or in the
// compact view, is another body. (The gzip coding of a body is the same representation: same tag.)
std::string plan_etag(const std::string& key, api::PlanView view,
                      const std::optional<double>& sample_period) {
  return view == api::PlanView::kCompact ? etag(key + ";view=compact")
         : sample_period                 ? etag(key + ";series=" + api::number_text(*sample_period))
                                         : etag(key);
}

// Whether an If-None-Match header names `tag`: "*", or a list of tags compared weakly (RFC 9110
// 13.1.2: W/"x" matches "x").
bool etag_matches(const std::string& header, const std::string& tag) {
  std::size_t at = 0;
  while (at < header.size()) {
    std::size_t end = header.find(',', at);
    if (end == std::string::npos) end = header.size();
    std::string item = header.substr(at, end - at);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.rfind("W/", 0) == 0) item.erase(0, 2);
    if (item == "*" || item == tag) return true;
    at = end + 1;
  }
  return false;
}

// The reply of a stored min-time answer: ETag = the key (one body per key), 304 for a cached
// answer whose ETag `if_none_match` names.
Reply min_time_reply(const std::string& key, const std::string& stored, bool cached,
                     const std::string& if_none_match) {
  Reply r;
  r.headers.emplace_back("ETag", etag(key));
  r.headers.emplace_back("X-Cache", cached ? "hit" : "miss");
  if (cached && etag_matches(if_none_match, etag(key))) {
    r.status = 304;
    return r;
  }
  r.body = api::render_min_time_reply(stored, cached);
  return r;
}

std::shared_ptr<RedisClient> make_redis(const ServerConfig& config) {
  const std::string url = redis_cache_url(config);
  if (url.empty()) return nullptr;
  return std::make_shared<RedisClient>(RedisOptions{
      .url = parse_redis_url(url), .timeout = std::chrono::milliseconds(config.redis_timeout_ms)});
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
                     .redis_ttl = std::chrono::seconds(config.cache_ttl_s)};
}

// Adds the shared level's state to `report`: Redis down makes a ready replica degraded (200: it
// answers from its local levels), or not ready (503) when Redis is required.
void add_redis_state(api::ReadyReport& report, RedisClient& redis, bool required, bool& unready) {
  redis.probe();  // a replica without traffic finds its Redis again through its probes
  const RedisClient::State state = redis.state();
  report.redis_configured = true;
  report.redis_url = redis.options().url.display();
  report.redis_up = state.up;
  report.redis_required = required;
  report.redis_error = state.error;
  if (state.up || (report.status != "ready" && report.status != "degraded")) return;
  const std::string why = "redis " + report.redis_url + " is down (" + state.error + "); " +
                          (required ? "redis_required is set, so this replica is not ready"
                                    : "answering from the local cache levels");
  report.reason = report.reason.empty() ? why : why + "; " + report.reason;
  report.status = "degraded";
  if (required) unready = true;
}

// Nobody waits for the solve any more (its reply is for a connection that is gone).
api::ApiError cancelled_error() {
  return api::ApiError(api::ErrorCode::kCancelled, "",
                       "not solved: every client waiting for it closed the connection");
}

double seconds_since(std::chrono::steady_clock::time_point started) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

}  // namespace

PlanService::PlanService(const ServerConfig& config)
    : config_(config),
      redis_(make_redis(config)),
      cache_(cache_config(config, redis_, CacheTable::kPlans)),
      min_time_cache_(cache_config(config, redis_, CacheTable::kMinTime)),
      export_budget_(config.cam_export_bytes),
      pool_(
          config.workers == 0 ? std::max(1u, std::thread::hardware_concurrency()) : config.workers,
          config.queue) {}

PlanService::~PlanService() = default;

Reply reply_of(const api::ApiError& error) {
  Reply r;
  r.status = error.status();
  r.body = api::error_body(error);
  // Every 503 says when to retry: overloaded, and unavailable (the shared store cannot answer now).
  if (error.code() == api::ErrorCode::kOverloaded || error.code() == api::ErrorCode::kUnavailable) {
    r.headers.emplace_back("Retry-After", std::to_string(kRetryAfterSeconds));
  }
  return r;
}

Reply internal_error_reply(const char* what) {
  return PlanService::error_reply(api::ErrorCode::kInternal, what);
}

Reply PlanService::error_reply(api::ErrorCode code, const std::string& message,
                               const std::string& field) {
  return reply_of(api::ApiError(code, field, message));
}

Reply PlanService::plan_reply(const std::string& key, const std::string& body, bool cached,
                              const std::string& if_none_match,
                              const std::optional<api::PlanRequest>& request,
                              std::optional<double> sample_period, api::PlanView view) const {
  Reply r;
  const std::string tag = plan_etag(key, view, sample_period);
  r.headers.emplace_back("ETag", tag);
  r.headers.emplace_back("X-Cache", cached ? "hit" : "miss");
  r.plan = plan_facts_of(key, body, cached);
  if (cached && etag_matches(if_none_match, tag)) {
    r.status = 304;
    return r;
  }
  r.body = api::render_plan_reply(body, cached, request ? &*request : nullptr, sample_period, view);
  return r;
}

Reply PlanService::hit_reply(const std::shared_ptr<const CachedValue>& plan,
                             const std::string& if_none_match, api::PlanView view, bool gzip) {
  Reply r;
  const std::string tag = plan_etag(plan->key(), view, std::nullopt);
  r.headers.emplace_back("ETag", tag);
  r.headers.emplace_back("X-Cache", "hit");
  r.plan = hit_facts(cache_, plan);
  if (etag_matches(if_none_match, tag)) {
    r.status = 304;
    return r;
  }
  HitBody body = hit_body(cache_, plan, view, gzip);
  r.body = std::move(body.body);
  if (body.gzip) r.content_encoding = "gzip";
  return r;
}

std::optional<std::string> PlanService::remembered_key(const std::string& text) {
  if (text.size() > kRequestKeyTextBytes) return std::nullopt;
  const std::lock_guard lock(request_keys_mutex_);
  const auto it = request_keys_.find(text);
  if (it == request_keys_.end()) return std::nullopt;
  return it->second;
}

void PlanService::remember_key(const std::string& text, const std::string& key) {
  if (text.size() > kRequestKeyTextBytes) return;
  const std::lock_guard lock(request_keys_mutex_);
  if (request_keys_.size() >= kRequestKeys) request_keys_.clear();
  request_keys_.emplace(text, key);
}

std::optional<Reply> PlanService::cached_plan_reply(const std::string& key,
                                                    const std::string& if_none_match,
                                                    api::PlanView view, bool gzip) {
  CacheLevel level{};
  const auto plan = cache_.find(key, &level);
  if (!plan) return std::nullopt;
  metrics_.count_cache_hit(level);
  return hit_reply(plan, if_none_match, view, gzip);
}

void PlanService::join_locked(FlightWaiters& waiters, bool cancellable) {
  if (cancellable) {
    ++waiters.waiters;
  } else {
    waiters.pinned = true;
  }
}

bool PlanService::leave_flight(std::unordered_map<std::string, Flight>& flights,
                               const std::string& key,
                               const std::shared_ptr<FlightWaiters>& waiters, bool gone) {
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

std::shared_future<PlanService::Outcome> PlanService::solve(
    const std::string& key, const api::PlanRequest& request, bool wait_for_room, bool* refused,
    TaskPriority priority, std::shared_ptr<FlightWaiters>* waiter, HitView hit) {
  *refused = false;
  auto promise = std::make_shared<std::promise<Outcome>>();
  auto waiters = std::make_shared<FlightWaiters>();
  std::shared_future<Outcome> future = promise->get_future().share();
  const double budget = request.options.time_limit;
  std::uint64_t flight = 0;
  {
    // Single flight: a request for a recipe already being solved with at least its budget waits
    // for that solve (a larger budget is another answer: it solves on its own). The lock covers
    // only the map, never the queueing below (workers take it to finish their task).
    std::lock_guard lock(inflight_mutex_);
    if (auto it = inflight_.find(key); it != inflight_.end() && it->second.budget >= budget) {
      metrics_.count_singleflight_join();
      join_locked(*it->second.waiters, waiter != nullptr);
      if (waiter != nullptr) *waiter = it->second.waiters;
      return it->second.future;
    }
    if (!ready_) {
      *refused = true;
      return {};
    }
    flight = ++flights_;
    join_locked(*waiters, waiter != nullptr);
    inflight_[key] = Flight{future, budget, flight, waiters};
  }
  if (waiter != nullptr) *waiter = waiters;
  // The solve stops (between its starts) once nobody waits for it: see leave_flight.
  api::PlanRequest solving = request;
  solving.options.stop = &waiters->stop;
  auto forget = [this, key, flight] { forget_flight(inflight_, key, flight); };
  metrics_.count_cache_miss();
  auto task = [this, key, request = std::move(solving), promise, forget, waiters, hit] {
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
    forget();
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
  };
  const bool queued =
      wait_for_room ? pool_.submit_wait(task, priority) : pool_.try_submit(task, priority);
  if (!queued) {
    // Whoever joined this solve meanwhile gets the refusal too (never a future that hangs).
    forget();
    promise->set_value(Outcome{{}, overloaded_error()});
    *refused = true;
    return {};
  }
  return future;
}

api::ApiError PlanService::overloaded_error() const {
  return api::ApiError(
      api::ErrorCode::kOverloaded, "",
      ready_ ? "all " + std::to_string(pool_.workers()) + " workers are busy and the queue of " +
                   std::to_string(pool_.capacity()) + " solves is full; retry after " +
                   std::to_string(kRetryAfterSeconds) + " s"
             : "the service is shutting down");
}

Reply PlanService::counted(Reply reply) {
  if (reply.plan) metrics_.count_plan(reply.plan->strategy, reply.plan->status);
  return reply;
}

Reply PlanService::overloaded_reply() const {
  return reply_of(overloaded_error());
}

Reply PlanService::post_plan(const std::string& text, const std::string& if_none_match,
                             const std::vector<std::string>& view_query, bool gzip,
                             const std::function<bool()>& abandoned) {
  return guarded_reply([&] {
    const api::PlanView view = api::parse_view_query(view_query);
    // A request text seen before (without series) needs no parsing to be answered from the cache.
    if (auto key = remembered_key(text)) {
      if (auto reply = cached_plan_reply(*key, if_none_match, view, gzip)) {
        return counted(std::move(*reply));
      }
    }
    api::PlanRequest request = api::parse_plan_text(text, config_.solve_budget_s);
    api::require_no_series(view, request.sample_period);
    const std::string key = api::recipe_key(request);
    // The plan is cached per recipe; the series are rendered per request (they are not part of
    // the recipe, and a cached plan must answer whatever period this request asks for).
    const std::optional<double> sample_period = std::exchange(request.sample_period, std::nullopt);
    if (!sample_period) {
      if (auto reply = cached_plan_reply(key, if_none_match, view, gzip)) {
        remember_key(text, key);
        return counted(std::move(*reply));
      }
    } else {
      CacheLevel level{};
      if (const auto hit = cache_.find(key, &level)) {
        metrics_.count_cache_hit(level);
        return counted(
            plan_reply(key, hit->value(), true, if_none_match, request, sample_period, view));
      }
    }
    bool refused = false;
    std::shared_ptr<FlightWaiters> waiters;
    auto future = solve(key, request, false, &refused, TaskPriority::kInteractive,
                        abandoned ? &waiters : nullptr, HitView{view, gzip});
    if (refused) return overloaded_reply();
    const WaitEnd end = wait_for_client(
        future, after(request.options.time_limit + config_.queue_wait_s), abandoned);
    if (leave_flight(inflight_, key, waiters, end == WaitEnd::kGone)) ++cancelled_plans_;
    if (end == WaitEnd::kGone) return reply_of(cancelled_error());
    if (end == WaitEnd::kTimeout) {
      return error_reply(api::ErrorCode::kTimeout,
                         "the plan did not finish within its budget of " +
                             api::number_text(request.options.time_limit) + " s plus " +
                             api::number_text(config_.queue_wait_s) + " s of queueing");
    }
    const Outcome& outcome = future.get();
    if (outcome.error) return reply_of(*outcome.error);
    return counted(
        plan_reply(key, outcome.body, false, if_none_match, request, sample_period, view));
  });
}

// A min-time search in flight: the request, one result slot per strategy, and the promise kept
// by the last task to finish.
struct PlanService::MinTimeSearch {
  api::MinTimeRequest request;
  std::string key;
  std::uint64_t flight{};
  std::vector<MinTimeResult> results;
  // Tasks not finished, plus one held by the queueing thread until it has queued them all.
  std::atomic<std::size_t> remaining{0};
  // A task could not be queued: the 503 is published and the queued tasks skip their strategy.
  std::atomic<bool> refused{false};
  // A task was still queued when shutdown began: the search answers 503, as queued plan solves do.
  std::atomic<bool> shut_down{false};
  std::promise<Outcome> promise;
  // Who waits; its stop flag ends every strategy's search between two plans.
  std::shared_ptr<FlightWaiters> waiters{std::make_shared<FlightWaiters>()};
};

void PlanService::leave_min_time(const PendingMinTime& pending, bool gone) {
  if (leave_flight(min_time_inflight_, pending.key, pending.waiters, gone)) ++cancelled_min_times_;
}

void PlanService::forget_flight(std::unordered_map<std::string, Flight>& flights,
                                const std::string& key, std::uint64_t id) {
  const std::lock_guard lock(inflight_mutex_);
  if (auto it = flights.find(key); it != flights.end() && it->second.id == id) flights.erase(it);
}

PendingMinTime PlanService::start_min_time(const api::MinTimeRequest& request, bool wait_for_room,
                                           bool cancellable) {
  PendingMinTime pending;
  pending.key = api::min_time_key(request);
  CacheLevel level{};
  if (auto hit = min_time_cache_.get(pending.key, &level)) {
    metrics_.count_cache_hit(level);
    pending.cached = std::move(hit);
    return pending;
  }
  auto search = std::make_shared<MinTimeSearch>();
  pending.search = search->promise.get_future().share();
  const double budget = request.options.plan.time_limit;
  {
    // Single flight, as for plans: a request joins a running search of its key that has at least
    // its budget (a larger budget may find more). The lock covers only the map.
    const std::lock_guard lock(inflight_mutex_);
    if (auto it = min_time_inflight_.find(pending.key);
        it != min_time_inflight_.end() && it->second.budget >= budget) {
      metrics_.count_min_time_join();
      pending.search = it->second.future;
      join_locked(*it->second.waiters, cancellable);
      if (cancellable) pending.waiters = it->second.waiters;
      return pending;
    }
    if (ready_) {
      search->flight = ++flights_;
      join_locked(*search->waiters, cancellable);
      min_time_inflight_[pending.key] =
          Flight{pending.search, budget, search->flight, search->waiters};
      if (cancellable) pending.waiters = search->waiters;
    }
  }
  if (search->flight == 0) {  // shutting down
    search->promise.set_value(Outcome{{}, overloaded_error()});
    return pending;
  }
  // A search of this key may have finished (cached, then forgotten) since the lookup above.
  if (auto hit = min_time_cache_.get(pending.key, &level)) {
    forget_flight(min_time_inflight_, pending.key, search->flight);
    search->promise.set_value(Outcome{*hit, std::nullopt});  // for whoever joined meanwhile
    metrics_.count_cache_hit(level);
    pending.cached = std::move(hit);
    pending.search = {};
    pending.waiters.reset();
    return pending;
  }
  search->request = request;
  search->key = pending.key;
  search->results.resize(request.strategies.size());
  queue_min_time_tasks(search, wait_for_room);
  return pending;
}

void PlanService::queue_min_time_tasks(const std::shared_ptr<MinTimeSearch>& search,
                                       bool wait_for_room) {
  const std::size_t n = search->results.size();
  search->remaining = n + 1;
  for (std::size_t i = 0; i < n; ++i) {
    // Background priority: a search is up to a second of work per strategy, and the plans an HMI
    // waits for go ahead of its queued strategies (as batch jobs' items).
    auto task = [this, search, i] { run_min_time_task(search, i); };
    const bool queued = wait_for_room ? pool_.submit_wait(task, TaskPriority::kBackground)
                                      : pool_.try_submit(task, TaskPriority::kBackground);
    if (!queued) {
      // Whoever joined this search gets the refusal too (never a future that hangs), and a new
      // request starts afresh; the i tasks already queued skip their strategy.
      search->refused = true;
      forget_flight(min_time_inflight_, search->key, search->flight);
      search->promise.set_value(Outcome{{}, overloaded_error()});
      search->remaining -= n - i + 1;
      return;
    }
  }
  metrics_.count_min_time_search();
  metrics_.count_cache_miss();
  if (search->remaining.fetch_sub(1) == 1) finish_min_time(*search);
}

void PlanService::run_min_time_task(const std::shared_ptr<MinTimeSearch>& search, std::size_t i) {
  if (!search->refused) {
    const api::MinTimeRequest& request = search->request;
    MinTimeResult& slot = search->results[i];
    const auto started = std::chrono::steady_clock::now();
    slot.strategy = request.strategies[i];
    if (!ready_) {
      // Shutting down: what is still queued is answered at once, only running searches finish.
      search->shut_down = true;
    } else if (search->waiters->stop) {
      slot.status = SolveStatus::kTimeLimit;  // nobody waits: not searched (and not cached)
      slot.message = "not searched: every client waiting for it closed the connection";
    } else {
      try {
        MinTimeOptions options = request.options;
        options.plan.stop = &search->waiters->stop;
        slot = min_time(request.format, request.strategies[i], options);
      } catch (...) {
        slot = MinTimeResult{};
        slot.strategy = request.strategies[i];
        slot.status = SolveStatus::kFailed;
        slot.message = "the search failed";
      }
    }
    metrics_.observe_solve(
        "min_time:" + to_string(request.strategies[i]),
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  }
  if (search->remaining.fetch_sub(1) == 1) finish_min_time(*search);
}

void PlanService::finish_min_time(MinTimeSearch& search) {
  if (search.refused) return;  // its refusal has been published
  Outcome outcome;
  try {
    if (search.shut_down) throw overloaded_error();
    if (search.waiters->stop) throw cancelled_error();
    api::check_min_time_inputs(search.request, search.results);
    outcome.body = api::stored_min_time(search.request, search.results, search.key);
    // Cached before the flight is forgotten: a new request finds one or the other.
    if (api::is_min_time_cacheable(search.results)) min_time_cache_.put(search.key, outcome.body);
  } catch (const api::ApiError& e) {
    outcome.error = e;
  } catch (const std::exception& e) {
    outcome.error = api::ApiError(api::ErrorCode::kInternal, "", e.what());
  } catch (...) {
    outcome.error = api::ApiError(api::ErrorCode::kInternal, "",
                                  "the min-time answer failed with an unknown error");
  }
  forget_flight(min_time_inflight_, search.key, search.flight);
  search.promise.set_value(std::move(outcome));
}

Reply PlanService::post_min_time(const std::string& text, const std::string& if_none_match,
                                 const std::function<bool()>& abandoned) {
  return guarded_reply([&] {
    const api::MinTimeRequest request =
        api::parse_min_time_request(api::parse_json_body(text), config_.solve_budget_s);
    const PendingMinTime pending = start_min_time(request, false, static_cast<bool>(abandoned));
    if (pending.cached) return min_time_reply(pending.key, *pending.cached, true, if_none_match);
    const WaitEnd end = wait_for_client(
        pending.search, after(request.options.plan.time_limit + config_.queue_wait_s), abandoned);
    leave_min_time(pending, end == WaitEnd::kGone);
    if (end == WaitEnd::kGone) return reply_of(cancelled_error());
    if (end == WaitEnd::kTimeout) {
      return error_reply(api::ErrorCode::kTimeout,
                         "the min-time search did not finish within its budget of " +
                             api::number_text(request.options.plan.time_limit) + " s plus " +
                             api::number_text(config_.queue_wait_s) + " s of queueing");
    }
    const Outcome& outcome = pending.search.get();
    if (outcome.error) return reply_of(*outcome.error);
    // A request that joined another's search answers as that one did: a miss, the same body.
    return min_time_reply(pending.key, outcome.body, false, if_none_match);
  });
}

Reply PlanService::get_plan(const std::string& key, const std::string& if_none_match,
                            const std::vector<std::string>& view_query, bool gzip) {
  return guarded_reply([&] {
    if (key == "batch") {  // the path of POST /v1/plans/batch, not a key
      Reply r = error_reply(api::ErrorCode::kMethodNotAllowed,
                            "GET is not allowed on /v1/plans/batch; allowed: POST");
      r.headers.emplace_back("Allow", "POST");
      return r;
    }
    const api::PlanView view = api::parse_view_query(view_query);
    if (auto reply = cached_plan_reply(key, if_none_match, view, gzip)) {
      return counted(std::move(*reply));
    }
    return error_reply(
        api::ErrorCode::kNotFound,
        "no plan with key '" + key.substr(0, 64) + "': POST the recipe to /v1/plans first", "key");
  });
}

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

StartedItem PlanService::start_batch_item(const json& item, TaskPriority priority) {
  StartedItem started;
  BatchResult& result = started.result;
  try {
    const api::PlanRequest request = api::parse_batch_item(item, config_.solve_budget_s);
    const std::string key = api::recipe_key(request);
    CacheLevel level{};
    if (const auto hit = cache_.find(key, &level)) {
      metrics_.count_cache_hit(level);
      result.plan = api::render_plan_reply(hit->value(), true);
      result.cached = true;
      return started;
    }
    bool refused = false;
    started.pending = solve(key, request, true, &refused, priority);
    if (refused) result.error = overloaded_error();
  } catch (const api::ApiError& e) {
    result.error = e;
  } catch (const std::exception& e) {
    result.error = api::ApiError(api::ErrorCode::kInternal, "", e.what());
  }
  return started;
}

PendingBatch PlanService::start_batch(const std::vector<json>& requests,
                                      const std::function<bool()>& abandoned) {
  PendingBatch batch;
  const std::size_t n = requests.size();
  batch.results_.resize(n);
  batch.pending_.resize(n);
  bool gone = false;
  for (std::size_t i = 0; i < n; ++i) {
    // A client that went away gets no more solves queued for it (the queued ones still run);
    // cache hits and invalid items are still answered.
    gone = gone || (abandoned && abandoned());
    if (gone) {
      try {
        const api::PlanRequest request = api::parse_batch_item(requests[i], config_.solve_budget_s);
        CacheLevel level{};
        if (const auto hit = cache_.find(api::recipe_key(request), &level)) {
          metrics_.count_cache_hit(level);
          batch.results_[i].plan = api::render_plan_reply(hit->value(), true);
          batch.results_[i].cached = true;
        } else {
          batch.results_[i].error = api::ApiError(api::ErrorCode::kCancelled, "",
                                                  "not solved: the client closed the connection");
        }
      } catch (const api::ApiError& e) {
        batch.results_[i].error = e;
      }
      continue;
    }
    StartedItem started = start_batch_item(requests[i]);
    batch.results_[i] = std::move(started.result);
    batch.pending_[i] = std::move(started.pending);
  }
  return batch;
}

Reply PlanService::post_batch(const std::string& text, const std::function<bool()>& abandoned,
                              const std::vector<std::string>& view_query) {
  return guarded_reply([&] {
    const api::BatchBody body = api::parse_batch_body(text, config_.batch_max);
    const api::PlanView view = api::batch_view(view_query, body.view);
    const PendingBatch batch = start_batch(body.requests, abandoned);
    api::BatchReplyWriter writer(config_.max_response_bytes);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      const BatchResult item = batch.get(i);
      if (item.ok()) {
        const PlanFacts facts = plan_facts_of("", item.plan, item.cached);
        metrics_.count_plan(facts.strategy, facts.status);
        writer.add_plan(
            i, view == api::PlanView::kCompact ? api::compact_plan_text(item.plan) : item.plan);
      } else {
        writer.add_error(i, *item.error);
      }
    }
    Reply r;
    r.body = writer.finish();
    return r;
  });
}

Reply PlanService::post_simulate(const std::string& text) {
  return guarded_reply([&] {
    Reply r;
    r.body =
        api::dump_json(api::run_simulate(api::parse_simulate_request(api::parse_json_body(text))));
    return r;
  });
}

Reply PlanService::web_asset(const std::string& name, const std::string& if_none_match,
                             bool gzip) const {
  const WebAsset* asset = find_web_asset(name.empty() ? "index.html" : name);
  if (asset == nullptr) {
    return error_reply(api::ErrorCode::kNotFound,
                       "no asset '" + name.substr(0, 64) + "' of the web page", "name");
  }
  Reply r;
  const std::string tag(asset->etag);
  r.headers.emplace_back("ETag", tag);
  // Revalidated on every use (a 304 is a few bytes): a new binary's page is never mixed with an
  // older cached script.
  r.headers.emplace_back("Cache-Control", "no-cache");
  r.headers.emplace_back("X-Content-Type-Options", "nosniff");
  r.headers.emplace_back("Content-Security-Policy", "frame-ancestors 'none'");
  if (etag_matches(if_none_match, tag)) {
    r.status = 304;
    return r;
  }
  r.content_type = std::string(asset->content_type);
  if (gzip && worth_compressing(asset->content_type, asset->body.size())) {
    r.body = std::string(gzipped_body(*asset));
    r.content_encoding = "gzip";
  } else {
    r.body = std::string(asset->body);
  }
  return r;
}

Reply PlanService::cam_table(const std::string& key, CamFileFormat format, const CamQuery& query) {
  return guarded_reply([&] {
    const CamOptions options = parse_cam_query(query, format);
    const std::string allow_infeasible =
        single_query_value(query.allow_infeasible, "allow_infeasible").value_or("false");
    if (allow_infeasible != "true" && allow_infeasible != "false") {
      throw api::ApiError(
          api::ErrorCode::kInvalidValue, "allow_infeasible",
          "allow_infeasible = " +
              (allow_infeasible.empty() ? "(empty)" : allow_infeasible.substr(0, 32)) +
              " is not allowed: one of \"true\", \"false\"");
    }
    CacheLevel level{};
    const auto hit = cache_.find(key, &level);
    if (!hit) {
      return error_reply(
          api::ErrorCode::kNotFound,
          "no plan with key '" + key.substr(0, 64) + "': POST the recipe to /v1/plans first",
          "key");
    }
    metrics_.count_cache_hit(level);
    const bool st = format == CamFileFormat::kSt;
    Reply r;
    r.content_type = st ? "text/plain; charset=utf-8" : "text/csv; charset=utf-8";
    r.body = plan_cam_file(api::render_plan_reply(hit->value(), true), options,
                           allow_infeasible == "true",
                           [&](std::size_t bytes) { r.hold = reserve_export(bytes); });
    const std::string table =
        options.master_period
            ? "master"
            : api::number_text(options.period_ms.value_or(kDefaultPeriodMs)) + "ms";
    r.headers.emplace_back("Content-Disposition", "attachment; filename=\"cam-" +
                                                      key.substr(0, 64) + "-" + table +
                                                      (st ? ".st\"" : ".csv\""));
    return r;
  });
}

std::shared_ptr<const void> PlanService::reserve_export(std::size_t bytes) {
  auto ticket = export_budget_.try_reserve(bytes);
  if (ticket) return ticket;
  metrics_.count_export_refusal();
  throw api::ApiError(
      api::ErrorCode::kOverloaded, "",
      "the cam exports in flight hold " + std::to_string(export_budget_.in_flight()) + " of the " +
          std::to_string(export_budget_.capacity()) + " bytes allowed (cam_export_bytes); this " +
          "table needs up to " + std::to_string(bytes) + ": retry later");
}

Reply PlanService::fluids() const {
  Reply r;
  r.body = api::dump_json(api::fluids_json());
  return r;
}

Reply PlanService::openapi() const {
  Reply r;
  r.body = api::dump_json(api::openapi_document(kVersion));
  return r;
}

Reply PlanService::health() const {
  Reply r;
  r.body = api::health_body(kVersion);
  return r;
}

std::string PlanService::store_error() const {
  std::string error = cache_.storage_error();
  return error.empty() ? min_time_cache_.storage_error() : error;
}

Reply PlanService::ready() const {
  const auto stats = cache_.stats();
  const std::string storage_error = store_error();
  const double stalled = std::chrono::duration<double>(pool_.stalled_for()).count();
  const double stall_limit = std::max(kMinStallSeconds, 3.0 * config_.solve_budget_s);
  api::ReadyReport report{.status = "ready",
                          .reason = {},
                          .workers = pool_.workers(),
                          .busy_workers = pool_.busy(),
                          .queue_depth = pool_.queue_depth(),
                          .cache_persistent = stats.persistent,
                          .cache_memory_entries = stats.memory_entries,
                          .cache_memory_bytes = stats.memory_bytes,
                          .cache_storage_error = storage_error};
  if (!ready_) {
    report.status = "stopping";
  } else if (stalled > stall_limit) {
    // Every solve has a budget: a pool with work that finished nothing for 3 budgets is wedged.
    report.status = "stalled";
    report.reason = "no solve has finished for " + api::number_text(std::round(stalled)) +
                    " s (the limit is " + api::number_text(stall_limit) + " s) with " +
                    std::to_string(report.busy_workers) + " running and " +
                    std::to_string(report.queue_depth) + " queued";
  } else if (!storage_error.empty()) {
    // Still ready: plans (and min-time answers) are answered correctly (from memory), they are
    // only not kept across a restart. Taking the replica out of rotation would stop a line that
    // one replica serves; the failure is logged, said here and in slosh_cache_store_ok.
    report.status = "degraded";
    report.reason = storage_error;
  }
  bool unready = false;
  if (redis_) add_redis_state(report, *redis_, config_.redis_required, unready);
  Reply r;
  r.status = !unready && (report.status == "ready" || report.status == "degraded") ? 200 : 503;
  r.body = api::ready_body(report);
  return r;
}

Reply PlanService::metrics_text() const {
  Reply r;
  r.content_type = "text/plain; version=0.0.4";
  r.body = metrics_.render(pool_.queue_depth(), pool_.busy(), pool_.workers());
  r.body +=
      "# HELP slosh_cache_store_ok 0 while the plan store cannot be opened or written, else 1.\n"
      "# TYPE slosh_cache_store_ok gauge\n"
      "slosh_cache_store_ok " +
      std::string(store_error().empty() ? "1" : "0") + "\n";
  if (redis_) {
    r.body +=
        "# HELP slosh_redis_up 1 while the shared cache's Redis answers, 0 while it is down or "
        "slow (the replica answers from its local levels); absent without a Redis cache.\n"
        "# TYPE slosh_redis_up gauge\n"
        "slosh_redis_up " +
        std::string(redis_->state().up ? "1" : "0") + "\n";
  }
  r.body +=
      "# HELP slosh_cam_export_bytes Bytes reserved by the cam exports in flight (until their "
      "responses are written).\n"
      "# TYPE slosh_cam_export_bytes gauge\n"
      "slosh_cam_export_bytes " +
      std::to_string(export_budget_.in_flight()) +
      "\n"
      "# HELP slosh_cam_export_budget_bytes The budget of the cam exports in flight "
      "(cam_export_bytes).\n"
      "# TYPE slosh_cam_export_budget_bytes gauge\n"
      "slosh_cam_export_budget_bytes " +
      std::to_string(export_budget_.capacity()) + "\n";
  return r;
}

std::shared_ptr<const CachedValue> PlanService::solve_once_across_replicas(
    const std::string& key, const api::PlanRequest& request, Outcome& outcome,
    std::chrono::steady_clock::time_point started) {
  RedisCache* shared = cache_.shared();
  std::string token;
  if (shared != nullptr) {
    // The lock outlives the solve's budget by a second; a replica that dies holding it delays the
    // others by at most that, never forever.
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
    if (api::is_cacheable(plan.status) && !stopped) stored = cache_.put(key, plan.body);
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

std::string PlanService::cache_description() const {
  std::string text = config_.cache_entries > 0 ? "memory" : "";
  if (const std::string path = local_cache_path(config_); !path.empty()) {
    text += (text.empty() ? "" : " + ") + std::string("sqlite ") + path;
  }
  if (redis_)
    text += (text.empty() ? "" : " + ") + std::string("redis ") + redis_->options().url.display();
  return text.empty() ? "none" : text;
}

void PlanService::begin_shutdown() {
  ready_ = false;
  pool_.stop_accepting();
}

}  // namespace slosh::service
