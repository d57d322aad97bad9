// Responses of a rectangular cup of a form-fill-seal line: 120 x 80 mm, water filled 50 mm
// (h/L = 0.42, h/W = 0.63), the asymmetric 7-segment law over 100 mm in 1 s (9.4 mm at the wall
// linear, 10.7 mm nonlinear: k1 eta = 0.28, inside the nonlinear model's range), rest window 1 s;
// the tank straight on the path (one direction) and turned by 30 degrees (both directions and the
// corners); and a whole plan of that cup by notch (default options: the robustness sweep
// included), whose own cost is mostly the tank's verified predictions.

#include <benchmark/benchmark.h>

#include "fixtures.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace {

using slosh::bench::kAsymmetric;

slosh::RectangularModel cup(double orientation_deg) {
  return slosh::make_rectangular_model({0.12, 0.08, orientation_deg}, 0.05,
                                       slosh::Fluid{"water", 998.2, 1.0016e-3, ""});
}

void BM_RectangularLinear(benchmark::State& state) {
  const slosh::RectangularModel model = cup(static_cast<double>(state.range(0)));
  const slosh::SevenSegmentLaw law(kAsymmetric, 0.1);
  for (auto _ : state) {
    benchmark::DoNotOptimize(slosh::RectangularLinearResponse(model, law.law(), 1.0).peaks());
  }
}
BENCHMARK(BM_RectangularLinear)->Arg(0)->Arg(30)->Unit(benchmark::kMicrosecond);

void BM_RectangularNonlinear(benchmark::State& state) {
  const slosh::RectangularModel model = cup(static_cast<double>(state.range(0)));
  const slosh::SevenSegmentLaw law(kAsymmetric, 0.1);
  if (!slosh::rectangular_nonlinear_peaks(model, law.law(), 1.0).nonlinear) {
    state.SkipWithError("the benchmark format left the nonlinear model's range");
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(slosh::rectangular_nonlinear_peaks(model, law.law(), 1.0));
  }
}
BENCHMARK(BM_RectangularNonlinear)->Arg(0)->Arg(30)->Unit(benchmark::kMicrosecond);

void BM_RectangularPlanNotch(benchmark::State& state) {
  slosh::Format f;
  f.container.rectangular = slosh::RectangularTank{0.12, 0.08, static_cast<double>(state.range(0))};
  f.container.height = 0.07;
  f.fill_height = 0.05;
  f.fluid = slosh::Fluid{"water", 998.2, 1.0016e-3, ""};
  f.stroke = 0.1;
  f.motion_time = 1.0;
  const slosh::PlanOptions options;
  if (!slosh::plan(f, slosh::Strategy::kNotch, options).usable()) {
    state.SkipWithError("the benchmark cup's notch plan is not usable");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(slosh::plan(f, slosh::Strategy::kNotch, options));
}
BENCHMARK(BM_RectangularPlanNotch)->Arg(0)->Arg(30)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
