// PlanEngine's min-time searches (SPEC §9): one pool task per strategy, single flight per request
// key, the answer assembled and cached by the last task to finish.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <utility>

#include "engine/engine_errors.hpp"
#include "engine/plan_engine.hpp"
#include "http/client_wait.hpp"
#include "slosh/api/format_json.hpp"

namespace slosh::service {

// A min-time search in flight: the request, one result slot per strategy, and the promise kept
// by the last task to finish.
struct PlanEngine::MinTimeSearch {
  api::MinTimeRequest request;
  std::string key;
  std::string flight_name;  // its single-flight entry (flight_name of key and budget)
  std::uint64_t flight{};
  std::vector<MinTimeResult> results;
  // Pool tasks of the search: task i searches strategies i, i + tasks, i + 2 tasks, ...
  std::size_t tasks{1};
  // Tasks not finished, plus one held by the queueing thread until it has queued them all.
  std::atomic<std::size_t> remaining{0};
  // A task could not be queued: the 503 is published and the queued tasks skip their strategy.
  std::atomic<bool> refused{false};
  // A task was still queued when shutdown began: the search answers 503, as queued plan solves do.
  std::atomic<bool> shut_down{false};
  // Counted in slosh_min_time_searches_total (by its first strategy that runs).
  std::atomic<bool> counted{false};
  std::promise<Outcome> promise;
  // Who waits; its stop flag ends every strategy's search between two plans.
  std::shared_ptr<FlightWaiters> waiters{std::make_shared<FlightWaiters>()};
};

void PlanEngine::leave_min_time(const PendingMinTime& pending, bool gone, bool timed_out) {
  if (leave_flight(min_time_inflight_, pending.flight, pending.waiters, gone || timed_out)) {
    ++(timed_out ? timed_out_min_times_ : cancelled_min_times_);
  }
}

bool PlanEngine::join_or_add_search(PendingMinTime& pending,
                                    const std::shared_ptr<MinTimeSearch>& search, double budget,
                                    bool cancellable) {
  // Single flight, as for plans: a request joins a running search of its key with its budget
  // (flight_name). The lock covers only the map.
  pending.flight = flight_name(pending.key, budget);
  const std::lock_guard lock(inflight_mutex_);
  if (auto it = min_time_inflight_.find(pending.flight); it != min_time_inflight_.end()) {
    metrics_.count_min_time_join();
    pending.search = it->second.future;
    join_locked(*it->second.waiters, cancellable);
    if (cancellable) pending.waiters = it->second.waiters;
    return true;
  }
  if (ready_) {
    search->flight = ++flights_;
    join_locked(*search->waiters, cancellable);
    min_time_inflight_[pending.flight] =
        Flight{pending.search, budget, search->flight, search->waiters};
    if (cancellable) pending.waiters = search->waiters;
  }
  return false;
}

PendingMinTime PlanEngine::start_min_time(const api::MinTimeRequest& request, bool wait_for_room,
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
  if (join_or_add_search(pending, search, request.options.plan.time_limit, cancellable)) {
    return pending;
  }
  if (search->flight == 0) {  // shutting down
    search->promise.set_value(Outcome{{}, overloaded_error()});
    return pending;
  }
  // A search of this key may have finished (cached, then forgotten) since the lookup above.
  if (auto hit = min_time_cache_.get(pending.key, &level)) {
    forget_flight(min_time_inflight_, pending.flight, search->flight);
    search->promise.set_value(Outcome{*hit, std::nullopt});  // for whoever joined meanwhile
    metrics_.count_cache_hit(level);
    pending.cached = std::move(hit);
    pending.search = {};
    pending.waiters.reset();
    return pending;
  }
  search->request = request;
  search->key = pending.key;
  search->flight_name = pending.flight;
  search->results.resize(request.strategies.size());
  queue_min_time_tasks(search, wait_for_room);
  return pending;
}

std::size_t PlanEngine::min_time_tasks(std::size_t strategies) const {
  return std::max<std::size_t>(1, std::min(strategies, pool_.workers() + pool_.capacity()));
}

void PlanEngine::queue_min_time_tasks(const std::shared_ptr<MinTimeSearch>& search,
                                      bool wait_for_room) {
  // One task per strategy, but never more than an idle pool admits (workers + queue): a search
  // of more strategies runs some of them one after the other instead of being refused forever
  // with an "all workers are busy" that no retry can cure.
  const std::size_t n = min_time_tasks(search->results.size());
  search->tasks = n;
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
      forget_flight(min_time_inflight_, search->flight_name, search->flight);
      search->promise.set_value(Outcome{{}, overloaded_error()});
      search->remaining -= n - i + 1;
      return;
    }
  }
  metrics_.count_cache_miss();
  if (search->remaining.fetch_sub(1) == 1) finish_min_time(*search);
}

