// Where the time of one plan goes: the phases of plan() for one strategy on the thesis format
// (R = 48.5 mm, h = 82 mm, water, s = 800 mm, T = 1 s), each timed alone the way plan() runs it,
// next to the whole plan() and its rendering to the JSON the service caches. The phases' sum is
// close to BM_PlanPhase/plan (the rest is validation, the model and the message).
//
//   build/bench/bench_phases --benchmark_filter='BM_PlanPhase/' --benchmark_repetitions=3
//
// Arg: 0 the whole plan(), 1 baseline (the uniform law's prediction: kinematics, linear and
// nonlinear peaks), 2 references (set_design and set_references: the design band and X_ref),
// 3 solve (the strategy's optimisation, all starts), 4 verification (the planned law's
// prediction), 5 report (the robustness report of SPEC §10, 21 points x 2 models), 6 rendering
// (api::plan_json of the plan, dumped to text). The strategy is notch unless --phase_strategy
// names another (baseline, notch, multi_notch, min_jerk_band, time_domain).

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "slosh/api/plan.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "slosh/core/strategy/robustness.hpp"
#include "strategy/strategies.hpp"
#include "strategy_context.hpp"

namespace {

using slosh::PlanOptions;
using slosh::Strategy;

Strategy g_strategy = Strategy::kNotch;

const char* const kPhaseNames[] = {"plan",         "baseline", "references", "solve",
                                   "verification", "report",   "rendering"};

/// The prediction plan() makes of a law (kinematics, then both models' peaks), as plan() makes
/// it: the nonlinear peaks without keeping the trajectory (nothing after the verdict needs it).
slosh::LawPrediction predict(const slosh::SloshingModel& model, const slosh::MotionLaw& law,
                             double rest_time) {
  slosh::LawPrediction p;
  p.kinematics = law.summary();
  p.linear = slosh::LinearResponse(model, law, rest_time).peaks();
  p.nonlinear = slosh::nonlinear_peaks(model, law, rest_time);
  return p;
}

/// The context plan() builds before it solves, and one plan to verify, report and render.
struct Setup : slosh::bench::StrategyContextFixture {
  slosh::MotionLaw uniform =
      slosh::SevenSegmentLaw(slosh::uniform_durations(format.motion_time), format.stroke).law();
  slosh::LawPrediction baseline = predict(model, uniform, options.rest_time);
  slosh::PlanResult plan = slosh::plan(format, g_strategy, options);
  Setup() {
    slosh::detail::set_design(context);
    slosh::detail::set_references(context, baseline.nonlinear.motion.value);
    context.uniform_prediction = &baseline;
  }
};

slosh::detail::StrategyOutcome solve(Setup& s) {
  switch (g_strategy) {
    case Strategy::kMultiNotch:
      return slosh::detail::solve_multi_notch(s.context);
    case Strategy::kMinJerkBand:
      return slosh::detail::solve_min_jerk_band(s.context);
    case Strategy::kTimeDomain: {
      const std::vector<slosh::Durations> seeds{
          slosh::detail::solve_notch(s.context).durations,
          slosh::detail::solve_multi_notch(s.context).durations,
          slosh::detail::solve_min_jerk_band(s.context).durations};
      return slosh::detail::solve_time_domain(s.context, seeds);
    }
    default:
      return slosh::detail::solve_notch(s.context);
  }
}

void BM_PlanPhase(benchmark::State& state) {
  Setup s;
  const auto phase = state.range(0);
  slosh::api::PlanRequest request;
  request.format = s.format;
  request.strategy = g_strategy;
  request.options = s.options;
  for (auto _ : state) {
    switch (phase) {
      case 0:
        benchmark::DoNotOptimize(slosh::plan(s.format, g_strategy, s.options));
        break;
      case 1:
        benchmark::DoNotOptimize(predict(s.model, s.uniform, s.options.rest_time));
        break;
      case 2: {
        slosh::detail::StrategyContext c{s.format, s.options, s.model,
                                         slosh::detail::DurationSpace(s.format, s.options),
                                         s.deadline};
        slosh::detail::set_design(c);
        slosh::detail::set_references(c, s.baseline.nonlinear.motion.value);
        benchmark::DoNotOptimize(c.x_ref);
        break;
      }
      case 3:
        if (g_strategy == Strategy::kBaseline) break;
        benchmark::DoNotOptimize(solve(s));
        break;
      case 4:
        benchmark::DoNotOptimize(predict(s.model, s.plan.law, s.options.rest_time));
        break;
      case 5:
        benchmark::DoNotOptimize(slosh::robustness_of(s.format, s.options, s.plan));
        break;
      default:
        benchmark::DoNotOptimize(slosh::api::plan_json(request, s.plan).dump());
        break;
    }
  }
  state.SetLabel(std::string(slosh::to_string(g_strategy)) + " " + kPhaseNames[phase]);
}
BENCHMARK(BM_PlanPhase)->DenseRange(0, 6)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  // --phase_strategy=NAME (removed before Google Benchmark reads the rest).
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    constexpr const char* kFlag = "--phase_strategy=";
    if (std::strncmp(argv[i], kFlag, std::strlen(kFlag)) == 0) {
      const std::string name = argv[i] + std::strlen(kFlag);
      bool known = false;
      for (int k = 0; k <= static_cast<int>(Strategy::kTimeDomain); ++k) {
        if (slosh::to_string(static_cast<Strategy>(k)) == name) {
          g_strategy = static_cast<Strategy>(k);
          known = true;
        }
      }
      if (!known) {
        std::fprintf(stderr,
                     "bench_phases: --phase_strategy = '%s' is not one of baseline, notch, "
                     "multi_notch, min_jerk_band, time_domain\n",
                     name.c_str());
        return 2;
      }
      continue;
    }
    args.push_back(argv[i]);
  }
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
