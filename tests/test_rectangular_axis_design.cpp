// A turned rectangular tank's design over both directions that fails on the tank (not usable,
// or resting above the uniform law) gives way to a direction's own design (the law the
// strategy gives on that axis), and a square tank's two coinciding first modes get the notch two
// nearly equal ones get. Checked against the axis plans' laws simulated on the turned tank, and
// against the law's spectrum by quadrature.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/law_quadrature.hpp"

namespace slosh {
namespace test_rectangular_axis_design {

constexpr double kPi = std::numbers::pi;

/// A tank of water, `fill_mm` deep, at `orientation` [deg], moved `stroke_mm` in `T` s.
Format tank(double length_mm, double width_mm, double orientation, double fill_mm, double stroke_mm,
            double T) {
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{length_mm * 1e-3, width_mm * 1e-3, orientation};
  f.fill_height = fill_mm * 1e-3;
  f.stroke = stroke_mm * 1e-3;
  f.motion_time = T;
  return f;
}

PlanOptions quick_options() {
  PlanOptions o;
  o.robustness = false;
  o.time_limit = 60.0;
  return o;
}

/// The nonlinear peaks of `law` simulated on `format` (the verification's own models).
SloshPeaks peaks_on(const Format& format, const MotionLaw& law) {
  SimulationOptions o;
  const SimulationResult r = simulate(format, law, o);
  EXPECT_FALSE(r.invalid_input.has_value());
  return r.nonlinear;
}

double rest_on(const Format& format, const MotionLaw& law) {
  return peaks_on(format, law).rest.value;
}

/// Whether each figure of `a` is at most `b`'s.
bool no_worse(const SloshPeaks& a, const SloshPeaks& b) {
  return a.motion.value <= b.motion.value && a.rest.value <= b.rest.value;
}

TEST(RectangularAxisDesign, AnUnusableDesignOverBothGivesWayToAnAxisLaw) {
  // Tanks turned to the motion, each strategy: the laws it gives on the two axes (orientation 0
  // and 90), simulated on the turned tank. Where the plan is a direction's own design (the
  // design over both directions not usable, or worse than the uniform law), it rests no higher
  // than any axis law that is optimal on its axis and no worse than the uniform law on the
  // turned tank; where the plan is not usable, no such axis law exists. (200 x 60 mm at 74
  // degrees, min_jerk_band returned 3.65 mm where the length's law rests at 1.05 mm.)
  struct Case {
    double length, width, fill, stroke, T;
  };
  int own = 0;
  for (const Case& k : {Case{120, 80, 50, 60, 1.0}, Case{200, 60, 60, 300, 1.5}}) {
    for (Strategy s : {Strategy::kNotch, Strategy::kMultiNotch, Strategy::kMinJerkBand,
                       Strategy::kFirChain, Strategy::kShaper, Strategy::kIir}) {
      std::vector<MotionLaw> axis_laws;
      for (double axis : {0.0, 90.0}) {
        const PlanResult a =
            plan(tank(k.length, k.width, axis, k.fill, k.stroke, k.T), s, quick_options());
        if (a.status == SolveStatus::kOptimal) axis_laws.push_back(a.law);
      }
      for (double phi : {0.1, 10.0, 30.0, 56.3, 60.0, 74.0, 85.0}) {
        const Format turned = tank(k.length, k.width, phi, k.fill, k.stroke, k.T);
        const PlanResult r = plan(turned, s, quick_options());
        const bool alone = r.message.find("'s first mode alone") != std::string::npos;
        own += alone ? 1 : 0;
        if (!alone && r.usable()) continue;
        const SloshPeaks uniform =
            peaks_on(turned, SevenSegmentLaw(uniform_durations(k.T), k.stroke * 1e-3).law());
        for (const MotionLaw& law : axis_laws) {
          const SloshPeaks axis = peaks_on(turned, law);
          if (!no_worse(axis, uniform)) continue;
          EXPECT_TRUE(alone) << k.length << " x " << k.width << " " << to_string(s) << " " << phi
                             << ": " << r.message;
          EXPECT_LE(r.prediction.nonlinear.rest.value, axis.rest.value * (1.0 + 1e-9))
              << k.length << " x " << k.width << " " << to_string(s) << " " << phi << ": "
              << r.message;
        }
      }
    }
  }
  EXPECT_GT(own, 5);
}

TEST(RectangularAxisDesign, ThePlanIsContinuousWhereTheMostExcitedDirectionChanges) {
  // 200 x 60 mm: the width becomes the most excited direction (the higher static wall height) at
  // atan(200 / 60) = 73.3007558 degrees. Every direction's own design is weighed, so the plan
  // does not change there (min_jerk_band jumped from 1.08 to 3.80 mm across 2e-6 degree).
  const double at = std::atan2(200.0, 60.0) * 180.0 / kPi;
  const PlanResult below =
      plan(tank(200, 60, at - 1e-6, 60, 300, 1.5), Strategy::kMinJerkBand, quick_options());
  const PlanResult above =
      plan(tank(200, 60, at + 1e-6, 60, 300, 1.5), Strategy::kMinJerkBand, quick_options());
  EXPECT_NEAR(below.prediction.nonlinear.rest.value, above.prediction.nonlinear.rest.value,
              1e-4 * below.prediction.nonlinear.rest.value);
  // The design over both directions is infeasible on its band there, and the plan says so
  // rather than calling the length's law better on a figure.
  EXPECT_NE(above.message.find("min_jerk_band optimal: designed for the length's first mode "
                               "alone (the law this strategy gives along the length, which does "
                               "not act on the width's first mode): the design over both "
                               "directions is infeasible on the tank (|X| <= 20 % of X_ref on "
                               "the band is not reachable in 1.5 s"),
            std::string::npos)
      << above.message;
}

TEST(RectangularAxisDesign, MinJerkBandAHairOffTheAxisIsNotInfeasible) {
  // 0.1 degree off the axis, the width's share of the residual wave is 0.0015: min_jerk_band's
  // band over both modes is out of reach in 1 s (it was returned, infeasible, at 1.51 mm), while
  // each direction's own band is met. The plan is a direction's own law, optimal, and rests no
  // higher on the tank than the length's law of the axis plan.
  const PlanResult on =
      plan(tank(120, 80, 0.0, 50, 60, 1.0), Strategy::kMinJerkBand, quick_options());
  const Format turned = tank(120, 80, 0.1, 50, 60, 1.0);
  const PlanResult off = plan(turned, Strategy::kMinJerkBand, quick_options());
  ASSERT_EQ(on.status, SolveStatus::kOptimal) << on.message;
  EXPECT_EQ(off.status, SolveStatus::kOptimal) << off.message;
  EXPECT_NE(off.message.find("'s first mode alone (the law this strategy gives along the "),
            std::string::npos)
      << off.message;
  EXPECT_NE(off.message.find("): the design over both directions is infeasible on the tank (|X| "
                             "<= 20 % of X_ref on the band is not reachable in 1 s"),
            std::string::npos)
      << off.message;
  EXPECT_LE(off.prediction.nonlinear.rest.value, rest_on(turned, on.law) * (1.0 + 1e-9));
}

TEST(RectangularAxisDesign, ADesignOverBothThatRestsAboveTheUniformLawGivesWay) {
  // The README's cup, 50 mm of water, 60 mm in 1 s, nearly across the motion: iir's cascade over
  // both directions rested 24 % above the uniform law at 89 degrees (1.32 against 1.07 mm, under
  // the worse_than_baseline guard's 0.5 mm) and stood optimal, while the width's own design rests
  // at 0.195 mm. Every plan here rests no higher than the uniform law simulated on the tank, and
  // where the design over both does not, the plan is a direction's own design and says why.
  for (double phi : {85.0, 89.0, 89.9}) {
    const Format turned = tank(120, 80, phi, 50, 60, 1.0);
    const PlanResult r = plan(turned, Strategy::kIir, quick_options());
    ASSERT_EQ(r.status, SolveStatus::kOptimal) << phi << ": " << r.message;
    const double uniform = rest_on(turned, SevenSegmentLaw(uniform_durations(1.0), 0.06).law());
    EXPECT_NEAR(r.prediction.nonlinear.rest.value, rest_on(turned, r.law),
                1e-9 * r.prediction.nonlinear.rest.value);
    EXPECT_LT(r.prediction.nonlinear.rest.value, 0.25 * uniform) << phi << ": " << r.message;
    EXPECT_EQ(r.message.rfind("iir optimal: designed for the width's first mode alone (the law "
                              "this strategy gives along the width, which does not act on the "
                              "length's first mode): the design over both directions rests "
                              "above the uniform law on the tank (nominal eta_rest ",
                              0),
              0U)
        << r.message;
    // The sentence's figures: the design over both's and the uniform law's nominal eta_rest, then
    // the returned law's.
    char rests[96];
    std::snprintf(rests, sizeof rests, " mm against %.3g mm); on the tank it rests at %.3g mm",
                  uniform * 1e3, r.prediction.nonlinear.rest.value * 1e3);
    EXPECT_NE(r.message.find(rests), std::string::npos) << rests << "\n" << r.message;
  }
  // notch next to 90 degrees on the README's cup (40 mm, 200 mm in 1.2 s): two mirror optima
  // over both of equal jerk, a hair apart in orientation, rested at 0.225 and 0.571 mm (the
  // uniform law at 0.44 mm); the second gives way to the width's own design.
  const PlanResult a =
      plan(tank(120, 80, 89.99994267005074, 40, 200, 1.2), Strategy::kNotch, quick_options());
  const PlanResult b =
      plan(tank(120, 80, 89.99994267005073, 40, 200, 1.2), Strategy::kNotch, quick_options());
  EXPECT_NEAR(a.prediction.nonlinear.rest.value, b.prediction.nonlinear.rest.value,
              0.05 * a.prediction.nonlinear.rest.value)
      << a.message << "\n"
      << b.message;
}

TEST(RectangularAxisDesign, ASpectralLawAndItsMirrorAreWeighedOnATurnedTank) {
  // multi_notch's law and its mirror (the durations reversed) reach the same objective, and the
  // solve returned one or the other as the orientation moved by 1e-12 degree (eta_rest 0.857 and
  // 0.936 mm on the README's cup at 86.9357 degrees). Both are verified on the turned tank and the
  // lower kept: the plan is the same on both sides and rests no higher than its mirror simulated
  // here.
  const double at[] = {86.9356909665562, 86.93569096655665};
  std::vector<PlanResult> r;
  for (double phi : at) {
    r.push_back(plan(tank(120, 80, phi, 40, 200, 1.2), Strategy::kMultiNotch, quick_options()));
    ASSERT_EQ(r.back().status, SolveStatus::kOptimal) << r.back().message;
  }
  EXPECT_NEAR(r[0].prediction.nonlinear.rest.value, r[1].prediction.nonlinear.rest.value,
              1e-6 * r[0].prediction.nonlinear.rest.value);
  for (std::size_t k = 0; k < 2; ++k) {
    Durations mirrored = *r[k].durations;
    std::reverse(mirrored.begin(), mirrored.end());
    const Format turned = tank(120, 80, at[k], 40, 200, 1.2);
    EXPECT_LE(r[k].prediction.nonlinear.rest.value,
              rest_on(turned, SevenSegmentLaw(mirrored, 0.2).law()) * (1.0 + 1e-9));
  }
}

TEST(RectangularAxisDesign, AnUnusableDesignGivesWayToAnUnusableOwnDesignThatRestsLower) {
  // A 200 x 60 mm tray at 15 degrees, 40 mm of water, 150 mm in 1 s: min_jerk_band's band is out
  // of reach over both directions (15.1 mm at rest) and along the length alone (2.9 mm). The
  // plan is infeasible either way, and returns the law that rests lower.
  const Format turned = tank(200, 60, 15.0, 40, 150, 1.0);
  const PlanResult r = plan(turned, Strategy::kMinJerkBand, quick_options());
  const PlanResult axis =
      plan(tank(200, 60, 0.0, 40, 150, 1.0), Strategy::kMinJerkBand, quick_options());
  EXPECT_EQ(r.status, SolveStatus::kInfeasible) << r.message;
  EXPECT_NE(r.message.find("designed for the length's first mode alone (the law this strategy "
                           "gives along the length, which does not act on the width's first "
                           "mode): neither it nor the design over both directions is usable on "
                           "the tank, and it rests lower: on the tank at "),
            std::string::npos)
      << r.message;
  EXPECT_LE(r.prediction.nonlinear.rest.value, rest_on(turned, axis.law) * (1.0 + 1e-9));
  EXPECT_LT(r.prediction.nonlinear.rest.value, 5e-3);
}

TEST(RectangularAxisDesign, UnderARangeTheChoiceSaysWhichFiguresItCompares) {
  // Under an uncertainty range the designs are ranked on their worst over it, while the uniform
  // law's figure is its nominal one: the sentence quoted the design over both's worst (0.774 mm)
  // as if above the uniform law's nominal 0.451 mm. It now compares nominal with nominal and
  // says the designs' figures are their worst.
  PlanOptions o = quick_options();
  o.uncertainty.omega_error = 0.05;
  const PlanResult r = plan(tank(120, 80, 89.9, 40, 200, 1.2), Strategy::kShaper, o);
  ASSERT_EQ(r.status, SolveStatus::kOptimal) << r.message;
  EXPECT_NE(r.message.find("the design over both directions rests above the uniform law on the "
                           "tank (nominal eta_rest "),
            std::string::npos)
      << r.message;
  EXPECT_NE(r.message.find(" mm (each its worst over the uncertainty range)"), std::string::npos)
      << r.message;
}

TEST(RectangularAxisDesign, AutosCandidatesThatSloshMoreThanTheUniformLawAreNotOptimal) {
  // The README's cup at 89.9 degrees: multi_notch, min_jerk_band and time_domain slosh more than
  // the uniform law there (worse_than_baseline). Planned alone each is acceptable; auto listed
  // them as optimal candidates.
  const PlanResult r = plan(tank(120, 80, 89.9, 40, 200, 1.2), Strategy::kAuto, quick_options());
  int worse = 0;
  for (const PlanCandidate& k : r.candidates) {
    if (k.worse_than_baseline.empty()) continue;
    ++worse;
    EXPECT_NE(k.status, SolveStatus::kOptimal) << to_string(k.strategy);
  }
  EXPECT_GE(worse, 2);
}

/// The closed-form first frequency along `side` [m] at fill h [m] (rad/s).
double omega1(double side, double h) {
  const double k = kPi / side;
  return std::sqrt(9.81 * k * std::tanh(k * h));
}

TEST(RectangularAxisDesign, NotchMovesContinuouslyAsASquareTanksSidesPart) {
  // 80 x 80 mm at 45 degrees, 35 mm of water, 100 mm in 1 s: both directions share one first
  // frequency. Two zeros a hair apart force a double zero that one zero does not, so the law
  // jumped between 80 mm (one zero: eta_rest 0.339 mm) and 80.0003 mm (0.073 mm). Now the notch
  // is made double below a 0.1 % gap, continuously, and the law moves smoothly with the width.
  std::vector<PlanResult> sweep;
  const std::vector<double> widths{80.0,  80.00001, 80.0001, 80.0003, 80.001, 80.01,
                                   80.03, 80.06,    80.1,    80.2,    80.5,   81.0};
  for (double w : widths) {
    sweep.push_back(plan(tank(80, w, 45.0, 35, 100, 1.0), Strategy::kNotch, quick_options()));
    ASSERT_EQ(sweep.back().status, SolveStatus::kOptimal) << w << ": " << sweep.back().message;
  }
  for (std::size_t k = 1; k < sweep.size(); ++k) {
    const PlanResult &a = sweep[k - 1], &b = sweep[k];
    EXPECT_NEAR(b.prediction.linear.rest.value, a.prediction.linear.rest.value,
                0.03 * a.prediction.linear.rest.value)
        << widths[k];
    for (std::size_t i = 0; i < 7; ++i) {
      EXPECT_NEAR((*b.durations)[i], (*a.durations)[i], 5e-3) << widths[k] << " " << i;
    }
  }
  EXPECT_NE(sweep.front().message.find("made double as the two lie within 0.1 % of each other"),
            std::string::npos)
      << sweep.front().message;
  EXPECT_EQ(sweep.back().message.find("made double"), std::string::npos) << sweep.back().message;
  // The square tank's law by quadrature: a zero at the common frequency and X equal (to the
  // notch's depth) 0.05 % on either side of it, so |X| there is a double zero's, far below a
  // single zero's slope would leave.
  const PlanResult& square = sweep.front();
  const double w1 = square.rectangular->along_length.omega1();
  EXPECT_NEAR(w1, omega1(0.08, 0.035), 1e-3 * w1);
  const MotionLaw uniform = SevenSegmentLaw(uniform_durations(1.0), 0.1).law();
  double x_ref = 0.0;
  for (int k = 0; k <= 200; ++k) {
    x_ref = std::max(x_ref, std::abs(test::quadrature_of(uniform, w1 * (0.85 + 0.3 * k / 200.0))));
  }
  EXPECT_LT(std::abs(test::quadrature_of(square.law, w1)), 2e-6 * x_ref);
  const std::complex<double> lo = test::quadrature_of(square.law, w1 * (1.0 - 5e-4));
  const std::complex<double> hi = test::quadrature_of(square.law, w1 * (1.0 + 5e-4));
  EXPECT_LT(std::abs(hi - lo), 3e-6 * x_ref);
  // The single zero the exactly square tank used to get had a slope 1e3 times that.
  EXPECT_LT(std::abs(hi), 1e-4 * x_ref);
}

}  // namespace test_rectangular_axis_design
}  // namespace slosh
