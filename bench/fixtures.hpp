#pragma once
// The benchmark bodies more than one benchmark binary measures: a whole plan(), the robustness
// report, one response of each model and the cached serve path, all on the thesis format
// (R = 48.5 mm, h = 82 mm, water, s = 800 mm, T = 1 s). The guard of `make bench-check`
// (bench_check.cpp) runs the same bodies as bench_core, bench_planner and bench_cache, so a figure
// of the guard and one of the README measure the same thing.

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "slosh/core/strategy/robustness.hpp"

// The serve path is there only for the binaries linked with slosh::service (its headers are on
// their include path): bench_core and bench_planner link the numerics alone.
#if __has_include("http/plan_service.hpp")
#include <nlohmann/json.hpp>

#include "http/plan_service.hpp"
#define SLOSH_BENCH_HAS_SERVICE 1
#endif

namespace slosh::bench {

/// An asymmetric admissible set of durations summing to 1 s [s].
inline const Durations kAsymmetric{0.08, 0.17, 0.06, 0.21, 0.12, 0.09, 0.27};

/// The whole plan() of `strategy` on the thesis format, once per iteration; returns the last
/// plan's nonlinear eta_rest [m].
inline double plan_loop(benchmark::State& state, Strategy strategy, const PlanOptions& options) {
  const Format format = thesis_format();
  double rest = 0.0;
  for (auto _ : state) {
    const PlanResult r = plan(format, strategy, options);
    rest = r.prediction.nonlinear.rest.value;
    benchmark::DoNotOptimize(r);
  }
  return rest;
}

/// The robustness report of SPEC §10 alone for the law `strategy` plans on the thesis format
/// (planned once, without its own report, outside the timing).
inline void robustness_report_loop(benchmark::State& state, Strategy strategy) {
  const Format format = thesis_format();
  PlanOptions options;
  options.robustness = false;
  const PlanResult r = plan(format, strategy, options);
  RobustnessSweep sweep;
  sweep.zeta = r.model.zeta;
  sweep.eta_rest_max = options.eta_rest_max;
  for (auto _ : state) benchmark::DoNotOptimize(robustness_report(r.model, r.law, sweep));
}

/// Builds the response of `Response` (LinearResponse or NonlinearResponse) to the asymmetric
/// 7-segment law (stroke 0.8 m) on the thesis model and takes its peaks, once per iteration.
template <typename Response>
void response_peaks_loop(benchmark::State& state) {
  const SloshingModel model = make_sloshing_model(thesis_format(), {});
  const SevenSegmentLaw law(kAsymmetric, 0.8);
  for (auto _ : state) {
    const Response r(model, law.law(), 1.0);
    benchmark::DoNotOptimize(r.peaks());
  }
}

#ifdef SLOSH_BENCH_HAS_SERVICE
/// The request of the cached-serve benchmarks: multi_notch on the thesis format.
inline const std::string& cached_plan_request() {
  static const std::string body =
      nlohmann::json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "strategy": "multi_notch"})")
          .dump();
  return body;
}

/// POST /v1/plans of a cached recipe without HTTP (parse, key, lookup, reply) on `service`, with
/// `views` and the stored gzip bytes when `gzip`: solved and stored once before the timing; a
/// reply that is not a 200 from the cache ends the benchmark with an error (a solve would be
/// timed instead).
inline void cached_serve_loop(benchmark::State& state, service::PlanService& service,
                              const std::vector<std::string>& views = {}, bool gzip = false) {
  if (service.post_plan(cached_plan_request(), "", views, gzip).status != 200) {
    state.SkipWithError("the plan was not solved");
    return;
  }
  for (auto _ : state) {
    const auto reply = service.post_plan(cached_plan_request(), "", views, gzip);
    if (reply.status != 200 || !reply.plan || !reply.plan->cached)
      state.SkipWithError("not cached");
    benchmark::DoNotOptimize(reply);
  }
}
#endif

}  // namespace slosh::bench
