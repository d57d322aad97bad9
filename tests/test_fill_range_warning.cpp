// A fill height range whose low end leaves the models (a cylinder's shallow-liquid regime, a
// rectangular tank's fill below its nonlinear model's depth range) while the nominal fill is
// within them: the range scales the nominal fill's models, so the plan says that its figures near
// that end are not a model of that fill.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "slosh/core/model/format.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "slosh/core/warning.hpp"

namespace slosh {
namespace test_fill_range_warning {

constexpr const char* kTail =
    "; the range's figures are the nominal fill's models with their frequencies and damping "
    "scaled (SPEC §10), so the worst case and the robustness figures near that end are not "
    "reliable";

Format cup(double orientation, double fill) {
  Format f = thesis_format();
  f.container.rectangular = RectangularTank{0.12, 0.08, orientation};
  f.fill_height = fill;
  f.stroke = 0.2;
  f.motion_time = 1.2;
  return f;
}

/// The texts of `r`'s fill_range_beyond_models warnings.
std::vector<std::string> range_warnings(const PlanResult& r) {
  std::vector<std::string> out;
  for (const Warning& w : r.warnings) {
    if (w.kind == WarningKind::kFillRangeBeyondModels) out.push_back(w.text);
  }
  return out;
}

PlanResult plan_with_fills(const Format& f, double lo, double hi) {
  PlanOptions o;
  o.uncertainty.fill_height = std::array<double, 2>{lo, hi};
  const PlanResult r = plan(f, Strategy::kBaseline, o);
  EXPECT_TRUE(r.usable()) << r.message;
  return r;
}

std::string ratio(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", v);
  return text;
}

TEST(FillRangeWarning, ARectangularTanksRangeBelowItsDepthRatioIsSaidPerExcitedDirection) {
  // Along L (0 degrees): 20 / 120 = 0.167 < 0.24; W is not excited (20 / 80 would be too).
  EXPECT_EQ(range_warnings(plan_with_fills(cup(0.0, 0.04), 0.02, 0.05)),
            std::vector<std::string>{"fill height range 20 to 50 mm: at its low end fill "
                                     "height / length = " +
                                     ratio(0.02 / 0.12) +
                                     " is below 0.24 (shallow fill), where the rectangular "
                                     "nonlinear model does not hold" +
                                     kTail});
  // Turned by 30 degrees both are excited; 24 mm: 0.2 along L, 0.3 along W (within).
  EXPECT_EQ(range_warnings(plan_with_fills(cup(30.0, 0.04), 0.024, 0.05)),
            std::vector<std::string>{"fill height range 24 to 50 mm: at its low end fill "
                                     "height / length = " +
                                     ratio(0.024 / 0.12) +
                                     " is below 0.24 (shallow fill), where the rectangular "
                                     "nonlinear model does not hold" +
                                     kTail});
  // 15 mm: both below.
  EXPECT_EQ(range_warnings(plan_with_fills(cup(30.0, 0.04), 0.015, 0.05)),
            std::vector<std::string>{"fill height range 15 to 50 mm: at its low end fill "
                                     "height / length = " +
                                     ratio(0.015 / 0.12) +
                                     " and fill height / width = " + ratio(0.015 / 0.08) +
                                     " are below 0.24 (shallow fill), where the rectangular "
                                     "nonlinear model does not hold" +
                                     kTail});
  // A range within the models says nothing; nor does one whose nominal fill is already out of
  // them (the plan's own warnings say that).
  EXPECT_TRUE(range_warnings(plan_with_fills(cup(0.0, 0.04), 0.0289, 0.05)).empty());
  EXPECT_TRUE(range_warnings(plan_with_fills(cup(0.0, 0.025), 0.02, 0.03)).empty());
}

TEST(FillRangeWarning, ACylindersRangeInTheShallowLiquidRegimeIsSaid) {
  Format f = thesis_format();  // R 48.5 mm, fill 82 mm
  const double R = f.container.radius;
  EXPECT_EQ(range_warnings(plan_with_fills(f, 0.01, 0.09)),
            std::vector<std::string>{"fill height range 10 to 90 mm: at its low end the fill "
                                     "ratio h/R = " +
                                     ratio(0.01 / R) +
                                     " is below 0.3, the shallow-liquid regime, which is not "
                                     "modelled" +
                                     kTail});
  EXPECT_TRUE(range_warnings(plan_with_fills(f, 0.3 * R, 0.09)).empty());
}

// The ratio is written with as many decimals as show it below the limit, the range as given; a
// ratio at the limit in decimal (19.2 / 80, 0.23999999999999996 once in m) is within the model.
TEST(FillRangeWarning, ARatioJustBelowTheLimitIsNotRoundedOntoIt) {
  const std::vector<std::string> w =
      range_warnings(plan_with_fills(cup(0.0, 0.04), 0.12 * 0.23996, 0.05));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w.front().rfind("fill height range 28.7952 to 50 mm: at its low end fill height / "
                            "length = 0.23996 is below 0.24",
                            0),
            0u)
      << w.front();
  EXPECT_TRUE(range_warnings(plan_with_fills(cup(90.0, 0.04), 0.0192, 0.05)).empty());
  Format cylinder = thesis_format();
  cylinder.container.radius = 0.05;
  EXPECT_TRUE(range_warnings(plan_with_fills(cylinder, 0.015, 0.09)).empty());
  const std::vector<std::string> near = range_warnings(plan_with_fills(cylinder, 0.01499, 0.09));
  ASSERT_EQ(near.size(), 1u);
  EXPECT_EQ(near.front().rfind("fill height range 14.99 to 90 mm: at its low end the fill ratio "
                               "h/R = 0.2998 is below 0.3",
                               0),
            0u)
      << near.front();
}

}  // namespace test_fill_range_warning
}  // namespace slosh
