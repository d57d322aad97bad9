// The 7-segment law: closed-form A and B against the integrated acceleration, admissibility.

#include <gtest/gtest.h>

#include <stdexcept>

#include "slosh/core/law/seven_segment.hpp"
#include "support/fixtures.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_seven_segment {

test::TrapezoidAcceleration reference_of(const SevenSegmentLaw& law) {
  return {law.durations(), law.A(), law.B()};
}

TEST(SevenSegment, UniformThesisLawByHand) {
  // Uniform T/7: each lobe has area 2T/7 * A and the cruise lasts 4T/7 on average, so
  // v = 7 s / (4 T) = 1.4 m/s and A = B = 4.9 m/s^2 for s = 0.8 m, T = 1 s.
  const SevenSegmentLaw law(uniform_durations(1.0), 0.8);
  EXPECT_NEAR(law.v_peak(), 1.4, 1e-13);
  EXPECT_NEAR(law.A(), 4.9, 1e-13);
  EXPECT_NEAR(law.B(), 4.9, 1e-13);
  EXPECT_NEAR(law.jerks()[0], 4.9 / (1.0 / 7.0), 1e-11);
  EXPECT_NEAR(law.motion_time(), 1.0, 1e-15);
}

TEST(SevenSegment, LevelsReachTheStrokeWithZeroFinalVelocity) {
  const double s = 0.8;
  const SevenSegmentLaw law(test::kAsymmetricDurations, s);
  const auto a = reference_of(law);
  const auto knots = a.knots();
  // v(T) = int a dt and s(T) = int a(t) (T - t) dt, Simpson per segment (exact for these degrees).
  const double T = knots[7];
  EXPECT_NEAR(test::simpson_piecewise(a, knots, 10), 0.0, 1e-9);
  EXPECT_NEAR(test::simpson_piecewise([&](double t) { return a(t) * (T - t); }, knots, 10), s,
              1e-9);
  // The peak velocity is reached on the cruise.
  const std::array<double, 5> to_cruise{knots[0], knots[1], knots[2], knots[3], knots[4]};
  EXPECT_NEAR(test::simpson_piecewise(a, to_cruise, 10), law.v_peak(), 1e-9);
}

TEST(SevenSegment, SampledLawMatchesTheReferenceEverywhere) {
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.5);
  const auto a = reference_of(law);
  double worst_a = 0.0, worst_v = 0.0, worst_s = 0.0;
  for (int i = 0; i <= 1000; ++i) {
    const double t = 1e-3 * i;
    const KinematicState k = law.law().at(t);
    worst_a = std::max(worst_a, std::abs(k.acceleration - a(t)));
    const std::vector<double> upto = [&] {
      std::vector<double> u;
      for (double knot : a.knots())
        if (knot < t) u.push_back(knot);
      u.push_back(t);
      return u;
    }();
    worst_v = std::max(worst_v, std::abs(k.velocity - test::simpson_piecewise(a, upto, 4)));
    worst_s = std::max(
        worst_s, std::abs(k.position - test::simpson_piecewise(
                                           [&](double x) { return a(x) * (t - x); }, upto, 4)));
  }
  EXPECT_LT(worst_a, 1e-12);
  EXPECT_LT(worst_v, 1e-12);
  EXPECT_LT(worst_s, 1e-12);
}

TEST(SevenSegment, JerkIntegralIsTheSumOverRamps) {
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.8);
  const auto j = law.jerks();
  double expected = 0.0;
  for (int i = 0; i < 7; i += 2) expected += j[i] * j[i] * test::kAsymmetricDurations[i];
  EXPECT_NEAR(law.jerk_integral(), expected, 1e-9 * expected);
  EXPECT_NEAR(j[0], law.A() / test::kAsymmetricDurations[0], 1e-12);
  EXPECT_NEAR(j[2], -law.A() / test::kAsymmetricDurations[2], 1e-12);
  EXPECT_NEAR(j[4], -law.B() / test::kAsymmetricDurations[4], 1e-12);
  EXPECT_NEAR(j[6], law.B() / test::kAsymmetricDurations[6], 1e-12);
  EXPECT_EQ(j[1], 0.0);
  EXPECT_EQ(j[3], 0.0);
}

TEST(SevenSegment, SwitchTimesAreCumulativeSums) {
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.8);
  const auto t = law.switch_times();
  EXPECT_EQ(t[0], 0.0);
  double sum = 0.0;
  for (int i = 0; i < 7; ++i) {
    sum += test::kAsymmetricDurations[i];
    EXPECT_NEAR(t[i + 1], sum, 1e-15);
  }
  const auto b = law.law().breakpoints();
  EXPECT_NEAR(b.back(), 1.0, 1e-15);
}

TEST(SevenSegment, ZeroPlateausAreAllowed) {
  const Durations d{0.25, 0.0, 0.25, 0.0, 0.25, 0.0, 0.25};
  const SevenSegmentLaw law(d, 1.0);
  // Two triangles of base T/2: v = A T / 4 and, by point symmetry of v(t), s = v T / 2.
  EXPECT_NEAR(law.v_peak(), 2.0, 1e-12);
  EXPECT_NEAR(law.A(), 8.0, 1e-12);
}

TEST(SevenSegment, AdmissibilityMessages) {
  AdmissibilityRules rules;
  rules.motion_time = 1.0;
  EXPECT_FALSE(check_admissible(test::kAsymmetricDurations, rules).has_value());

  Durations d = test::kAsymmetricDurations;
  d[2] = 0.04;
  d[3] += 0.02;
  EXPECT_EQ(check_admissible(d, rules).value(),
            "durations_s[2] = 0.04 s is below the minimum ramp duration 0.05 s");

  d = test::kAsymmetricDurations;
  d[5] = -0.01;
  d[6] += 0.01;
  EXPECT_EQ(check_admissible(d, rules).value(),
            "durations_s[5] = -0.01 s is negative: plateaus must be >= 0 s");

  d = test::kAsymmetricDurations;
  d[3] += 0.1;
  EXPECT_EQ(check_admissible(d, rules).value(),
            "durations_s sum to 1.1 s but the motion time is 1 s (tolerance 1e-09 s)");

  d = test::kAsymmetricDurations;
  d[1] = std::nan("");
  EXPECT_EQ(check_admissible(d, rules).value(), "durations_s[1] is not a finite number");
}

TEST(SevenSegment, DegenerateDurationsThrow) {
  EXPECT_THROW(SevenSegmentLaw(Durations{0.1, 0.1, 0.0, 0.1, 0.1, 0.1, 0.1}, 1.0),
               std::invalid_argument);
  EXPECT_THROW(SevenSegmentLaw(Durations{0.1, -0.1, 0.1, 0.1, 0.1, 0.1, 0.1}, 1.0),
               std::invalid_argument);
  // Finite A but an overflowing jerk A / 1e-320.
  EXPECT_THROW(SevenSegmentLaw(Durations{1e-320, 0.5, 1e-320, 0.0, 1e-320, 0.5, 1e-320}, 1.0),
               std::invalid_argument);
}

TEST(SevenSegment, LongDoubleLevelsAgree) {
  std::array<long double, 7> dl{};
  for (int i = 0; i < 7; ++i) dl[i] = test::kAsymmetricDurations[i];
  const auto l = plateau_levels<long double>(dl, 0.8L);
  const SevenSegmentLaw law(test::kAsymmetricDurations, 0.8);
  EXPECT_NEAR(static_cast<double>(l.A), law.A(), 1e-13);
  EXPECT_NEAR(static_cast<double>(l.B), law.B(), 1e-13);
}

}  // namespace test_seven_segment
}  // namespace slosh
