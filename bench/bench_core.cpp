// Core numerics on the thesis format (R = 48.5 mm, h = 82 mm, water, s = 800 mm, T = 1 s).

#include <benchmark/benchmark.h>

#include "fixtures.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/response/spectrum.hpp"

namespace {

using slosh::bench::kAsymmetric;

void BM_Spectrum(benchmark::State& state) {
  const double w1 = slosh::natural_frequency(0.0485, 0.082, 1);
  for (auto _ : state) {
    benchmark::DoNotOptimize(slosh::seven_segment_spectrum<double>(kAsymmetric, 0.8, w1));
  }
}
BENCHMARK(BM_Spectrum);

void BM_SpectrumPowerGradient(benchmark::State& state) {
  const double w1 = slosh::natural_frequency(0.0485, 0.082, 1);
  for (auto _ : state) {
    benchmark::DoNotOptimize(slosh::spectrum_power_gradient(kAsymmetric, 0.8, w1));
  }
}
BENCHMARK(BM_SpectrumPowerGradient);

void BM_SevenSegmentLaw(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(slosh::SevenSegmentLaw(kAsymmetric, 0.8));
}
BENCHMARK(BM_SevenSegmentLaw);

void BM_LinearResponseBuild(benchmark::State& state) {
  const slosh::SloshingModel model = slosh::make_sloshing_model(slosh::thesis_format(), {});
  const slosh::SevenSegmentLaw law(kAsymmetric, 0.8);
  for (auto _ : state) benchmark::DoNotOptimize(slosh::LinearResponse(model, law.law(), 1.0));
}
BENCHMARK(BM_LinearResponseBuild);

void BM_LinearResponsePeaks(benchmark::State& state) {
  slosh::bench::response_peaks_loop<slosh::LinearResponse>(state);
}
BENCHMARK(BM_LinearResponsePeaks)->Unit(benchmark::kMicrosecond);

void BM_NonlinearResponsePeaks(benchmark::State& state) {
  slosh::bench::response_peaks_loop<slosh::NonlinearResponse>(state);
}
BENCHMARK(BM_NonlinearResponsePeaks)->Unit(benchmark::kMicrosecond);

// The peaks alone (no trajectory kept, the rest window ended by the energy bound).
void BM_NonlinearPeaks(benchmark::State& state) {
  const slosh::SloshingModel model = slosh::make_sloshing_model(slosh::thesis_format(), {});
  const slosh::SevenSegmentLaw law(kAsymmetric, 0.8);
  for (auto _ : state) benchmark::DoNotOptimize(slosh::nonlinear_peaks(model, law.law(), 1.0));
}
BENCHMARK(BM_NonlinearPeaks)->Unit(benchmark::kMicrosecond);

void BM_Simulate(benchmark::State& state) {
  const slosh::SevenSegmentLaw law(kAsymmetric, 0.8);
  const slosh::SimulationOptions options;
  for (auto _ : state) {
    benchmark::DoNotOptimize(slosh::simulate(slosh::thesis_format(), law.law(), options));
  }
}
BENCHMARK(BM_Simulate)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
