// The strategies on the thesis format (R = 48.5 mm, h = 82 mm, water, s = 800 mm, T = 1 s).
// BM_Optimise_*: the optimisation alone, all starts included (the SPEC §8 targets);
// BM_Plan_*: the whole plan() call, i.e. plus the dense verification of the plan and of the
// uniform baseline with both models (about 0.5 ms) and, for time_domain, its spectral seeds.

#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "fixtures.hpp"
#include "response/nonlinear_sensitivity.hpp"
#include "response/planar_sensitivity.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "slosh/core/strategy/min_time.hpp"
#include "slosh/core/strategy/path_plan.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "strategy/strategies.hpp"
#include "strategy_context.hpp"

namespace {

using slosh::PlanOptions;
using slosh::Strategy;

// The context plan() builds, for calling one strategy directly.
struct Setup : slosh::bench::StrategyContextFixture {
  explicit Setup(slosh::SolverChoice solver = slosh::SolverChoice::kAuto) {
    options.solver = solver;
    const auto uniform = slosh::uniform_durations(format.motion_time);
    const slosh::SevenSegmentLaw law(uniform, 0.8);
    slosh::detail::set_design(context);
    slosh::detail::set_references(
        context, slosh::NonlinearResponse(model, law.law(), 1.0).peaks().motion.value);
  }
};

template <typename F>
void run(benchmark::State& state, F solve) {
  double objective = 0.0;
  int evaluations = 0;
  for (auto _ : state) {
    const slosh::detail::StrategyOutcome o = solve();
    objective = o.objective;
    evaluations = o.evaluations;
    benchmark::DoNotOptimize(o);
  }
  state.counters["objective"] = objective;
  state.counters["evaluations"] = evaluations;
}

void BM_Optimise_Notch(benchmark::State& state) {
  Setup s(static_cast<slosh::SolverChoice>(state.range(0)));
  run(state, [&] { return slosh::detail::solve_notch(s.context); });
}
void BM_Optimise_MultiNotch(benchmark::State& state) {
  Setup s(static_cast<slosh::SolverChoice>(state.range(0)));
  run(state, [&] { return slosh::detail::solve_multi_notch(s.context); });
}
void BM_Optimise_MinJerkBand(benchmark::State& state) {
  Setup s(static_cast<slosh::SolverChoice>(state.range(0)));
  run(state, [&] { return slosh::detail::solve_min_jerk_band(s.context); });
}
void BM_Optimise_TimeDomain(benchmark::State& state) {
  Setup s(static_cast<slosh::SolverChoice>(state.range(0)));
  // Seeds: the spectral optima, as plan() passes them.
  std::vector<slosh::Durations> seeds{slosh::detail::solve_notch(s.context).durations,
                                      slosh::detail::solve_multi_notch(s.context).durations,
                                      slosh::detail::solve_min_jerk_band(s.context).durations};
  run(state, [&] { return slosh::detail::solve_time_domain(s.context, seeds); });
}
// Arg 1 = NLopt SLSQP (the default), 2 = Ipopt.
BENCHMARK(BM_Optimise_Notch)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Optimise_MultiNotch)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Optimise_MinJerkBand)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Optimise_TimeDomain)->Arg(1)->Unit(benchmark::kMillisecond);

// One evaluation of time_domain's response with its gradient (the uniform law on the thesis
// format, 20 steps per period, 1 s of rest): what each SLSQP evaluation integrates per model.
void BM_NonlinearSensitivity(benchmark::State& state) {
  Setup s;
  slosh::NonlinearOptions o;
  o.steps_per_period = 20.0;
  slosh::detail::NonlinearSensitivity sens(s.model, 0.8, 1.0, o);
  const auto d = slosh::uniform_durations(s.format.motion_time);
  sens.freeze_steps(d.data());
  for (auto _ : state) {
    sens.compute(d.data());
    benchmark::DoNotOptimize(sens.motion_time());
  }
}
BENCHMARK(BM_NonlinearSensitivity)->Unit(benchmark::kMicrosecond);

