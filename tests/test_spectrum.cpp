// Closed-form spectrum of the 7-segment law against quadrature and an FFT of the sampled law;
// the exact gradient of |X|^2 against long-double central differences.

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

#include "slosh/core/response/spectrum.hpp"
#include "support/fixtures.hpp"
#include "support/law_quadrature.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_spectrum {

using test::quadrature_of;

std::complex<double> quadrature_spectrum(const SevenSegmentLaw& law, double w) {
  const test::TrapezoidAcceleration a{law.durations(), law.A(), law.B()};
  // Simpson on every segment; 4000 intervals keep (w h)^4 below 1e-12 for w <= 200 rad/s.
  return test::simpson_piecewise([&](double t) { return a(t) * std::polar(1.0, -w * t); },
                                 a.knots(), 4000);
}

TEST(Spectrum, ClosedFormMatchesQuadratureOnBothBranches) {
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.8);
  // w T < 1 uses the per-segment form, w T >= 1 the jerk-jump form.
  for (double w : {1e-3, 0.05, 0.4, 0.999, 1.0, 3.0, 19.26, 41.55, 120.0, 200.0}) {
    const std::complex<double> closed = acceleration_spectrum(law, w);
    const std::complex<double> reference = quadrature_spectrum(law, w);
    EXPECT_NEAR(closed.real(), reference.real(), 1e-11) << "w = " << w;
    EXPECT_NEAR(closed.imag(), reference.imag(), 1e-11) << "w = " << w;
  }
}

TEST(Spectrum, ClosedFormMatchesTheGeneralLawQuadrature) {
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.6);
  for (double w : {0.7, 10.0, 19.26, 75.0}) {
    const std::complex<double> closed = acceleration_spectrum(law, w);
    const std::complex<double> gauss = quadrature_of(law.law(), w);
    EXPECT_LT(std::abs(closed - gauss), 1e-13 * (1.0 + std::abs(closed))) << "w = " << w;
  }
}

TEST(Spectrum, ZeroAtZeroFrequencyForRestToRest) {
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.8);
  EXPECT_LT(std::abs(acceleration_spectrum(law, 0.0)), 1e-12);
  // |X(w)| = w s + O(w^2): vanishes linearly.
  EXPECT_NEAR(std::abs(acceleration_spectrum(law, 1e-9)), 0.8e-9, 1e-15);
}

TEST(Spectrum, LowFrequencyLimitIsJOmegaTimesTheStroke) {
  // X(w) ~ int a dt - j w int a t dt = j w s, since int a = v(T) = 0 and int a t dt = -s.
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.8);
  const double w = 1e-4;
  const std::complex<double> X = acceleration_spectrum(law, w);
  EXPECT_NEAR(X.imag() / w, 0.8, 1e-6);
}

TEST(Spectrum, FftOfTheSampledLawMatchesWithEq450Normalisation) {
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.8);
  const double T = 1.0;
  const int n = 1 << 14;
  const double dt = T / n;
  std::vector<double> samples(n);
  for (int i = 0; i < n; ++i) samples[i] = law.law().at(dt * i).acceleration;
  for (int bin : {1, 3, 5, 12, 30}) {
    const double w = 2.0 * std::numbers::pi * bin / T;
    const std::complex<double> fft = test::dft_bin(samples, dt, w);
    const std::complex<double> closed = acceleration_spectrum(law, w);
    // Single-sided FFT amplitude 2/N |FFT_k| = (2/T) |X_a(w_k)|, thesis eq. 4.50.
    const double fft_single_sided = 2.0 / n * std::abs(fft / dt);
    EXPECT_NEAR(fft_single_sided, fft_amplitude(closed, T), 1e-7 * (1.0 + fft_single_sided))
        << "bin " << bin;
  }
}

