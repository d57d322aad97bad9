// Seeded property tests over random admissible formats and durations.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "slosh/core/response/response.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "support/law_quadrature.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_properties {

using test::quadrature_of;

struct RandomCase {
  Format format;
  Durations durations;
};

class RandomFormats {
 public:
  explicit RandomFormats(std::uint64_t seed) : rng_(seed) {}

  RandomCase next() {
    RandomCase c;
    c.format.container.radius = uniform(0.015, 0.15);
    c.format.fill_height = c.format.container.radius * uniform(0.3, 3.0);
    c.format.fluid = Fluid{"custom", uniform(780.0, 1250.0), uniform(8e-4, 0.09), "random"};
    c.format.stroke = uniform(0.05, 1.5);
    c.format.motion_time = uniform(0.3, 3.0);
    std::array<double, 7> w{};
    double sum = 0.0;
    for (int i = 0; i < 7; ++i) {
      w[i] = i % 2 == 0 ? uniform(0.2, 1.0) : (uniform(0.0, 1.0) < 0.2 ? 0.0 : uniform(0.0, 1.0));
      sum += w[i];
    }
    for (int i = 0; i < 7; ++i) c.durations[i] = w[i] / sum * c.format.motion_time;
    return c;
  }

 private:
  double uniform(double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(rng_); }
  std::mt19937_64 rng_;
};

constexpr std::uint64_t kSeed = 20261123;

TEST(Properties, LawsAreRestToRestAndReachTheStroke) {
  RandomFormats gen(kSeed);
  for (int k = 0; k < 300; ++k) {
    const RandomCase c = gen.next();
    const SevenSegmentLaw law(c.durations, c.format.stroke);
    const double T = c.format.motion_time;
    const test::TrapezoidAcceleration a{c.durations, law.A(), law.B()};
    const auto knots = a.knots();
    EXPECT_NEAR(test::simpson_piecewise(a, knots, 2), 0.0, 1e-9 * law.v_peak()) << k;
    EXPECT_NEAR(test::simpson_piecewise([&](double t) { return a(t) * (T - t); }, knots, 2),
                c.format.stroke, 1e-9 * c.format.stroke)
        << k;
    const KinematicState end = law.law().at(T);
    EXPECT_NEAR(end.position, c.format.stroke, 1e-12 * c.format.stroke) << k;
    EXPECT_NEAR(end.velocity, 0.0, 1e-12 * law.v_peak()) << k;
    EXPECT_GT(law.A(), 0.0);
    EXPECT_GT(law.B(), 0.0);
  }
}

TEST(Properties, ReversedDurationsMirrorTheLaw) {
  // Durations reversed give a_rev(t) = -a(T - t): A and B swap and |X| is unchanged.
  RandomFormats gen(kSeed + 1);
  for (int k = 0; k < 200; ++k) {
    const RandomCase c = gen.next();
    Durations reversed = c.durations;
    std::reverse(reversed.begin(), reversed.end());
    const SevenSegmentLaw law(c.durations, c.format.stroke);
    const SevenSegmentLaw mirror(reversed, c.format.stroke);
    EXPECT_NEAR(mirror.A(), law.B(), 1e-10 * law.B()) << k;
    EXPECT_NEAR(mirror.B(), law.A(), 1e-10 * law.A()) << k;
    const double w = natural_frequency(c.format.container.radius, c.format.fill_height, 1);
    const double x = std::abs(acceleration_spectrum(law, w));
    EXPECT_NEAR(std::abs(acceleration_spectrum(mirror, w)), x, 1e-10 * (1.0 + x)) << k;
  }
}

TEST(Properties, SpectrumAndGradientAgreeWithIndependentComputations) {
  RandomFormats gen(kSeed + 2);
  for (int k = 0; k < 200; ++k) {
    const RandomCase c = gen.next();
    const SevenSegmentLaw law(c.durations, c.format.stroke);
    const double w1 = natural_frequency(c.format.container.radius, c.format.fill_height, 1);
    for (double w : {0.85 * w1, w1, 1.15 * w1}) {
      const std::complex<double> closed = acceleration_spectrum(law, w);
      const std::complex<double> quad = quadrature_of(law.law(), w);
      const double scale = c.format.stroke / c.format.motion_time;  // |X| ~ v_peak
      EXPECT_LT(std::abs(closed - quad), 1e-11 * scale) << k;

      const SpectrumPowerGradient g = spectrum_power_gradient(c.durations, c.format.stroke, w);
      std::array<long double, 7> dl{};
      for (int i = 0; i < 7; ++i) dl[i] = c.durations[i];
      double gmax = 0.0;
      for (double gi : g.gradient) gmax = std::max(gmax, std::abs(gi));
      for (int i = 0; i < 7; ++i) {
        auto up = dl, down = dl;
        const long double h = 1e-7L * c.format.motion_time;
        up[i] += h;
        down[i] -= h;
        const long double s = c.format.stroke, wl = w;
        const auto fd =
            static_cast<double>((std::norm(seven_segment_spectrum<long double>(up, s, wl)) -
                                 std::norm(seven_segment_spectrum<long double>(down, s, wl))) /
                                (2 * h));
        EXPECT_NEAR(g.gradient[i], fd, 1e-7 * gmax + 1e-12 * scale * scale) << k << " " << i;
      }
    }
  }
}

TEST(Properties, LinearResponseMatchesRk4AndScalesWithTheStroke) {
  RandomFormats gen(kSeed + 3);
  for (int k = 0; k < 12; ++k) {
    const RandomCase c = gen.next();
    ModelOptions options;
    options.modes = 2;
    const SloshingModel model = make_sloshing_model(c.format, options);
    const SevenSegmentLaw law(c.durations, c.format.stroke);
    const double rest = 0.5;
    const LinearResponse exact(model, law.law(), rest);
    const test::TrapezoidAcceleration a{c.durations, law.A(), law.B()};
    const double h = 2e-6;
    const double end = c.format.motion_time + rest;
    std::vector<test::Rk4Trajectory> ref;
    for (int m = 0; m < 2; ++m) {
      const double w = model.omega[m], z = model.zeta;
      ref.push_back(test::rk4_solve(
          [&](double t, double x, double v) { return -a(t) - 2 * z * w * v - w * w * x; }, end, h));
    }
    double worst = 0.0, peak = 0.0;
    for (std::size_t i = 0; i < ref[0].t.size(); i += 101) {
      const double eta_ref = model.eta_gain[0] * ref[0].x[i] + model.eta_gain[1] * ref[1].x[i];
      worst = std::max(worst, std::abs(exact.eta(ref[0].t[i]) - eta_ref));
      peak = std::max(peak, std::abs(eta_ref));
    }
    EXPECT_LT(worst, 1e-7 * peak) << k;

    const SevenSegmentLaw doubled(c.durations, 2.0 * c.format.stroke);
    const SloshPeaks p1 = exact.peaks();
    const SloshPeaks p2 = LinearResponse(model, doubled.law(), rest).peaks();
    EXPECT_NEAR(p2.motion.value, 2.0 * p1.motion.value, 1e-9 * p1.motion.value) << k;
    EXPECT_NEAR(p2.rest.value, 2.0 * p1.rest.value, 1e-9 * p1.rest.value) << k;
  }
}

}  // namespace test_properties
}  // namespace slosh