void BM_Plan(benchmark::State& state) {
  const auto strategy = static_cast<Strategy>(state.range(0));
  const double rest = slosh::bench::plan_loop(state, strategy, PlanOptions{});
  state.SetLabel(slosh::to_string(strategy));
  state.counters["eta_rest_mm"] = rest * 1e3;
}
// 0 baseline, 1 notch, 2 multi_notch, 3 min_jerk_band, 4 time_domain, 5 fir_chain, 6 shaper,
// 7 iir, 8 auto.
BENCHMARK(BM_Plan)->DenseRange(0, 8)->Unit(benchmark::kMillisecond);

// The whole plan() over 8 seeded formats (R 30-100 mm, fill 0.4-2.5 R, stroke 0.2-1 m, T 0.6-1.6
// s: the property tests' ranges), one after the other: the thesis format alone can flatter a
// change of the search path; counter: the summed solver evaluations.
void BM_PlanFormats(benchmark::State& state) {
  const auto strategy = static_cast<Strategy>(state.range(0));
  std::mt19937 rng(20261126);
  auto draw = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  std::vector<slosh::Format> formats;
  for (int k = 0; k < 8; ++k) {
    slosh::Format f;
    f.container.radius = draw(0.03, 0.1);
    f.fill_height = draw(0.4, 2.5) * f.container.radius;
    f.stroke = draw(0.2, 1.0);
    f.motion_time = draw(0.6, 1.6);
    formats.push_back(f);
  }
  PlanOptions options;
  options.robustness = false;
  int evaluations = 0;
  for (auto _ : state) {
    evaluations = 0;
    for (const slosh::Format& f : formats) {
      const slosh::PlanResult r = slosh::plan(f, strategy, options);
      evaluations += r.solver.iterations;
      benchmark::DoNotOptimize(r);
    }
  }
  state.SetLabel(slosh::to_string(strategy));
  state.counters["evaluations"] = evaluations;
}
BENCHMARK(BM_PlanFormats)->DenseRange(1, 4)->Arg(8)->Unit(benchmark::kMillisecond);

// The robustness report of SPEC §10 alone (21 frequency errors in +-10 %, both models, the
// delta = 0 point simulated too) for the law of each strategy on the thesis format.
void BM_RobustnessReport(benchmark::State& state) {
  const auto strategy = static_cast<Strategy>(state.range(0));
  slosh::bench::robustness_report_loop(state, strategy);
  state.SetLabel(slosh::to_string(strategy));
}
BENCHMARK(BM_RobustnessReport)->Arg(0)->Arg(4)->Arg(6)->Unit(benchmark::kMillisecond);

// A robust plan: time_domain over +-5 % and +-10 % of omega (5 sample models, verified on the
// 21-point grid), and auto judged by the worst case over +-5 %.
void BM_RobustPlan(benchmark::State& state) {
  const auto strategy = static_cast<Strategy>(state.range(0));
  PlanOptions options;
  options.uncertainty.omega_error = static_cast<double>(state.range(1)) / 100.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(slosh::plan(slosh::thesis_format(), strategy, options));
  }
  state.SetLabel(slosh::to_string(strategy) + " +-" + std::to_string(state.range(1)) + " %");
}
BENCHMARK(BM_RobustPlan)->Args({4, 5})->Args({4, 10})->Args({8, 5})->Unit(benchmark::kMillisecond);

// The filtering designs alone (closed forms; no verification).
void BM_Design(benchmark::State& state) {
  Setup s;
  const auto strategy = static_cast<Strategy>(state.range(0));
  for (auto _ : state) {
    slosh::detail::FilterOutcome o =
        strategy == Strategy::kFirChain ? slosh::detail::design_fir_chain(s.context)
        : strategy == Strategy::kShaper ? slosh::detail::design_shaper(s.context)
                                        : slosh::detail::design_iir(s.context);
    benchmark::DoNotOptimize(o);
  }
  state.SetLabel(slosh::to_string(strategy));
}
BENCHMARK(BM_Design)
    ->Arg(static_cast<int>(Strategy::kFirChain))
    ->Arg(static_cast<int>(Strategy::kShaper))
    ->Arg(static_cast<int>(Strategy::kIir))
    ->Unit(benchmark::kMicrosecond);