TEST(Spectrum, LongDoubleInstantiationAgrees) {
  std::array<long double, 7> dl{};
  for (int i = 0; i < 7; ++i) dl[i] = test::kAsymmetricDurations[i];
  for (double w : {0.3, 19.26, 90.0}) {
    const auto xl = seven_segment_spectrum<long double>(dl, 0.8L, static_cast<long double>(w));
    const auto xd = seven_segment_spectrum<double>(test::kAsymmetricDurations, 0.8, w);
    EXPECT_NEAR(static_cast<double>(xl.real()), xd.real(), 1e-12);
    EXPECT_NEAR(static_cast<double>(xl.imag()), xd.imag(), 1e-12);
  }
}

long double power_ld(std::array<long double, 7> d, long double w) {
  return std::norm(seven_segment_spectrum<long double>(d, 0.8L, w));
}

TEST(SpectrumGradient, MatchesHighPrecisionCentralDifferences) {
  for (double w : {1.5, 19.26, 32.84, 70.0}) {
    const SpectrumPowerGradient g = spectrum_power_gradient(test::kAsymmetricDurations, 0.8, w);
    EXPECT_NEAR(
        g.power,
        std::norm(acceleration_spectrum(SevenSegmentLaw(test::kAsymmetricDurations, 0.8), w)),
        1e-14 * (1.0 + g.power));
    std::array<long double, 7> dl{};
    for (int i = 0; i < 7; ++i) dl[i] = test::kAsymmetricDurations[i];
    const long double h = 1e-7L;
    double scale = 0.0;
    for (double gi : g.gradient) scale = std::max(scale, std::abs(gi));
    for (int i = 0; i < 7; ++i) {
      auto up = dl, down = dl;
      up[i] += h;
      down[i] -= h;
      const auto fd = static_cast<double>((power_ld(up, w) - power_ld(down, w)) / (2 * h));
      EXPECT_NEAR(g.gradient[i], fd, 1e-8 * scale) << "w = " << w << ", i = " << i;
    }
  }
}

TEST(SpectrumGradient, VanishesWhereTheSpectrumHasAZero) {
  // |X|^2 has a double zero at a notch: the gradient must vanish too. The uniform law's
  // spectrum is zero at w = 2 pi k / (T/7) (every segment a whole number of periods).
  const double w = 2.0 * std::numbers::pi * 7.0;
  const SpectrumPowerGradient g = spectrum_power_gradient(uniform_durations(1.0), 0.8, w);
  EXPECT_LT(g.power, 1e-20);
  for (double gi : g.gradient) EXPECT_LT(std::abs(gi), 1e-9);
}

}  // namespace test_spectrum
}  // namespace slosh

namespace slosh {
namespace test_spectrum {

TEST(Spectrum, BothFormsAgreeAroundTheSwitch) {
  // Short ramps, long cruise: the hardest case for the jerk-jump form at small omega T.
  const Durations d{0.05, 0.0, 0.05, 0.8, 0.05, 0.0, 0.05};
  const SevenSegmentLaw law(d, 0.3);
  for (double w : {0.99999, 1.0, 7.99, 8.0, 8.01}) {
    const std::complex<double> closed = acceleration_spectrum(law, w);
    const std::complex<double> reference = quadrature_of(law.law(), w);
    EXPECT_LT(std::abs(closed - reference), 2e-14 * std::abs(reference)) << "w = " << w;
  }
}

}  // namespace test_spectrum
}  // namespace slosh

