// The comparison laws: rest-to-rest, stroke reached, continuity, known acceleration coefficients,
// and position / velocity consistent with the integrated acceleration.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace test_motion_laws {

struct LawCase {
  const char* name;
  MotionLaw (*make)(double, double);
  double acceleration_coefficient;  // C_a = a_max T^2 / s
};

const LawCase kCases[] = {
    {"poly5", make_poly5_law, 10.0 / std::sqrt(3.0)},
    {"cycloidal", make_cycloidal_law, 2.0 * std::numbers::pi},
    {"modified_trapezoid", make_modified_trapezoid_law, 4.888},
};

void PrintTo(const LawCase& c, std::ostream* os) {
  *os << c.name;
}

class ComparisonLaws : public ::testing::TestWithParam<LawCase> {};

TEST_P(ComparisonLaws, RestToRestWithTheStroke) {
  const double s = 0.8, T = 1.3;
  const MotionLaw law = GetParam().make(s, T);
  EXPECT_NEAR(law.duration(), T, 1e-15);
  EXPECT_NEAR(law.stroke(), s, 1e-12);
  const KinematicState end = law.at(T);
  EXPECT_NEAR(end.position, s, 1e-12);
  EXPECT_NEAR(end.velocity, 0.0, 1e-12);
  EXPECT_NEAR(end.acceleration, 0.0, 1e-12);
  const KinematicState start = law.at(0.0);
  EXPECT_EQ(start.position, 0.0);
  EXPECT_NEAR(start.velocity, 0.0, 1e-15);
  EXPECT_NEAR(start.acceleration, 0.0, 1e-12);
  // At rest outside the motion.
  EXPECT_EQ(law.at(-1.0).velocity, 0.0);
  EXPECT_NEAR(law.at(T + 5.0).position, s, 1e-12);
  EXPECT_EQ(law.at(T + 5.0).acceleration, 0.0);
}

TEST_P(ComparisonLaws, AccelerationCoefficient) {
  const double s = 0.5, T = 0.7;
  const KinematicSummary k = GetParam().make(s, T).summary();
  EXPECT_NEAR(k.a_peak_positive * T * T / s, GetParam().acceleration_coefficient, 1e-3);
  EXPECT_NEAR(k.a_peak_negative, k.a_peak_positive, 1e-9);  // all three are symmetric
}

TEST_P(ComparisonLaws, ContinuousAtEveryBreakpoint) {
  const MotionLaw law = GetParam().make(0.8, 1.0);
  for (double t : law.breakpoints()) {
    const KinematicState l = law.at(t - 1e-12), r = law.at(t + 1e-12);
    EXPECT_NEAR(l.position, r.position, 1e-10) << t;
    EXPECT_NEAR(l.velocity, r.velocity, 1e-9) << t;
    EXPECT_NEAR(l.acceleration, r.acceleration, 1e-8) << t;
  }
}

TEST_P(ComparisonLaws, VelocityAndPositionAreTheIntegralsOfAcceleration) {
  const MotionLaw law = GetParam().make(0.8, 1.0);
  const auto accel = [&](double t) { return law.at(t).acceleration; };
  const auto knots = law.breakpoints();
  for (double t : {0.1, 0.33, 0.5, 0.77, 1.0}) {
    std::vector<double> upto;
    for (double k : knots)
      if (k < t) upto.push_back(k);
    upto.push_back(t);
    const double v = test::simpson_piecewise(accel, upto, 2000);
    EXPECT_NEAR(law.at(t).velocity, v, 1e-10) << t;
    const auto moment = [&](double tau) { return accel(tau) * (t - tau); };
    EXPECT_NEAR(law.at(t).position, test::simpson_piecewise(moment, upto, 2000), 1e-10) << t;
  }
}

TEST_P(ComparisonLaws, JerkIsTheDerivativeOfAcceleration) {
  const MotionLaw law = GetParam().make(0.8, 1.0);
  for (double t : {0.05, 0.21, 0.5, 0.66, 0.93}) {
    const double h = 1e-6;
    const double fd = (law.at(t + h).acceleration - law.at(t - h).acceleration) / (2 * h);
    EXPECT_NEAR(law.at(t).jerk, fd, 1e-5 * (1.0 + std::abs(fd))) << t;
  }
}

INSTANTIATE_TEST_SUITE_P(Laws, ComparisonLaws, ::testing::ValuesIn(kCases),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(MotionLaw, ScaledMultipliesEverything) {
  const MotionLaw law = make_cycloidal_law(1.0, 1.0);
  const MotionLaw half = law.scaled(0.5);
  for (double t : {0.1, 0.4, 0.9}) {
    EXPECT_NEAR(half.at(t).position, 0.5 * law.at(t).position, 1e-15);
    EXPECT_NEAR(half.at(t).jerk, 0.5 * law.at(t).jerk, 1e-12);
  }
}

// The summary of a law of many linear pieces (the exact per-piece path) against a dense scan with
// the velocity integrated by the trapezoid rule, on seeded random sample laws.
TEST(MotionLawSummary, LinearPiecesAgreeWithADenseScan) {
  std::mt19937 rng(7);
  std::normal_distribution<double> value(0.0, 3.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 50 + trial * 10;
    const double h = 1.0 / n;
    std::vector<double> a(static_cast<std::size_t>(n) + 1);
    for (double& x : a) x = value(rng);
    std::vector<LawPiece> pieces(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
      LawPiece& p = pieces[static_cast<std::size_t>(k)];
      p.t_begin = k * h;
      p.t_end = (k + 1) * h;
      p.poly = {a[k], (a[k + 1] - a[k]) / h, 0.0, 0.0};
    }
    const MotionLaw law("samples", pieces);
    const KinematicSummary got = law.summary();
    double a_pos = 0.0, a_neg = 0.0, v_peak = 0.0, j_peak = 0.0, v = 0.0;
    const int m = 400;  // sub-steps per piece
    for (int k = 0; k < n; ++k) {
      j_peak = std::max(j_peak, std::abs(a[k + 1] - a[k]) / h);
      for (int i = 0; i < m; ++i) {
        const double u0 = static_cast<double>(i) / m, u1 = static_cast<double>(i + 1) / m;
        const double x0 = a[k] + u0 * (a[k + 1] - a[k]), x1 = a[k] + u1 * (a[k + 1] - a[k]);
        v += 0.5 * (x0 + x1) * h / m;  // exact for a linear integrand
        a_pos = std::max(a_pos, x1);
        a_neg = std::max(a_neg, -x1);
        v_peak = std::max(v_peak, std::abs(v));
      }
    }
    a_pos = std::max(a_pos, a[0]);
    a_neg = std::max(a_neg, -a[0]);
    EXPECT_NEAR(got.a_peak_positive, a_pos, 1e-12) << trial;
    EXPECT_NEAR(got.a_peak_negative, a_neg, 1e-12) << trial;
    EXPECT_NEAR(got.j_peak, j_peak, 1e-9 * j_peak) << trial;
    // The scan misses the true extremum by at most |a| dt / 2 between its samples.
    EXPECT_GE(got.v_peak, v_peak - 1e-12) << trial;
    EXPECT_LE(got.v_peak, v_peak + 10.0 * h / m) << trial;
  }
}

}  // namespace test_motion_laws
}  // namespace slosh