// X_a(omega) of a general law at one frequency: the shaped poly5 law (a few cubic pieces) and
// the IIR law (1000 linear pieces); the plan response evaluates 512 of them.
void BM_GeneralLawSpectrum(benchmark::State& state) {
  Setup s;
  const slosh::MotionLaw law = state.range(0) == 0 ? slosh::detail::design_shaper(s.context).law
                                                   : slosh::detail::design_iir(s.context).law;
  const double w = s.model.omega1();
  for (auto _ : state) benchmark::DoNotOptimize(slosh::acceleration_spectrum(law, w));
  state.SetLabel(state.range(0) == 0 ? "shaper" : "iir");
  state.counters["pieces"] = static_cast<double>(law.pieces().size());
}
BENCHMARK(BM_GeneralLawSpectrum)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

// The whole minimum-time search of one strategy (SPEC §8/§9) on the thesis format: R 48.5 mm,
// fill 82 mm, height 150 mm (eta_motion <= the free board, 68 mm), water, stroke
// 800 mm, eta_rest <= 3 mm on the nonlinear model; counters: plans solved and T_min.
void BM_MinTime(benchmark::State& state) {
  slosh::Format f = slosh::thesis_format();
  f.container.height = 0.150;
  const auto strategy = static_cast<slosh::Strategy>(state.range(0));
  slosh::MinTimeOptions o;
  o.free_board_margin = 0.0;
  o.plan.time_limit = 60.0;
  slosh::MinTimeResult r;
  for (auto _ : state) {
    r = slosh::min_time(f, strategy, o);
    benchmark::DoNotOptimize(r.t_min);
  }
  state.SetLabel(slosh::to_string(strategy) + " " + slosh::to_string(r.status));
  state.counters["plans"] = r.plans;
  state.counters["t_min_ms"] = r.t_min ? *r.t_min * 1e3 : -1.0;
}
BENCHMARK(BM_MinTime)->DenseRange(0, 6)->Unit(benchmark::kMillisecond);

// The minimum-time search over 6 seeded formats (the ranges of BM_PlanFormats, a container
// 1.5 R above the fill so that eta_motion is bounded by its free board), one after the other: the
// thesis container alone can flatter a change of the search path (which local optimum a plan
// near T_min reaches decides its T_min); counters: the plans solved and the summed T_min.
void BM_MinTimeFormats(benchmark::State& state) {
  const auto strategy = static_cast<slosh::Strategy>(state.range(0));
  std::mt19937 rng(20261127);
  auto draw = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  std::vector<slosh::Format> formats;
  for (int k = 0; k < 6; ++k) {
    slosh::Format f;
    f.container.radius = draw(0.03, 0.1);
    f.fill_height = draw(0.4, 2.5) * f.container.radius;
    f.container.height = f.fill_height + 1.5 * f.container.radius;
    f.stroke = draw(0.2, 1.0);
    formats.push_back(f);
  }
  slosh::MinTimeOptions o;
  o.free_board_margin = 0.0;
  o.plan.time_limit = 60.0;
  int plans = 0;
  double t_min_sum = 0.0;
  for (auto _ : state) {
    plans = 0;
    t_min_sum = 0.0;
    for (const slosh::Format& f : formats) {
      const slosh::MinTimeResult r = slosh::min_time(f, strategy, o);
      plans += r.plans;
      t_min_sum += r.t_min ? *r.t_min : 0.0;
      benchmark::DoNotOptimize(r.t_min);
    }
  }
  state.SetLabel(slosh::to_string(strategy));
  state.counters["plans"] = plans;
  state.counters["t_min_sum_ms"] = t_min_sum * 1e3;
}
BENCHMARK(BM_MinTimeFormats)->Arg(4)->Unit(benchmark::kMillisecond);

