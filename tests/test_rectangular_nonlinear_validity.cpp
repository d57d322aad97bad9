// The range of the rectangular nonlinear model: every limit's exact sentence, the order of the
// checks, the boundaries of each limit, and that only the excited directions are judged.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/response/rectangular_nonlinear_validity.hpp"

namespace slosh {
namespace test_rectangular_nonlinear_validity {

using Limit = RectangularNonlinearLimit;

RectangularModel tank(double length, double width, double orientation_deg, double h) {
  return make_rectangular_model({length, width, orientation_deg}, h, thesis_format().fluid);
}

TEST(RectangularNonlinearValidity, FiniteDepthInRangeIsValid) {
  const auto v = rectangular_nonlinear_validity(tank(0.1, 0.08, 30.0, 0.045));
  EXPECT_TRUE(v.valid);
  EXPECT_EQ(v.limit, Limit::kNone);
  EXPECT_EQ(v.reason, "");
}

TEST(RectangularNonlinearValidity, ShallowFillIsRefusedWithItsSentence) {
  const auto v = rectangular_nonlinear_validity(tank(0.1, 0.08, 0.0, 0.02));
  EXPECT_FALSE(v.valid);
  EXPECT_EQ(v.limit, Limit::kShallowDepth);
  EXPECT_EQ(v.axis, TankAxis::kLength);
  EXPECT_EQ(v.reason,
            "rectangular nonlinear model not valid along the length: fill height / length = "
            "0.200 is below 0.24 (shallow fill, outside the Moiseev-type modal theory of "
            "Faltinsen et al. 2000); linear model used");
}

TEST(RectangularNonlinearValidity, SteepWaveNearTheCriticalDepthIsRefusedWithItsSentence) {
  // h / W = 0.0333 / 0.1 = 0.333: c = 0.0055, so the fifth-order term 0.28 (k1 eta)^2 exceeds
  // it from k1 eta = 0.140 (eta = 4.45 mm); the length (h / L = 0.222) is not excited at 90 deg.
  const RectangularModel m = tank(0.15, 0.1, 90.0, 0.0333);
  EXPECT_TRUE(rectangular_nonlinear_validity(m).valid) << "no height, no critical-depth check";
  EXPECT_TRUE(rectangular_nonlinear_validity(m, {0.0, 0.0044}).valid);
  const auto v = rectangular_nonlinear_validity(m, {0.0, 0.0045});
  EXPECT_FALSE(v.valid);
  EXPECT_EQ(v.limit, Limit::kCriticalDepth);
  EXPECT_EQ(v.axis, TankAxis::kWidth);
  EXPECT_EQ(v.reason,
            "rectangular nonlinear model not valid along the width: fill height / width = 0.333 "
            "is near the critical depth 0.3368, where at the nonlinear model's wall height 4.5 mm "
            "(k1 eta = 0.14) "
            "the fifth-order frequency shift the model leaves out exceeds its third-order one; "
            "linear model used");
}

TEST(RectangularNonlinearValidity, DepthLimitsHaveTheirStatedBoundaries) {
  const double L = 0.1;
  auto limit = [L](double ratio, double steepness) {
    const double eta = steepness * L / std::numbers::pi;
    return rectangular_nonlinear_validity(tank(L, L, 0.0, ratio * L), {eta, 0.0}).limit;
  };
  EXPECT_EQ(limit(0.2399, 0.0), Limit::kShallowDepth);
  EXPECT_EQ(limit(0.2401, 0.0), Limit::kNone);
  EXPECT_EQ(limit(3.0, 0.29), Limit::kNone);
  // At the critical depth itself any wave is refused, no wave is not.
  EXPECT_EQ(limit(kRectangularCriticalDepthRatio, 0.0), Limit::kNone);
  EXPECT_EQ(limit(kRectangularCriticalDepthRatio, 0.01), Limit::kCriticalDepth);
  // At the steepness limit 0.3 the band is 0.3208 < h / L < 0.3575, where |c| < 0.28 * 0.09
  // (c re-typed from Tadjbakhsh & Keller 1960); a gentler wave narrows it.
  auto c = [](double ratio) {
    const double t2 = std::pow(std::tanh(std::numbers::pi * ratio), 2);
    return (9 / (t2 * t2) - 12 / t2 - 3 - 2 * t2) / 64;
  };
  EXPECT_NEAR(c(kRectangularCriticalDepthRatio), 0.0, 1e-5);
  EXPECT_GT(std::abs(c(0.3200)), 0.0252);
  EXPECT_LT(std::abs(c(0.3215)), 0.0252);
  EXPECT_LT(std::abs(c(0.3570)), 0.0252);
  EXPECT_GT(std::abs(c(0.3580)), 0.0252);
  EXPECT_EQ(limit(0.3200, 0.3), Limit::kNone);
  EXPECT_EQ(limit(0.3215, 0.3), Limit::kCriticalDepth);
  EXPECT_EQ(limit(0.3570, 0.3), Limit::kCriticalDepth);
  EXPECT_EQ(limit(0.3580, 0.3), Limit::kNone);
  for (double ratio : {0.3215, 0.3570}) EXPECT_EQ(limit(ratio, 0.1), Limit::kNone) << ratio;
}

TEST(RectangularNonlinearValidity, SteepWaveIsRefusedWithItsSentence) {
  // L = 0.1: k1 = 31.4 /m, the limit 0.3 is a wall height of 9.55 mm.
  const RectangularModel m = tank(0.1, 0.08, 0.0, 0.05);
  EXPECT_TRUE(rectangular_nonlinear_validity(m, {0.0095, 0.0}).valid);
  const auto v = rectangular_nonlinear_validity(m, {0.0100, 0.0});
  EXPECT_FALSE(v.valid);
  EXPECT_EQ(v.limit, Limit::kSteepness);
  EXPECT_EQ(v.reason,
            "rectangular nonlinear model not valid along the length: the nonlinear model's wall "
            "height 10.0 mm is a "
            "wave steepness k1 eta = 0.31 above 0.30 (beyond the third-order theory); linear "
            "model used");
}

TEST(RectangularNonlinearValidity, NonFiniteHeightIsADivergence) {
  const RectangularModel m = tank(0.1, 0.08, 45.0, 0.05);
  const auto v =
      rectangular_nonlinear_validity(m, {0.001, std::numeric_limits<double>::quiet_NaN()});
  EXPECT_FALSE(v.valid);
  EXPECT_EQ(v.limit, Limit::kDiverged);
  EXPECT_EQ(v.axis, TankAxis::kWidth);
  EXPECT_EQ(v.reason, "rectangular nonlinear model diverges along the width; linear model used");
  // A NaN in the rest window of one direction survives wave_heights.
  RectangularPeaks p;
  p.along_width.motion.value = 0.002;
  p.along_width.rest.value = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(std::isfinite(wave_heights(p).along_width));
  p.along_length.motion.value = 0.003;
  p.along_length.rest.value = 0.004;
  EXPECT_EQ(wave_heights(p).along_length, 0.004);
}

TEST(RectangularNonlinearValidity, OnlyTheExcitedDirectionsAreJudgedLengthFirst) {
  // h / L = 0.2 (shallow), h / W = 0.5 (fine).
  const double h = 0.02;
  EXPECT_EQ(rectangular_nonlinear_validity(tank(0.1, 0.04, 90.0, h)).limit, Limit::kNone);
  EXPECT_EQ(rectangular_nonlinear_validity(tank(0.1, 0.04, -90.0, h)).limit, Limit::kNone);
  EXPECT_EQ(rectangular_nonlinear_validity(tank(0.1, 0.04, 180.0, h)).limit, Limit::kShallowDepth);
  // Both excited and both failing: the length is reported.
  const auto both = rectangular_nonlinear_validity(tank(0.1, 0.09, 10.0, h));
  EXPECT_EQ(both.axis, TankAxis::kLength);
  // A steep wave along an unexcited direction is ignored.
  EXPECT_TRUE(rectangular_nonlinear_validity(tank(0.1, 0.04, 0.0, 0.05), {0.001, 1.0}).valid);
}

TEST(RectangularNonlinearValidity, BothDirectionsOutOfRangeAreBothNamedInOneSentence) {
  // A square 100 x 100 tank at 45 deg in 20 mm: h / L = h / W = 0.200, both shallow.
  const auto both = rectangular_nonlinear_validity(tank(0.1, 0.1, 45.0, 0.02));
  EXPECT_FALSE(both.valid);
  EXPECT_EQ(both.limit, Limit::kShallowDepth);
  EXPECT_EQ(both.reason,
            "rectangular nonlinear model not valid along the length: fill height / length = "
            "0.200 is below 0.24 (shallow fill, outside the Moiseev-type modal theory of "
            "Faltinsen et al. 2000); rectangular nonlinear model not valid along the width: fill "
            "height / width = 0.200 is below 0.24 (shallow fill, outside the Moiseev-type modal "
            "theory of Faltinsen et al. 2000); linear model used");
  // Different limits on the two sides: each sentence says its own (length steep, width shallow).
  const auto mixed = rectangular_nonlinear_validity(tank(0.1, 0.2, 30.0, 0.045), {0.01, 0.0});
  EXPECT_EQ(mixed.limit, Limit::kSteepness);
  EXPECT_NE(mixed.reason.find("along the length: the nonlinear model's wall height 10.0 mm"),
            std::string::npos)
      << mixed.reason;
  EXPECT_NE(mixed.reason.find("; rectangular nonlinear model not valid along the width: fill "
                              "height / width = 0.225 is below 0.24"),
            std::string::npos)
      << mixed.reason;
}

}  // namespace test_rectangular_nonlinear_validity
}  // namespace slosh
