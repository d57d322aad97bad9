// The short benchmark set of `make bench-check` (scripts/bench-check.sh): one whole plan() of each
// strategy (without its robustness report), the report, one response of each model and the cached
// serve path, plus the calibration loop every figure is divided by (bench/bench_check.py compares
// the quotients with bench/budgets.tsv). Single-threaded; names are the budget file's keys.

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "fixtures.hpp"
#include "http/plan_service.hpp"

namespace {

using slosh::PlanOptions;
using slosh::Strategy;

// A fixed, deterministic floating-point workload of a dependent chain of multiplies, adds and
// square roots (the kind of work the numerics do), independent of slosh's code: what a
// benchmark costs is measured in multiples of it, so a slower or busier machine scales both.
double calibration_workload() {
  double x = 0.3;
  double sum = 0.0;
  for (int i = 0; i < 200000; ++i) {
    x = 3.9 * x * (1.0 - x);  // the logistic map: chaotic, never constant-folded
    sum += std::sqrt(x + 1.0);
  }
  return sum;
}

void BM_Calibration(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(calibration_workload());
}

// Without its robustness report: the report has its own row, and inside every plan it cost more
// than most solvers, so a 3x budget on a plan barely saw a solver regression.
void BM_Plan(benchmark::State& state, Strategy strategy) {
  PlanOptions options;
  options.robustness = false;
  slosh::bench::plan_loop(state, strategy, options);
}

void BM_RobustnessReport(benchmark::State& state) {
  slosh::bench::robustness_report_loop(state, Strategy::kNotch);
}

// The full plan, the compact view, and the full plan's stored gzip bytes, from the memory cache.
void BM_CachedServe(benchmark::State& state, const char* view, bool gzip) {
  slosh::service::ServerConfig config;
  config.cache_path = "";  // memory only
  config.workers = 1;
  slosh::service::PlanService service(config);
  const std::vector<std::string> views =
      view[0] == '\0' ? std::vector<std::string>{} : std::vector<std::string>{view};
  slosh::bench::cached_serve_loop(state, service, views, gzip);
}

void register_all() {
  benchmark::RegisterBenchmark("calibration", BM_Calibration)->Unit(benchmark::kMicrosecond);
  for (const Strategy s : {Strategy::kBaseline, Strategy::kNotch, Strategy::kMultiNotch,
                           Strategy::kMinJerkBand, Strategy::kTimeDomain, Strategy::kAuto,
                           Strategy::kFirChain, Strategy::kShaper, Strategy::kIir}) {
    benchmark::RegisterBenchmark(("plan/" + slosh::to_string(s)).c_str(), BM_Plan, s)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("robustness_report", BM_RobustnessReport)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("response/nonlinear",
                               slosh::bench::response_peaks_loop<slosh::NonlinearResponse>)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("response/linear",
                               slosh::bench::response_peaks_loop<slosh::LinearResponse>)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("serve/cached_full", BM_CachedServe, "", false)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("serve/cached_compact", BM_CachedServe, "compact", false)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("serve/cached_full_gzip", BM_CachedServe, "", true)
      ->Unit(benchmark::kMicrosecond);
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