namespace slosh {
namespace test_spectrum {

// The piecewise closed form on laws of every piece kind (cubic, harmonic, linear, many short
// pieces) against Simpson on the sampled acceleration and against Gauss-Legendre.
TEST(Spectrum, PiecewiseClosedFormMatchesQuadratureOnGeneralLaws) {
  std::vector<LawPiece> ramps;  // 400 short linear pieces (like a sampled IIR law)
  const double h = 2.5e-3;
  auto sample = [](int k) { return 4.0 * std::sin(0.0157 * k) + std::cos(0.05 * k) - 1.0; };
  for (int k = 0; k < 400; ++k) {
    LawPiece p;
    p.t_begin = k * h;
    p.t_end = (k + 1) * h;
    p.poly = {sample(k), (sample(k + 1) - sample(k)) / h, 0.0, 0.0};
    ramps.push_back(p);
  }
  const MotionLaw laws[] = {
      make_poly5_law(0.8, 1.0), make_modified_trapezoid_law(0.8, 1.0), make_cycloidal_law(0.5, 0.7),
      SevenSegmentLaw(test::kAsymmetricDurations, 0.8).law(), MotionLaw("ramps", ramps)};
  for (const MotionLaw& law : laws) {
    // Round-off of either sum is relative to int |a| dt, the size of its terms.
    const double l1 = std::abs(
        test::gauss_legendre_spectrum([&](double t) { return std::abs(law.at(t).acceleration); },
                                      law.breakpoints(), 0.0, law.pieces().front().harmonic_omega));
    for (double w : {0.0, 1e-3, 0.7, 5.0, 19.3, 60.0, 150.0, 400.0}) {
      const std::complex<double> closed = acceleration_spectrum(law, w);
      const std::complex<double> gauss = quadrature_of(law, w);
      std::complex<double> simpson(0.0);
      for (const LawPiece& p : law.pieces()) {
        // Each piece on its own (the law is discontinuous at its end); (w h)^4 / 180 < 1e-14.
        const int n = 2 * static_cast<int>(std::ceil(p.duration() * (w + 60.0) * 200.0));
        simpson += test::simpson(
            [&](double tau) {
              return p.at(tau).acceleration * std::polar(1.0, -w * (p.t_begin + tau));
            },
            0.0, p.duration(), n);
      }
      const double scale = 1e-3 + std::abs(gauss);
      EXPECT_LT(std::abs(closed - gauss), 1e-14 * (std::abs(gauss) + l1))
          << law.name() << " w = " << w;
      EXPECT_LT(std::abs(closed - simpson), 1e-9 * scale) << law.name() << " w = " << w;
    }
  }
}

// The band checks' grid evaluation (one complex rotation per point and switch time) against the
// long-double closed form at every point, on seeded random laws and grids from omega T = 0.5 up,
// on both sides of seven_segment_spectrum's omega T = 8 switch: within 1e-13 of the jerk-jump
// terms' scale sum |w_i| / omega^2.
TEST(Spectrum, GridMagnitudesMatchTheLongDoubleClosedForm) {
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    Durations d;
    double sum = 0.0;
    for (double& di : d) {
      di = 0.02 + u(rng);
      sum += di;
    }
    const double T = 0.2 + 2.0 * u(rng);
    for (double& di : d) di *= T / sum;
    const double stroke = 0.1 + u(rng);
    // omega T from 0.5 to 200 at the first point (a quarter of the trials below 8, where the
    // seven_segment_spectrum switches forms), 801 points over +-(5..30) %.
    const double w1 = (trial % 4 == 0 ? 0.5 + 7.5 * u(rng) : 2.0 + 198.0 * u(rng)) / T;
    const double band = 0.05 + 0.25 * u(rng);
    const std::size_t count = 801;
    const double lo = (1.0 - band) * w1;
    const double step = 2.0 * band * w1 / static_cast<double>(count - 1);
    std::vector<double> got;
    seven_segment_magnitudes(d, stroke, lo, step, count, &got);
    ASSERT_EQ(got.size(), count);
    std::array<long double, 7> dl{};
    for (std::size_t i = 0; i < 7; ++i) dl[i] = d[i];
    const SevenSegmentLaw law(d, stroke);
    const double jerk_scale =
        2.0 * (law.A() / d[0] + law.A() / d[2] + law.B() / d[4] + law.B() / d[6]);
    for (std::size_t k = 0; k < count; ++k) {
      const long double w = static_cast<long double>(lo) + static_cast<long double>(step) * k;
      const double exact = static_cast<double>(
          std::abs(seven_segment_spectrum<long double>(dl, static_cast<long double>(stroke), w)));
      const double scale = jerk_scale / static_cast<double>(w * w);
      ASSERT_NEAR(got[k], exact, 1e-13 * scale) << "trial " << trial << ", point " << k;
    }
  }
}

}  // namespace test_spectrum
}  // namespace slosh
