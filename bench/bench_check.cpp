// The short benchmark set of `make bench-check` (scripts/bench-check.sh): one whole plan() of each
// strategy, the robustness report, one response of each model and the cached serve path, plus the
// calibration loop every figure is divided by (bench/bench_check.py compares the quotients with
// bench/budgets.tsv). Single-threaded; names are the budget file's keys.

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "plan_service.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "slosh/core/strategy/robustness.hpp"

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

void BM_Plan(benchmark::State& state, Strategy strategy) {
  const slosh::Format format = slosh::thesis_format();
  const PlanOptions options;
  for (auto _ : state) benchmark::DoNotOptimize(slosh::plan(format, strategy, options));
}

void BM_RobustnessReport(benchmark::State& state) {
  const slosh::Format format = slosh::thesis_format();
  PlanOptions options;
  options.robustness = false;
  const slosh::PlanResult r = slosh::plan(format, Strategy::kNotch, options);
  slosh::RobustnessSweep sweep;
  sweep.zeta = r.model.zeta;
  sweep.eta_rest_max = options.eta_rest_max;
  for (auto _ : state) benchmark::DoNotOptimize(slosh::robustness_report(r.model, r.law, sweep));
}

// An asymmetric admissible set of durations summing to 1 s (as bench_core).
const slosh::Durations kAsymmetric{0.08, 0.17, 0.06, 0.21, 0.12, 0.09, 0.27};

void BM_NonlinearResponse(benchmark::State& state) {
  const slosh::SloshingModel model = slosh::make_sloshing_model(slosh::thesis_format(), {});
  const slosh::SevenSegmentLaw law(kAsymmetric, 0.8);
  for (auto _ : state) {
    const slosh::NonlinearResponse r(model, law.law(), 1.0);
    benchmark::DoNotOptimize(r.peaks());
  }
}

void BM_LinearResponse(benchmark::State& state) {
  const slosh::SloshingModel model = slosh::make_sloshing_model(slosh::thesis_format(), {});
  const slosh::SevenSegmentLaw law(kAsymmetric, 0.8);
  for (auto _ : state) {
    const slosh::LinearResponse r(model, law.law(), 1.0);
    benchmark::DoNotOptimize(r.peaks());
  }
}

// POST /v1/plans of a cached recipe without HTTP (parse, key, lookup, reply): the full plan, the
// compact view, and the full plan's stored gzip bytes.
void BM_CachedServe(benchmark::State& state, const char* view, bool gzip) {
  slosh::service::ServerConfig config;
  config.cache_path = "";  // memory only
  config.workers = 1;
  slosh::service::PlanService service(config);
  const std::string body =
      R"({"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82, "fluid": "water",)"
      R"( "stroke_mm": 800, "motion_time_s": 1.0}, "strategy": "multi_notch"})";
  const std::vector<std::string> views =
      view[0] == '\0' ? std::vector<std::string>{} : std::vector<std::string>{view};
  if (service.post_plan(body, "", views, gzip).status != 200) {
    state.SkipWithError("the plan was not solved");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(service.post_plan(body, "", views, gzip));
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
  benchmark::RegisterBenchmark("response/nonlinear", BM_NonlinearResponse)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("response/linear", BM_LinearResponse)->Unit(benchmark::kMicrosecond);
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
