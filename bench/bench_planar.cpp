// Planar sloshing responses (SPEC §14): a 90-degree index of a 300 mm rotary table in 1 s (the
// uniform 7-segment law along the arc, the container turning with the table), 1 s of rest.

#include <benchmark/benchmark.h>

#include <numbers>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/response/planar_response.hpp"

namespace {

struct TableIndex {
  slosh::SloshingModel model = slosh::make_sloshing_model(slosh::thesis_format(), {});
  double angle = std::numbers::pi / 2;
  slosh::PlanarDrive drive{
      slosh::PlanarPath::arc(0.3, angle, true),
      slosh::SevenSegmentLaw(slosh::uniform_durations(1.0), 0.3 * angle).law()};
};

// The stored response (eta(t) anywhere) and the peaks alone (rest window ended by the energy
// bound), for both models.
void BM_PlanarLinearResponse(benchmark::State& state) {
  const TableIndex c;
  for (auto _ : state) benchmark::DoNotOptimize(slosh::PlanarLinearResponse(c.model, c.drive, 1.0));
}
BENCHMARK(BM_PlanarLinearResponse)->Unit(benchmark::kMicrosecond);

void BM_PlanarLinearPeaks(benchmark::State& state) {
  const TableIndex c;
  for (auto _ : state) benchmark::DoNotOptimize(slosh::planar_linear_peaks(c.model, c.drive, 1.0));
}
BENCHMARK(BM_PlanarLinearPeaks)->Unit(benchmark::kMicrosecond);

void BM_PlanarNonlinearResponse(benchmark::State& state) {
  const TableIndex c;
  for (auto _ : state) {
    benchmark::DoNotOptimize(slosh::PlanarNonlinearResponse(c.model, c.drive, 1.0));
  }
}
BENCHMARK(BM_PlanarNonlinearResponse)->Unit(benchmark::kMicrosecond);

void BM_PlanarNonlinearPeaks(benchmark::State& state) {
  const TableIndex c;
  for (auto _ : state) {
    benchmark::DoNotOptimize(slosh::planar_nonlinear_peaks(c.model, c.drive, 1.0));
  }
}
BENCHMARK(BM_PlanarNonlinearPeaks)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
