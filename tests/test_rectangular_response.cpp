// Responses of a rectangular tank turned on a straight path against independent computations:
// a fine-step RK4 integration of the modal equations re-typed here, the 2-D (one-direction)
// answer for a tank very wide across the motion, and the symmetries of a square tank.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "slosh/core/response/simulation.hpp"
#include "support/rectangular_reference.hpp"

namespace slosh {
namespace test_rectangular_response {

using test::direction;
using test::RefPeaks;
using test::rk4_peaks;

constexpr double kPi = std::numbers::pi;

// The thesis bench's water (rho = 1000 kg/m^3, mu = 1.0e-3 Pa s).
Fluid water() {
  return thesis_format().fluid;
}

TEST(RectangularResponse, TurnedTankMatchesAFineStepIntegration) {
  const double L = 0.12, W = 0.08, h = 0.05;
  for (double phi : {30.0, 70.0, -120.0}) {
    const RectangularModel model = make_rectangular_model({L, W, phi}, h, water());
    for (const MotionLaw& law :
         {make_poly5_law(0.3, 0.6), make_modified_trapezoid_law(0.25, 0.45)}) {
      const RectangularPeaks p = RectangularLinearResponse(model, law, 1.0).peaks();
      const double c = std::cos(phi * kPi / 180), s = std::sin(phi * kPi / 180);
      const RefPeaks ref =
          rk4_peaks({direction(L, W, h, c, 3), direction(W, L, h, s, 3)}, law, 1.0, 1e-5);
      EXPECT_NEAR(p.highest.motion.value / ref.motion, 1.0, 1e-6) << phi;
      EXPECT_NEAR(p.highest.rest.value / ref.rest, 1.0, 1e-6) << phi;
      // Each direction alone is the same integration with the other left out.
      const RefPeaks only_l = rk4_peaks({direction(L, W, h, c, 3)}, law, 1.0, 1e-5);
      EXPECT_NEAR(p.along_length.motion.value / only_l.motion, 1.0, 1e-6) << phi;
      EXPECT_GT(p.highest.motion.value, p.along_length.motion.value);
      EXPECT_GT(p.highest.motion.value, p.along_width.motion.value);
    }
  }
}

TEST(RectangularResponse, TankVeryWideAcrossTheMotionEqualsTheTwoDimensionalAnswer) {
  // L along the motion, W 10^5 times longer: the W modes are not excited and the side
  // walls' share of the damping vanishes, leaving the 2-D tank of length L (no side walls).
  const double L = 0.12, h = 0.05;
  const RectangularModel model = make_rectangular_model({L, 1e5 * L, 0.0}, h, water());
  const MotionLaw law = make_modified_trapezoid_law(0.3, 0.5);
  const RectangularPeaks p = RectangularLinearResponse(model, law, 1.0).peaks();
  const RefPeaks two_d = rk4_peaks({direction(L, 0.0, h, 1.0, 3, false)}, law, 1.0, 1e-5);
  EXPECT_NEAR(p.highest.motion.value / two_d.motion, 1.0, 1e-5);
  EXPECT_NEAR(p.highest.rest.value / two_d.rest, 1.0, 1e-5);
  EXPECT_EQ(p.along_width.motion.value, 0.0);
  EXPECT_EQ(p.along_width.rest.value, 0.0);
  // And a tank turned by 90 degrees is the same tank moved along W.
  const RectangularModel turned = make_rectangular_model({1e5 * L, L, 90.0}, h, water());
  const RectangularPeaks q = RectangularLinearResponse(turned, law, 1.0).peaks();
  EXPECT_EQ(q.highest.motion.value, p.highest.motion.value);
  EXPECT_EQ(q.highest.rest.value, p.highest.rest.value);
  EXPECT_EQ(q.along_length.motion.value, 0.0);
}

TEST(RectangularResponse, SquareTankAt45DegreesExcitesBothDirectionsEqually) {
  const double side = 0.1, h = 0.045;
  const MotionLaw law = make_poly5_law(0.25, 0.4);
  const RectangularPeaks straight =
      RectangularLinearResponse(make_rectangular_model({side, side, 0.0}, h, water()), law, 1.0)
          .peaks();
  const RectangularPeaks plus =
      RectangularLinearResponse(make_rectangular_model({side, side, 45.0}, h, water()), law, 1.0)
          .peaks();
  const RectangularPeaks minus =
      RectangularLinearResponse(make_rectangular_model({side, side, -45.0}, h, water()), law, 1.0)
          .peaks();
  EXPECT_EQ(plus.along_length.motion.value, plus.along_width.motion.value);
  EXPECT_EQ(plus.along_length.rest.value, plus.along_width.rest.value);
  EXPECT_EQ(plus.highest.motion.value, minus.highest.motion.value);
  EXPECT_EQ(plus.highest.rest.value, minus.highest.rest.value);
  // Each direction carries cos 45 of the straight move's response and the corner adds both:
  // sqrt(2) times the straight move's wall height.
  EXPECT_NEAR(plus.along_length.motion.value / straight.highest.motion.value, std::sqrt(0.5),
              1e-12);
  EXPECT_NEAR(plus.highest.motion.value / straight.highest.motion.value, std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(plus.highest.rest.value / straight.highest.rest.value, std::sqrt(2.0), 1e-9);
}

TEST(RectangularResponse, CombinedResponseIsTheWeightedSumOfItsParts) {
  const RectangularModel model = make_rectangular_model({0.12, 0.08, 0.0}, 0.05, water());
  const MotionLaw law = make_poly5_law(0.2, 0.5);
  const LinearResponse a(model.along_length, law, 1.0);
  const LinearResponse b(model.along_width, law.scaled(0.4), 1.0);
  const LinearResponse sum = LinearResponse::combined(a, 0.7, b, -1.3);
  for (double t = 0.0; t <= 1.5; t += 0.0123) {
    EXPECT_NEAR(sum.eta(t), 0.7 * a.eta(t) - 1.3 * b.eta(t), 1e-15) << t;
  }
  // Different piece times (another motion time) cannot be summed piece by piece.
  const LinearResponse other(model.along_width, make_poly5_law(0.2, 0.6), 1.0);
  EXPECT_THROW((void)LinearResponse::combined(a, 1.0, other, 1.0), std::invalid_argument);
}

TEST(RectangularResponse, AxisComponentsAreExactAtQuarterTurns) {
  EXPECT_EQ(axis_components(0.0).along_width, 0.0);
  EXPECT_EQ(axis_components(90.0).along_length, 0.0);
  EXPECT_EQ(axis_components(-90.0).along_width, -1.0);
  EXPECT_EQ(axis_components(180.0).along_length, -1.0);
  EXPECT_EQ(axis_components(-180.0).along_width, 0.0);
  EXPECT_DOUBLE_EQ(axis_components(30.0).along_width, 0.5);
  EXPECT_DOUBLE_EQ(axis_components(-60.0).along_length, 0.5);
}

/// The warnings of `r` that judge a wave's steepness.
std::vector<std::string> steepness_warnings(const SimulationResult& r) {
  std::vector<std::string> out;
  for (const Warning& w : r.warnings) {
    if (w.text.find("steepest standing wave") != std::string::npos) out.push_back(w.text);
  }
  return out;
}

// A corner adds both directions' waves, but each is a standing wave of its own side, and no
// standing wave is steeper than k A = 0.68 (Penney & Price 1952): each direction's wave (here an
// RK4 integration of that direction alone) is judged against k1 = pi / its side, never the sum.
TEST(RectangularResponse, SteepnessWarningJudgesEachDirectionOnItsOwnSide) {
  const double side = 0.1, h = 0.1, stroke = 0.3, T = 0.75;
  const MotionLaw law = SevenSegmentLaw(uniform_durations(T), stroke).law();
  const double k1 = kPi / side;
  SimulationOptions options;
  options.rest_time = 1.0;
  for (const double phi : {45.0, -45.0, 0.0}) {
    Format f = thesis_format();
    f.container.rectangular = RectangularTank{side, side, phi};
    f.container.height = 0.3;
    f.fill_height = h;
    f.stroke = stroke;
    f.motion_time = T;
    const SimulationResult r = simulate(f, law, options);
    ASSERT_FALSE(r.invalid_input);
    const double c = std::abs(std::cos(phi * kPi / 180));
    const RefPeaks one = rk4_peaks({direction(side, side, h, c, 3)}, law, 1.0, 1e-5);
    const double wave = std::max(one.motion, one.rest);
    const std::vector<std::string> steep = steepness_warnings(r);
    if (phi != 0.0) {
      ASSERT_GT(k1 * r.linear.motion.value, 0.68) << "the corner's sum must be steeper";
      ASSERT_LT(k1 * wave, 0.68) << "and each direction's wave less steep";
      EXPECT_TRUE(steep.empty()) << phi << ": " << steep.front();
      continue;
    }
    ASSERT_GT(k1 * wave, 0.68) << "moved along its length, the one wave is too steep";
    ASSERT_GT(one.motion, one.rest);
    char text[256];
    std::snprintf(text, sizeof text,
                  "linear model beyond its theory: along the length 100.0 mm, the wall height "
                  "%.1f mm is a wave steepness k1 eta = %.2f, above the steepest standing wave "
                  "0.68 (Penney & Price 1952); the figures are not reliable",
                  wave * 1e3, k1 * wave);
    EXPECT_EQ(steep, std::vector<std::string>{text});
  }
  // A steepness just above the limit is written with the digits that show it above: 113 mm in
  // 0.5 s at 45 degrees gives each side k1 eta = 0.6804, not "0.68, above ... 0.68".
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{side, side, 45.0};
  f.fill_height = h;
  f.stroke = 0.113;
  f.motion_time = 0.5;
  const SimulationResult r =
      simulate(f, SevenSegmentLaw(uniform_durations(0.5), 0.113).law(), options);
  // Both sides of the square: one sentence names both.
  const std::vector<std::string> steep = steepness_warnings(r);
  ASSERT_EQ(steep.size(), 1u);
  const std::string& w = steep.front();
  EXPECT_EQ(
      w.rfind("linear model beyond its theory: along the length 100.0 mm, the wall height ", 0), 0u)
      << w;
  EXPECT_NE(w.find(" and along the width 100.0 mm, the wall height "), std::string::npos) << w;
  EXPECT_EQ(w.find("k1 eta = 0.68,"), std::string::npos) << w;
  EXPECT_NE(w.find("k1 eta = 0.680"), w.rfind("k1 eta = 0.680")) << w;  // both quoted
}

}  // namespace test_rectangular_response
}  // namespace slosh
