// A cached plan served from each level of the plan cache (SPEC §13): the in-memory LRU, the local
// SQLite file, and the shared Redis (a real redis-server on loopback, started here like the tests
// do). Two views: PlanCache::get alone (the level's cost: lookup, transfer, digest check), and
// PlanService::post_plan of a cached recipe (what POST /v1/plans costs without HTTP: parse, key,
// lookup, render the reply); and what rendering each kept view of a cached plan costs.

#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <string>

#include "cache/plan_cache.hpp"
#include "cache/rendered_plans.hpp"
#include "fixtures.hpp"
#include "http/plan_service.hpp"
#include "storage/redis_client.hpp"
#include "support/redis_server.hpp"

namespace {

using slosh::service::CacheConfig;
using slosh::service::PlanCache;
using slosh::service::PlanService;
using slosh::service::ServerConfig;

slosh::test::RedisServer& redis() {
  static slosh::test::RedisServer server;
  return server;
}

std::shared_ptr<slosh::service::RedisClient> redis_client() {
  return std::make_shared<slosh::service::RedisClient>(
      slosh::service::RedisOptions{.url = slosh::service::parse_redis_url(redis().url())});
}

/// A real stored plan body (as the cache holds it): solved once.
const std::string& stored_plan() {
  static const std::string body = [] {
    ServerConfig config;
    config.cache_path = "";
    config.workers = 1;
    PlanService service(config);
    const auto reply = service.post_plan(slosh::bench::cached_plan_request(), "");
    return reply.body;
  }();
  return body;
}

std::string sqlite_file() {
  return (std::filesystem::temp_directory_path() / "slosh_bench_cache.sqlite").string();
}

// range(0): 0 = memory, 1 = SQLite, 2 = Redis (the other levels off, so every get reaches it).
void BM_CacheGet(benchmark::State& state) {
  CacheConfig config;
  const auto level = state.range(0);
  if (level != 0) config.memory_entries = 0;
  if (level == 1) config.path = sqlite_file();
  if (level == 2) config.redis = redis_client();
  PlanCache cache(config);
  cache.put("bench-key", stored_plan());
  for (auto _ : state) {
    auto value = cache.get("bench-key");
    if (!value) state.SkipWithError("miss");
    benchmark::DoNotOptimize(value);
  }
  state.SetLabel(level == 0 ? "memory" : level == 1 ? "sqlite" : "redis");
  state.counters["plan_bytes"] = static_cast<double>(stored_plan().size());
  if (level == 1) std::filesystem::remove(sqlite_file());
}
BENCHMARK(BM_CacheGet)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

// POST /v1/plans of a cached recipe without HTTP: range(0) = 0 memory, 2 Redis (memory off).
void BM_CachedPlanReply(benchmark::State& state) {
  ServerConfig config;
  config.workers = 1;
  config.cache_path = state.range(0) == 2 ? redis().url() : "";
  if (state.range(0) == 2) config.cache_entries = 0;
  PlanService service(config);
  slosh::bench::cached_serve_loop(state, service);
  state.SetLabel(state.range(0) == 2 ? "redis" : "memory");
}
BENCHMARK(BM_CachedPlanReply)->Arg(0)->Arg(2)->Unit(benchmark::kMicrosecond);

// What one rendering of a cached plan costs, made on a fresh entry each time (what the worker
// renders after a solve, or the first hit that asks for it): range(0) = 0 the compact view,
// 1 the full plan's gzip bytes, 2 the compact view's gzip bytes (its compact view made first,
// outside the timing).
void BM_RenderPlanView(benchmark::State& state) {
  const auto which = state.range(0);
  PlanCache cache(CacheConfig{});
  const auto view = which == 1 ? slosh::api::PlanView::kFull : slosh::api::PlanView::kCompact;
  for (auto _ : state) {
    state.PauseTiming();
    const auto plan = cache.put("bench-key", stored_plan());
    if (which == 2) slosh::service::prepare_hit_body(cache, plan, view, false);
    state.ResumeTiming();
    slosh::service::prepare_hit_body(cache, plan, view, which != 0);
  }
  state.SetLabel(which == 0 ? "compact" : which == 1 ? "full gzip" : "compact gzip");
}
BENCHMARK(BM_RenderPlanView)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
