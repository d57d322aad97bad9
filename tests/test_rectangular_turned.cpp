// Plans for a rectangular tank turned to the motion (SPEC §15): both directions slosh, each at
// its own first frequency, and every strategy acts on both (a notch between them cancels
// neither). Checked against a fine-step RK4 of the linear modes re-typed in tests/support and
// closed-form frequencies; the plan must move continuously with the orientation (no cut-off at
// which the second direction joins the design).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "slosh/core/model/format.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/rectangular_reference.hpp"
#include "support/reference_integrators.hpp"

namespace slosh {
namespace {

constexpr double kPi = std::numbers::pi;

/// A 120 x 80 mm cup of water, fill `fill_mm`, at `orientation` [deg], moved 200 mm in `T` s.
Format cup(double orientation, double fill_mm = 40.0, double T = 1.2) {
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{0.12, 0.08, orientation};
  f.fill_height = fill_mm * 1e-3;
  f.stroke = 0.2;
  f.motion_time = T;
  return f;
}

PlanOptions quick_options() {
  PlanOptions o;
  o.robustness = false;
  o.time_limit = 60.0;
  return o;
}

/// The closed-form first frequency along `side` at fill h [rad/s].
double omega1(double side, double h) {
  const double k = kPi / side;
  return std::sqrt(9.81 * k * std::tanh(k * h));
}

/// "2.25 Hz" as the plans write frequencies (3 significant digits).
std::string hz(double omega) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g Hz", omega / (2 * kPi));
  return text;
}

/// The first modes of both directions at 30 degrees, at the tank's own damping: the residual
/// wave a law leaves on the corners, integrated independently of the product.
double corner_rest(const PlanResult& r, const MotionLaw& law, double phi_deg) {
  const double phi = phi_deg * kPi / 180.0;
  std::vector<test::Modes> modes{test::direction(0.12, 0.08, 0.04, std::cos(phi), 1),
                                 test::direction(0.08, 0.12, 0.04, std::sin(phi), 1)};
  modes[0].zeta = r.rectangular->along_length.zeta;
  modes[1].zeta = r.rectangular->along_width.zeta;
  return test::rk4_peaks(modes, law, 1.0, 1e-5).rest;
}

TEST(RectangularTurned, NotchFirChainAndIirCancelBothDirectionsFirstModes) {
  const double w_l = omega1(0.12, 0.04), w_w = omega1(0.08, 0.04);
  const MotionLaw uniform = SevenSegmentLaw(uniform_durations(1.2), 0.2).law();
  for (Strategy s : {Strategy::kNotch, Strategy::kFirChain, Strategy::kIir}) {
    const PlanResult r = plan(cup(30.0), s, quick_options());
    ASSERT_TRUE(r.usable()) << to_string(s) << ": " << r.message;
    // The message names both modes the law acts on, and no longer claims one "f1".
    EXPECT_NE(r.message.find("the length's f1 = " + hz(w_l)), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("the width's f1 = " + hz(w_w)), std::string::npos) << r.message;
    EXPECT_EQ(r.message.find("exact notch at f1 "), std::string::npos) << r.message;
    // Both directions' first modes are left (almost) at rest: a notch at the middle of the two
    // frequencies left 31 % of the uniform law's corner wave here.
    const double shaped = corner_rest(r, r.law, 30.0);
    const double base = corner_rest(r, uniform, 30.0);
    EXPECT_LT(shaped, 1.0 * base) << to_string(s) << ": " << shaped << " vs " << base;
  }
}

}  // namespace
}  // namespace slosh
