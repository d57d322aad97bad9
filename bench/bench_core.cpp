// Core numerics on the thesis format (R = 48.5 mm, h = 82 mm, water, s = 800 mm, T = 1 s).

#include <benchmark/benchmark.h>

#include <vector>

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

// The linear half of the robustness report: the asymmetric law's linear peaks on the thesis model
// with its frequencies scaled by 0.9 .. 1.1 (20 points, the nominal one left out as the report
// does), each built and scanned.
void BM_LinearReportPoints(benchmark::State& state) {
  const slosh::SloshingModel model = slosh::make_sloshing_model(slosh::thesis_format(), {});
  const slosh::SevenSegmentLaw law(slosh::bench::kAsymmetric, 0.8);
  for (auto _ : state) {
    std::vector<slosh::LinearResponse> responses;
    for (int p = 0; p <= 20; ++p) {
      if (p == 10) continue;
      slosh::SloshingModel m = model;
      for (double& w : m.omega) w *= 0.9 + 0.01 * p;
      responses.emplace_back(m, law.law(), 1.0);
    }
    for (const slosh::LinearResponse& r : responses) benchmark::DoNotOptimize(r.peaks());
  }
}
BENCHMARK(BM_LinearReportPoints)->Unit(benchmark::kMicrosecond);

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