// Along an arc (SPEC §14): the 90-degree index of a 300 mm table in 1.2 s, the container turning,
// against the straight line of the same length and time. Arg 0 = the arc (plan_on_path), 1 = the
// straight line (plan()); the SPEC's target: time_domain on the arc within 3 x the line's.
/// Plans `format` by `strategy` along the 90-degree index of a 300 mm table (the container
/// turning) or, `on_line`, on the straight line of the same length, labelled `label`.
void run_index_plan(benchmark::State& state, slosh::Format format, Strategy strategy, bool on_line,
                    const std::string& label) {
  const slosh::PlanarPath arc = slosh::PlanarPath::arc(0.3, 3.141592653589793 / 2.0, true);
  format.stroke = arc.length();
  format.motion_time = 1.2;
  PlanOptions options;
  options.robustness = false;
  // Under callgrind (50 x slower) the default 5 s budget would cut the arc's plan short.
  options.time_limit = 60.0;
  double rest = 0.0;
  int evaluations = 0;
  for (auto _ : state) {
    const slosh::PlanResult r = on_line ? slosh::plan(format, strategy, options)
                                        : slosh::plan_on_path(format, arc, strategy, options);
    rest = r.prediction.nonlinear.rest.value;
    evaluations = r.solver.iterations;
    benchmark::DoNotOptimize(r);
  }
  state.SetLabel(label);
  state.counters["eta_rest_mm"] = rest * 1e3;
  state.counters["evaluations"] = evaluations;
}

void BM_PlanArc(benchmark::State& state) {
  const auto strategy = static_cast<Strategy>(state.range(0));
  const bool on_line = state.range(1) == 1;
  run_index_plan(state, slosh::thesis_format(), strategy, on_line,
                 slosh::to_string(strategy) + (on_line ? " line" : " arc"));
}
// 4 time_domain, 8 auto, 1 notch; second arg 0 = arc, 1 = line.
BENCHMARK(BM_PlanArc)
    ->Args({4, 0})
    ->Args({4, 1})
    ->Args({1, 0})
    ->Args({8, 0})
    ->Unit(benchmark::kMillisecond);

// A rectangular tank on the same index (the README cup: 120 x 80 mm, 50 mm of water), turning
// with the table: time_domain optimises the tank's models along the arc. Arg 0 = the arc, 1 =
// the line of the same length (plan(), the tank's line models).
void BM_PlanTankArc(benchmark::State& state) {
  const bool on_line = state.range(0) == 1;
  slosh::Format format = slosh::thesis_format();
  format.container.rectangular = slosh::RectangularTank{0.12, 0.08, 0.0};
  format.fill_height = 0.05;
  run_index_plan(state, format, Strategy::kTimeDomain, on_line,
                 on_line ? "time_domain tank line" : "time_domain tank arc");
}
BENCHMARK(BM_PlanTankArc)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// One evaluation of time_domain's planar response with its gradient along the arc (the uniform
// law, 12 steps per period, 1 s of rest): what each SLSQP evaluation integrates.
void BM_PlanarSensitivity(benchmark::State& state) {
  const slosh::PlanarPath arc = slosh::PlanarPath::arc(0.3, 3.141592653589793 / 2.0, true);
  slosh::Format format = slosh::thesis_format();
  format.stroke = arc.length();
  format.motion_time = 1.2;
  const slosh::SloshingModel model = slosh::make_sloshing_model(format, {});
  slosh::detail::PlanarSensitivity sens(model, arc, 1.0, 12.0);
  const auto d = slosh::uniform_durations(format.motion_time);
  sens.freeze_steps(d.data());
  for (auto _ : state) {
    sens.compute(d.data());
    benchmark::DoNotOptimize(sens.motion_time());
  }
}
BENCHMARK(BM_PlanarSensitivity)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
