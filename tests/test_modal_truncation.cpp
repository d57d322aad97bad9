// A rectangular tank long against the distance a wave travels in the motion: the modes its model
// leaves out answer the motion dynamically, so the truncated modal sum is not converged and the
// answer says so (modal_sum_not_converged); a tank whose left-out modes are fast does not.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "slosh/core/warning.hpp"

namespace slosh {
namespace test_modal_truncation {

constexpr double kPi = std::numbers::pi;

Format tank(double side, double fill, double stroke, double motion_time) {
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{side, side, 0.0};
  f.container.height.reset();
  f.fill_height = fill;
  f.stroke = stroke;
  f.motion_time = motion_time;
  return f;
}

SimulationResult simulate_uniform(const Format& f, int modes) {
  SimulationOptions o;
  o.model.modes = modes;
  return simulate(f, SevenSegmentLaw(uniform_durations(f.motion_time), f.stroke).law(), o);
}

std::string text_of(const std::vector<Warning>& w, WarningKind kind) {
  for (const Warning& x : w) {
    if (x.kind == kind) return x.text;
  }
  return {};
}

std::string three(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

std::string four(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

// The 4 x 4 m tank in 50 mm of water moved 200 mm in 1 s (the hostile review's case): mode 4,
// k = 7 pi / 4, has a period of 1.67 s, over half the motion. The sum is indeed far from
// converged: 5 modes move eta_rest from 17.5 to 10.6 mm (a 150-mode sum, the review's, reaches
// 0.58 mm). The README cup (120 x 80 mm, 50 mm, 200 mm in 1 s) is converged: 5 modes move its
// figures by under 1 %, and it is not warned.
TEST(ModalTruncation, ALongShallowTankSaysItsModalSumIsNotConverged) {
  const Format big = tank(4.0, 0.05, 0.2, 1.0);
  const SimulationResult three_modes = simulate_uniform(big, 3);
  const SimulationResult five_modes = simulate_uniform(big, 5);
  EXPECT_GT(std::abs(three_modes.linear.rest.value - five_modes.linear.rest.value),
            0.2 * five_modes.linear.rest.value);
  const double k = 7.0 * kPi / 4.0;
  const double w = std::sqrt(9.81 * k * std::tanh(k * 0.05));
  const std::string want =
      "modal sum not converged along the length: the first mode the model leaves out (n = 4, " +
      three(w / (2.0 * kPi)) + " Hz) has a period of " + three(2.0 * kPi / w) +
      " s, over half the motion time 1 s, so it and the higher modes answer the motion "
      "dynamically and their waves are missing: the linear figures are not reliable (the side "
      "4000 mm is long against the " +
      four(std::sqrt(9.81 * 0.05) * 1e3) +
      " mm a shallow-water wave travels in the motion; more modes, up to 5 in "
      "options.model.modes, help only while the first left out stays fast)";
  EXPECT_EQ(text_of(three_modes.warnings, WarningKind::kModalSumNotConverged), want);
  // With 5 modes the first left out, n = 6, is still slow: still said.
  EXPECT_NE(text_of(five_modes.warnings, WarningKind::kModalSumNotConverged).find("(n = 6, "),
            std::string::npos);
  // A plan of that format says so too.
  PlanOptions po;
  po.robustness = false;
  po.time_limit = 60.0;
  const PlanResult p = plan(big, Strategy::kBaseline, po);
  EXPECT_EQ(text_of(p.warnings, WarningKind::kModalSumNotConverged), want);

  Format cup = tank(0.12, 0.05, 0.2, 1.0);
  cup.container.rectangular = RectangularTank{0.12, 0.08, 0.0};
  const SimulationResult c3 = simulate_uniform(cup, 3), c5 = simulate_uniform(cup, 5);
  EXPECT_NEAR(c3.linear.motion.value, c5.linear.motion.value, 0.01 * c5.linear.motion.value);
  EXPECT_FALSE(has_warning(c3.warnings, WarningKind::kModalSumNotConverged));
}

// A slower motion of the same tank (600 mm in 3.4 s): mode 4's period is under half the motion,
// yet the sum is not converged (the review's 40- and 100-mode sums give eta_rest 0.157 mm where 3
// modes give 1.21). Mode 4 simulated alone for the law says so: its wave after the motion is
// larger than the 3 modes' own. The independent evidence here: 5 modes move eta_rest by more
// than half.
TEST(ModalTruncation, TheLeftOutModeSimulatedForTheLawCatchesASlowerMotion) {
  const Format big = tank(4.0, 0.05, 0.6, 3.4);
  const SimulationResult three_modes = simulate_uniform(big, 3);
  const SimulationResult five_modes = simulate_uniform(big, 5);
  EXPECT_GT(std::abs(three_modes.linear.rest.value - five_modes.linear.rest.value),
            0.5 * five_modes.linear.rest.value);
  const std::string text = text_of(three_modes.warnings, WarningKind::kModalSumNotConverged);
  EXPECT_EQ(text.rfind("modal sum not converged along the length: the first mode the model "
                       "leaves out (n = 4, 0.605 Hz), simulated alone for this law, reaches ",
                       0),
            0U)
      << text;
  EXPECT_NE(text.find(" mm after the motion, "), std::string::npos) << text;
  EXPECT_NE(text.find(" % of the 3 modes' " + three(three_modes.linear.rest.value * 1e3) + " mm"),
            std::string::npos)
      << text;
}

// The direction across the motion is judged only when the motion drives it: the 4 m x 120 mm
// trough moved along its short side warns for nothing, along its long side it does.
TEST(ModalTruncation, OnlyTheDrivenDirectionsAreJudged) {
  Format f = tank(4.0, 0.05, 0.2, 1.0);
  f.container.rectangular = RectangularTank{0.12, 4.0, 0.0};
  EXPECT_FALSE(has_warning(simulate_uniform(f, 3).warnings, WarningKind::kModalSumNotConverged));
  f.container.rectangular->orientation_deg = 90.0;
  EXPECT_EQ(text_of(simulate_uniform(f, 3).warnings, WarningKind::kModalSumNotConverged)
                .rfind("modal sum not converged along the width: ", 0),
            0U);
}

// A plateau of exactly 10 m/s^2 computes as 10 + 2e-15: it is at the linear model's limit, not
// beyond it ("10.00 m/s^2 exceeds 10 m/s^2" was said); 10.01 is beyond.
TEST(ValidityWarnings, TheLinearModelsLimitIsNotCrossedByRoundOff) {
  const Format f = thesis_format();
  auto unreliable = [&f](double a) {
    return has_warning(validity_warnings(f, a, 0.01, 0.01, true, 0.001),
                       WarningKind::kLinearModelUnreliable);
  };
  EXPECT_FALSE(unreliable(10.000000000000002));
  EXPECT_TRUE(unreliable(10.01));
}

}  // namespace test_modal_truncation
}  // namespace slosh