void PlanEngine::run_min_time_task(const std::shared_ptr<MinTimeSearch>& search, std::size_t i) {
  for (std::size_t s = i; s < search->results.size() && !search->refused; s += search->tasks) {
    run_min_time_strategy(*search, s);
  }
  if (search->remaining.fetch_sub(1) == 1) finish_min_time(*search);
}

void PlanEngine::run_min_time_strategy(MinTimeSearch& search, std::size_t i) {
  const api::MinTimeRequest& request = search.request;
  MinTimeResult& slot = search.results[i];
  const auto started = std::chrono::steady_clock::now();
  slot.strategy = request.strategies[i];
  if (!ready_) {
    // Shutting down: not searched; the search answers the shutdown's 503 (finish_min_time).
    search.shut_down = true;
  } else if (search.waiters->stop) {
    slot.status = SolveStatus::kTimeLimit;  // nobody waits: not searched (and not cached)
    slot.message = "not searched: every client waiting for it closed the connection";
  } else {
    // A search is counted (and each strategy timed) when it runs: one skipped while queued because
    // its clients left is counted in the cancellations only, as a skipped plan solve is.
    if (!search.counted.exchange(true)) metrics_.count_min_time_search();
    try {
      MinTimeOptions options = request.options;
      options.plan.stop = &search.waiters->stop;
      slot = min_time(request.format, request.strategies[i], options);
    } catch (...) {
      slot = MinTimeResult{};
      slot.strategy = request.strategies[i];
      slot.status = SolveStatus::kFailed;
      slot.message = "the search failed";
    }
    metrics_.observe_solve(
        "min_time:" + to_string(request.strategies[i]),
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  }
}

void PlanEngine::finish_min_time(MinTimeSearch& search) {
  if (search.refused) return;  // its refusal has been published
  Outcome outcome;
  try {
    // Stopped by begin_shutdown (not by its clients): the shutdown's refusal.
    if (search.shut_down || (search.waiters->stop && !ready_)) throw overloaded_error();
    if (search.waiters->stop) throw cancelled_error();
    api::check_min_time_inputs(search.request, search.results);
    outcome.body = api::stored_min_time(search.request, search.results, search.key);
    // Cached before the flight is forgotten: a new request finds one or the other.
    outcome.partial = !api::is_min_time_cacheable(search.results);
    if (!outcome.partial) min_time_cache_.put(search.key, outcome.body);
  } catch (const api::ApiError& e) {
    outcome.error = e;
  } catch (const std::exception& e) {
    outcome.error = api::ApiError(api::ErrorCode::kInternal, "", e.what());
  } catch (...) {
    outcome.error = api::ApiError(api::ErrorCode::kInternal, "",
                                  "the min-time answer failed with an unknown error");
  }
  forget_flight(min_time_inflight_, search.flight_name, search.flight);
  search.promise.set_value(std::move(outcome));
}

MinTimeAnswer PlanEngine::answer_min_time(const api::MinTimeRequest& request,
                                          const std::function<bool()>& abandoned) {
  const PendingMinTime pending = start_min_time(request, false, static_cast<bool>(abandoned));
  if (pending.cached) return MinTimeAnswer{pending.key, *pending.cached, true};
  // A task that searches several strategies one after the other (min_time_tasks) has a budget
  // for each of them.
  const std::size_t n = request.strategies.size();
  const std::size_t tasks = min_time_tasks(n);
  const double budget =
      request.options.plan.time_limit * static_cast<double>((n + tasks - 1) / tasks);
  const WaitEnd end =
      wait_for_client(pending.search, after(budget + config_.queue_wait_s), abandoned);
  leave_min_time(pending, end == WaitEnd::kGone, end == WaitEnd::kTimeout);  // a 504 waits no more
  if (end == WaitEnd::kGone) throw cancelled_error();
  if (end == WaitEnd::kTimeout) {
    throw api::ApiError(api::ErrorCode::kTimeout, "",
                        "the min-time search did not finish within its budget of " +
                            api::number_text(budget) + " s plus " +
                            api::number_text(config_.queue_wait_s) + " s of queueing");
  }
  const Outcome& outcome = pending.search.get();
  if (outcome.error) throw *outcome.error;
  // A request that joined another's search answers as that one did: a miss, the same body.
  return MinTimeAnswer{pending.key, outcome.body, false, outcome.partial};
}

}  // namespace slosh::service
