// A rectangular cup on a rotary index table (SPEC §14 with §15): 120 x 80 mm, water filled 50 mm,
// on the 90-degree index of a 300 mm table in 1.5 s, turning with it, rest window 1 s: the tank's
// linear and nonlinear responses along the arc (both directions in its own frame, the corners),
// and a multi_notch plan verified on them.

#include <benchmark/benchmark.h>

#include <numbers>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/response/rectangular_planar.hpp"
#include "slosh/core/strategy/path_plan.hpp"

namespace {

constexpr double kRadius{0.3};
constexpr double kTime{1.5};

slosh::Format cup_format() {
  slosh::Format f;
  f.container.rectangular = slosh::RectangularTank{0.12, 0.08, 0.0};
  f.fill_height = 0.05;
  f.fluid = slosh::Fluid{"water", 998.2, 1.0016e-3, ""};
  f.motion_time = kTime;
  return f;
}

slosh::PlanarPath table() {
  return slosh::PlanarPath::arc(kRadius, std::numbers::pi / 2, true);
}

void BM_RectangularArcResponse(benchmark::State& state) {
  const slosh::RectangularModel model =
      slosh::make_rectangular_model({0.12, 0.08, 0.0}, 0.05, cup_format().fluid);
  const slosh::PlanarPath path = table();
  const slosh::MotionLaw law =
      slosh::SevenSegmentLaw(slosh::uniform_durations(kTime), path.length()).law();
  const slosh::PlanarDrive drive(path, law);
  const bool nonlinear = state.range(0) == 1;
  for (auto _ : state) {
    if (nonlinear) {
      benchmark::DoNotOptimize(slosh::rectangular_planar_nonlinear_peaks(model, drive, 0.0, 1.0));
    } else {
      benchmark::DoNotOptimize(slosh::rectangular_planar_linear_peaks(model, drive, 0.0, 1.0));
    }
  }
  state.SetLabel(nonlinear ? "nonlinear" : "linear");
}
BENCHMARK(BM_RectangularArcResponse)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_RectangularArcPlan(benchmark::State& state) {
  const slosh::Format f = cup_format();
  const slosh::PlanarPath path = table();
  slosh::PlanOptions o;
  o.robustness = false;
  const auto strategy = static_cast<slosh::Strategy>(state.range(0));
  for (auto _ : state) {
    benchmark::DoNotOptimize(slosh::plan_on_path(f, path, strategy, o));
  }
  state.SetLabel(slosh::to_string(strategy));
}
BENCHMARK(BM_RectangularArcPlan)
    ->Arg(static_cast<int>(slosh::Strategy::kMultiNotch))
    ->Arg(static_cast<int>(slosh::Strategy::kAuto))
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
