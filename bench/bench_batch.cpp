// A 1 000-recipe batch of distinct formats through the batch engine of `slosh batch` and
// POST /v1/plans/batch (PlanService::start_batch: parse, key, cache lookup, solve on the worker
// pool, render), from a cold memory-only cache, with 1 and 2 workers (SPEC §8: scales with the
// worker count). Strategies cycle notch / multi_notch / min_jerk_band.

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include <nlohmann/json.hpp>

#include "http/plan_service.hpp"

namespace {

using nlohmann::json;

constexpr std::size_t kRecipes = 1000;

std::vector<json> distinct_recipes() {
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> radius(30.0, 60.0), fill(50.0, 120.0),
      stroke(300.0, 900.0), motion_time(0.8, 1.4);
  const char* strategies[] = {"notch", "multi_notch", "min_jerk_band"};
  std::vector<json> recipes;
  recipes.reserve(kRecipes);
  for (std::size_t i = 0; i < kRecipes; ++i) {
    recipes.push_back({{"format",
                        {{"container", {{"radius_mm", radius(rng)}}},
                         {"fill_height_mm", fill(rng)},
                         {"fluid", "water"},
                         {"stroke_mm", stroke(rng)},
                         {"motion_time_s", motion_time(rng)}}},
                       {"strategy", strategies[i % 3]}});
  }
  return recipes;
}

void BM_Batch1000(benchmark::State& state) {
  const std::vector<json> recipes = distinct_recipes();
  slosh::service::ServerConfig config;
  config.workers = static_cast<std::size_t>(state.range(0));
  config.queue = kRecipes;
  config.cache_path = "";  // memory only, cold for every iteration
  std::size_t failed = 0;
  for (auto _ : state) {
    slosh::service::PlanService service(config);
    const slosh::service::PendingBatch batch = service.start_batch(
        slosh::api::read_batch_items(recipes, service.engine().config().solve_budget_s));
    for (std::size_t i = 0; i < batch.size(); ++i) {
      if (!batch.get(i).ok()) ++failed;
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kRecipes));
  state.counters["failed"] = static_cast<double>(failed);
}
BENCHMARK(BM_Batch1000)
    ->ArgName("workers")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
