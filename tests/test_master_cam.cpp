// Master-axis cam tables (core): every row against the time-based law through the master speed
// w = (end - start) / T, the law evaluated at t = (theta - start) / w by its own closed form
// (MotionLaw::at) and, for a quintic law, by the polynomial written here; the derivatives per
// master unit against central differences of the position column; exact dwell rows before the start
// and after the end; the rows (grid, start, end and period exactly); and each refusal of an axis.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "slosh/core/law/cam_table.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/law/seven_segment.hpp"

namespace slosh {
namespace test_master_cam {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The master positions of a table as the test expects them: k * step below the period (a point
/// within 1e-9 step of start, end or period replaced by it), plus start, end and period.
std::vector<double> expected_positions(const MasterAxis& m) {
  std::vector<double> out;
  const double tol = 1e-9 * m.step;
  const std::array<double, 3> anchors{m.start, m.end, m.period};
  for (int k = 0;; ++k) {
    double x = k * m.step;
    if (x > m.period + tol) break;
    for (const double a : anchors) {
      if (std::abs(x - a) <= tol) x = a;
    }
    out.push_back(x);
  }
  for (const double a : anchors) {
    if (std::find(out.begin(), out.end(), a) == out.end()) out.push_back(a);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// Checks every row of `table` against `law` through the master speed; `v_scale` etc. are the
/// magnitudes of the law's velocity, acceleration and jerk (for the tolerances).
void expect_rows_follow_the_law(const std::vector<MasterCamSample>& table, const MotionLaw& law,
                                double stroke, const MasterAxis& m, double rel = 1e-12) {
  const std::vector<double> thetas = expected_positions(m);
  ASSERT_EQ(table.size(), thetas.size());
  const double T = law.duration();
  const double w = (m.end - m.start) / T;  // master units per second
  const KinematicSummary peaks = law.summary();
  const double a_scale = std::max(peaks.a_peak_positive, peaks.a_peak_negative);
  for (std::size_t k = 0; k < table.size(); ++k) {
    const MasterCamSample& row = table[k];
    ASSERT_EQ(row.master, thetas[k]) << "row " << k;
    const double theta = thetas[k];
    if (theta < m.start) {
      // Dwell at 0 before the start: exactly zero.
      EXPECT_EQ(row.position, 0.0) << theta;
      EXPECT_EQ(row.velocity, 0.0) << theta;
      EXPECT_EQ(row.acceleration, 0.0) << theta;
      EXPECT_EQ(row.jerk, 0.0) << theta;
      continue;
    }
    if (theta >= m.end) {
      // At and after the end: at rest on the stroke exactly.
      EXPECT_EQ(row.position, stroke) << theta;
      EXPECT_EQ(row.velocity, 0.0) << theta;
      EXPECT_EQ(row.acceleration, 0.0) << theta;
      EXPECT_EQ(row.jerk, 0.0) << theta;
      continue;
    }
    const double t = (theta - m.start) / w;
    const KinematicState s = law.at(t);
    EXPECT_NEAR(row.position, s.position, rel * stroke) << theta;
    EXPECT_NEAR(row.velocity * w, s.velocity, rel * peaks.v_peak) << theta;
    EXPECT_NEAR(row.acceleration * w * w, s.acceleration, rel * a_scale) << theta;
    EXPECT_NEAR(row.jerk * w * w * w, s.jerk, rel * peaks.j_peak) << theta;
  }
}

TEST(MasterCamTable, SevenSegmentLawFollowsTheTimeLawThroughTheMasterSpeed) {
  // The example: a 360-degree cycle, the motion from 30 to 210 degrees.
  const Durations d{0.2784, 0.0787, 0.1429, 0.0, 0.1429, 0.0787, 0.2784};
  const double stroke = 0.8;
  const SevenSegmentLaw law(d, stroke);
  const MasterAxis m{360.0, 30.0, 210.0, 1.0};
  const std::vector<MasterCamSample> table = sample_master_cam_table(law.law(), stroke, m);
  ASSERT_EQ(table.size(), 361u);
  expect_rows_follow_the_law(table, law.law(), stroke, m);
  // Rows land exactly on the start, the end and the period.
  EXPECT_EQ(table[30].master, 30.0);
  EXPECT_EQ(table[210].master, 210.0);
  EXPECT_EQ(table[210].position, stroke);
  EXPECT_EQ(table.back().master, 360.0);
  // The start row carries the first ramp's jerk per master unit^3 (the segment starting there).
  const double w = 180.0 / law.motion_time();
  EXPECT_NEAR(table[30].jerk * w * w * w, law.jerks()[0], 1e-12 * law.jerks()[0]);
  EXPECT_EQ(table[29].jerk, 0.0);
  // The last moving row is one degree before the end.
  EXPECT_GT(table[209].velocity, 0.0);
  EXPECT_LT(table[209].position, stroke);
}

TEST(MasterCamTable, QuinticLawMatchesItsPolynomialPerMasterUnit) {
  // s = S (10u^3 - 15u^4 + 6u^5), u = (theta - start) / (end - start): the derivatives per
  // master unit are those of the polynomial in u divided by (end - start)^n, written here.
  const double S = 0.45, T = 0.7;
  const MotionLaw law = make_poly5_law(S, T);
  const MasterAxis m{400.0, 100.0, 300.0, 0.5};
  const std::vector<MasterCamSample> table = sample_master_cam_table(law, S, m);
  const double L = m.end - m.start;
  ASSERT_EQ(table.size(), 801u);
  for (const MasterCamSample& row : table) {
    const double u = std::clamp((row.master - m.start) / L, 0.0, 1.0);
    const double s = S * u * u * u * (10 - 15 * u + 6 * u * u);
    const double ds = S / L * 30 * u * u * (1 - u) * (1 - u);
    const double d2s = S / (L * L) * 60 * u * (1 - 3 * u + 2 * u * u);
    const bool moving = row.master >= m.start && row.master < m.end;
    const double d3s = moving ? S / (L * L * L) * 60 * (1 - 6 * u + 6 * u * u) : 0.0;
    EXPECT_NEAR(row.position, s, 1e-13 * S) << row.master;
    EXPECT_NEAR(row.velocity, ds, 1e-13 * 1.875 * S / L) << row.master;
    EXPECT_NEAR(row.acceleration, d2s, 1e-12 * 5.8 * S / (L * L)) << row.master;
    EXPECT_NEAR(row.jerk, d3s, 1e-12 * 60 * S / (L * L * L)) << row.master;
  }
}

TEST(MasterCamTable, DerivativesPerMasterUnitAreThoseOfThePositionColumn) {
  // Central differences of the position over the master axis (not through the time law).
  const Durations d{0.05, 0.1, 0.07, 0.2, 0.06, 0.12, 0.08};
  const double stroke = 0.3;
  const SevenSegmentLaw law(d, stroke);
  const MasterAxis m{1.0, 0.25, 0.75, 1e-4};  // a master in revolutions
  const std::vector<MasterCamSample> table = sample_master_cam_table(law.law(), stroke, m);
  ASSERT_EQ(table.size(), 10001u);
  const double h = m.step;
  double v_max = 0.0, a_max = 0.0;
  for (const MasterCamSample& r : table) {
    v_max = std::max(v_max, r.velocity);
    a_max = std::max(a_max, std::abs(r.acceleration));
  }
  for (std::size_t k = 2600; k + 2600 < table.size(); k += 37) {
    const double dv = (table[k + 1].position - table[k - 1].position) / (2 * h);
    EXPECT_NEAR(table[k].velocity, dv, 1e-5 * v_max) << table[k].master;
    const double da = (table[k + 1].velocity - table[k - 1].velocity) / (2 * h);
    EXPECT_NEAR(table[k].acceleration, da, 5e-3 * a_max) << table[k].master;
  }
  // The peak velocity per master unit is the law's peak over the master speed.
  const double w = (m.end - m.start) / law.motion_time();
  EXPECT_NEAR(v_max, law.v_peak() / w, 1e-6 * law.v_peak() / w);
}

TEST(MasterCamTable, RandomLawsAndAxesFollowTheTimeLaw) {
  std::mt19937 rng(4242u);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const std::array<double, 5> periods{360.0, 1.0, 36000.0, 100.0, 2.0 * 3.141592653589793};
  for (int trial = 0; trial < 60; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    Durations d{};
    for (std::size_t i = 0; i < 7; ++i) {
      d[i] = i % 2 == 0 ? uniform(0.02, 0.3) : (uniform(0, 1) < 0.3 ? 0.0 : uniform(0.0, 0.3));
    }
    const double stroke = uniform(0.05, 1.2);
    const SevenSegmentLaw law(d, stroke);
    const double P = periods[static_cast<std::size_t>(trial) % periods.size()];
    const double a = uniform(0.0, 0.5) * P;
    const double b = uniform(0.55, 1.0) * P;
    const MasterAxis m{P, a, trial % 4 == 0 ? P : b, P / uniform(90.0, 900.0)};
    expect_rows_follow_the_law(sample_master_cam_table(law.law(), stroke, m), law.law(), stroke, m,
                               1e-11);
    if (::testing::Test::HasFailure()) return;
  }
}

TEST(MasterCamTable, OffGridStartEndAndPeriodGetRowsOfTheirOwn) {
  const MotionLaw law = make_cycloidal_law(0.2, 0.5);
  const MasterAxis m{360.5, 30.5, 210.25, 1.0};
  const std::vector<MasterCamSample> table = sample_master_cam_table(law, 0.2, m);
  // 0..360 (361 points), plus 30.5, 210.25 and 360.5.
  ASSERT_EQ(table.size(), 364u);
  EXPECT_EQ(table[30].master, 30.0);
  EXPECT_EQ(table[31].master, 30.5);
  EXPECT_EQ(table[31].position, 0.0);
  EXPECT_EQ(table[32].master, 31.0);
  EXPECT_GT(table[32].position, 0.0);
  EXPECT_EQ(table[211].master, 210.0);
  EXPECT_LT(table[211].position, 0.2);
  EXPECT_EQ(table[212].master, 210.25);
  EXPECT_EQ(table[212].position, 0.2);
  EXPECT_EQ(table.back().master, 360.5);
  EXPECT_EQ(table[table.size() - 2].master, 360.0);
  expect_rows_follow_the_law(table, law, 0.2, m);
  EXPECT_FALSE(master_grid_is_equidistant(m));
  EXPECT_TRUE(master_grid_is_equidistant({360.0, 30.0, 210.0, 1.0}));
  // A step of 0.1 reaches 30 and 210 only up to rounding (300 * 0.1 = 30.000000000000004): the
  // rows are the exact values, not one more row beside them.
  const MasterAxis tenth{360.0, 30.0, 210.0, 0.1};
  EXPECT_TRUE(master_grid_is_equidistant(tenth));
  const std::vector<double> rows = master_positions(tenth);
  ASSERT_EQ(rows.size(), 3601u);
  EXPECT_EQ(rows[300], 30.0);
  EXPECT_EQ(rows[2100], 210.0);
  EXPECT_EQ(rows.back(), 360.0);
  // The motion to the end of the cycle, from its very start.
  const MasterAxis whole{360.0, 0.0, 360.0, 45.0};
  const std::vector<MasterCamSample> all = sample_master_cam_table(law, 0.2, whole);
  ASSERT_EQ(all.size(), 9u);
  EXPECT_EQ(all.front().position, 0.0);
  EXPECT_GT(all.front().jerk, 0.0);  // the cycloid's jerk at t = 0, per master unit^3
  EXPECT_EQ(all.back().position, 0.2);
  // A step longer than the motion: rows at 0, the start, the end and the period only.
  const std::vector<double> coarse = master_positions({360.0, 30.0, 210.0, 500.0});
  EXPECT_EQ(coarse, (std::vector<double>{0.0, 30.0, 210.0, 360.0}));
}

TEST(MasterCamTable, EachMemberIsRefusedWithItsRange) {
  struct Case {
    MasterAxis axis;
    MasterAxisInput input;
    InputBounds bounds;
    const char* allowed;
  };
  const std::vector<Case> cases{
      {{0.0, 0.0, 1.0, 1.0}, MasterAxisInput::kPeriod, {1e-6, kInf, false, false}, ">= 1e-06"},
      {{-360.0, 0.0, 1.0, 1.0}, MasterAxisInput::kPeriod, {1e-6, kInf, false, false}, ">= 1e-06"},
      {{kInf, 0.0, 1.0, 1.0}, MasterAxisInput::kPeriod, {1e-6, kInf, false, false}, ">= 1e-06"},
      {{std::nan(""), 0.0, 1.0, 1.0},
       MasterAxisInput::kPeriod,
       {1e-6, kInf, false, false},
       ">= 1e-06"},
      {{360.0, -1.0, 210.0, 1.0}, MasterAxisInput::kStart, {0.0, 360.0, false, true}, "[0, 360)"},
      {{360.0, 360.0, 210.0, 1.0}, MasterAxisInput::kStart, {0.0, 360.0, false, true}, "[0, 360)"},
      {{360.0, 30.0, 30.0, 1.0}, MasterAxisInput::kEnd, {30.0, 360.0, true, false}, "(30, 360]"},
      {{360.0, 250.0, 210.0, 1.0},
       MasterAxisInput::kEnd,
       {250.0, 360.0, true, false},
       "(250, 360]"},
      {{360.0, 30.0, 360.5, 1.0}, MasterAxisInput::kEnd, {30.0, 360.0, true, false}, "(30, 360]"},
      {{360.0, 30.0, 210.0, 0.0}, MasterAxisInput::kStep, {0.0, kInf, true, false}, "> 0"},
      {{360.0, 30.0, 210.0, -1.0}, MasterAxisInput::kStep, {0.0, kInf, true, false}, "> 0"},
      {{360.0, 30.0, 210.0, std::nan("")}, MasterAxisInput::kStep, {0.0, kInf, true, false}, "> 0"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.allowed) + " " + std::to_string(c.axis.period) + " " +
                 std::to_string(c.axis.start) + " " + std::to_string(c.axis.end) + " " +
                 std::to_string(c.axis.step));
    const auto refusal = check_master_axis(c.axis);
    ASSERT_TRUE(refusal.has_value());
    EXPECT_EQ(refusal->input, c.input);
    EXPECT_EQ(refusal->bounds.lo, c.bounds.lo);
    EXPECT_EQ(refusal->bounds.hi, c.bounds.hi);
    EXPECT_EQ(refusal->bounds.lo_open, c.bounds.lo_open);
    EXPECT_EQ(refusal->bounds.hi_open, c.bounds.hi_open);
    EXPECT_FALSE(refusal->too_many_rows);
    EXPECT_EQ(refusal->allowed(), c.allowed);
    EXPECT_THROW((void)sample_master_cam_table(make_poly5_law(0.1, 1.0), 0.1, c.axis),
                 std::invalid_argument);
  }
  const auto end = check_master_axis({360.0, 250.0, 210.0, 1.0});
  EXPECT_EQ(end->message, "master end = 210 must be finite and in (250, 360] (master units)");
  // Rows: period / step grid points plus start, end and period, at most kCamMaxSamples.
  const auto rows = check_master_axis({360.0, 30.0, 210.0, 1e-5});
  ASSERT_TRUE(rows.has_value());
  EXPECT_EQ(rows->input, MasterAxisInput::kStep);
  EXPECT_TRUE(rows->too_many_rows);
  EXPECT_DOUBLE_EQ(rows->bounds.lo, 360.0 / (10'000'000 - 3));
  EXPECT_EQ(rows->message,
            "master step = 1e-05 gives more than 10000000 rows over the master period 360: it "
            "must be >= 3.60000108e-05 (master units)");
  EXPECT_FALSE(check_master_axis({360.0, 30.0, 210.0, 3.600001081e-05}).has_value());
  EXPECT_TRUE(check_master_axis({360.0, 30.0, 210.0, 0.0018}, 200000).has_value());
  EXPECT_FALSE(check_master_axis({360.0, 30.0, 210.0, 0.001800027001}, 200000).has_value());
  // A valid axis, and a law without duration.
  EXPECT_FALSE(check_master_axis({360.0, 0.0, 360.0, 360.0}).has_value());
  EXPECT_THROW((void)sample_master_cam_table(MotionLaw(), 0.1, {360.0, 30.0, 210.0, 1.0}),
               std::invalid_argument);
}

// Regression: a master span of 1e-300 made the derivatives per master unit inf and nan. The
// shortest span is also the shortest period (the refusal named the end with the empty range
// "[1e-06, 1e-300]").
TEST(MasterCamTable, ASpanTooShortForFiniteDerivativesIsRefused) {
  MasterAxis axis;
  axis.period = 1e-300;
  axis.start = 0.0;
  axis.end = 1e-300;
  axis.step = 1e-301;
  const auto refusal = check_master_axis(axis);
  ASSERT_TRUE(refusal.has_value());
  EXPECT_EQ(refusal->input, MasterAxisInput::kPeriod);
  EXPECT_EQ(refusal->message, "master period = 1e-300 must be finite and >= 1e-06 (master units)");
  axis = MasterAxis{};
  axis.start = 30.0;
  axis.end = 30.0 + 2e-6;
  EXPECT_FALSE(check_master_axis(axis).has_value());
  axis.end = 30.0000000001;
  const auto end = check_master_axis(axis);
  ASSERT_TRUE(end.has_value());
  EXPECT_EQ(end->input, MasterAxisInput::kEnd);
  EXPECT_EQ(end->message,
            "master end = 30.0000000001 must be finite and in [30.000001, 360] (master units)");
}

// Regression in the refusals' texts: an allowed set that is empty ("[360.0000005, 360]" for
// a start 5e-7 before the period), values rounded onto their bounds ("master end = 360 is out of
// range (30, 360]" for 360.0000000001) and a denormal called "not a number".
TEST(MasterCamTable, EveryRefusalShowsAValueVisiblyOutsideANonEmptyRange) {
  struct Case {
    MasterAxis axis;
    MasterAxisInput input;
    std::string value;
    std::string allowed;
  };
  const std::vector<Case> cases{
      // A start too late for the shortest span: the start is refused with its own bound.
      {{360.0, 359.9999995, 360.0, 1.0}, MasterAxisInput::kStart, "359.9999995", "[0, 359.999999]"},
      {{1e-6, 5e-7, 1e-6, 1e-7}, MasterAxisInput::kStart, "5e-07", "[0, 0]"},
      // Enough digits that the value lies visibly outside the range.
      {{360.0, 30.0, 360.0000000001, 1.0}, MasterAxisInput::kEnd, "360.0000000001", "(30, 360]"},
      {{360.0, 30.0, 30.000000999, 1.0}, MasterAxisInput::kEnd, "30.000000999", "[30.000001, 360]"},
      {{360.0, 359.99999900000006, 360.0, 1.0},
       MasterAxisInput::kStart,
       "359.99999900000006",
       "[0, 359.999999]"},
      {{360.0, -4.9e-324, 210.0, 1.0}, MasterAxisInput::kStart, "-5e-324", "[0, 360)"},
      // A denormal is a number: the period is refused for being below the shortest span.
      {{4.9e-324, 0.0, 4.9e-324, 1.0}, MasterAxisInput::kPeriod, "5e-324", ">= 1e-06"},
      // Between the smallest step (3.600001080000324e-05) and its 10-digit text.
      {{360.0, 30.0, 210.0, 3.6000010800001e-05},
       MasterAxisInput::kStep,
       "3.6000010800001e-05",
       ">= 3.6000010800003e-05"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.value + " " + c.allowed);
    const auto refusal = check_master_axis(c.axis);
    ASSERT_TRUE(refusal.has_value());
    EXPECT_EQ(refusal->input, c.input);
    EXPECT_EQ(refusal->value_text(), c.value);
    EXPECT_EQ(refusal->allowed(), c.allowed);
    // The set is not empty and, as its text reads, leaves the value out.
    EXPECT_LE(refusal->bounds.lo, refusal->bounds.hi);
    EXPECT_THROW((void)sample_master_cam_table(make_poly5_law(0.1, 1.0), 0.1, c.axis),
                 MasterAxisError);
  }
  // A start 1 ulp below the latest one is allowed, and so is its end at the period.
  MasterAxis last{360.0, 0.0, 360.0, 1.0};
  last.start = std::nextafter(360.0 - kMinMasterSpan, 0.0);
  EXPECT_FALSE(check_master_axis(last).has_value());
}

// Regression: a master period of 1e308 (end 1e308) over a 0.5 s law overflowed the master
// speed to inf: a table of zeros, `speed_per_s: null` and "inf" in the ST header.
TEST(MasterCamTable, AMasterSpeedThatIsNotAFiniteNumberIsRefusedAtThePeriod) {
  const MotionLaw law = make_poly5_law(0.1, 0.5);
  struct Case {
    MasterAxis axis;
    std::string speed;
  };
  const std::vector<Case> cases{
      {{1e308, 0.0, 1e308, 1e306}, "inf"},
      {{1.7e308, 0.0, 1.7e308, 1e306}, "inf"},
      {{1e31, 0.0, 1e30, 1e29}, "2e+30"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.speed);
    ASSERT_FALSE(check_master_axis(c.axis).has_value());  // the axis alone is fine
    const auto refusal = check_master_speed(c.axis, law.duration());
    ASSERT_TRUE(refusal.has_value());
    EXPECT_EQ(refusal->input, MasterAxisInput::kPeriod);
    EXPECT_EQ(refusal->value, c.axis.period);
    ASSERT_TRUE(refusal->speed.has_value());
    EXPECT_EQ(refusal->allowed(), "[1e-30, 1e+30]");
    EXPECT_EQ(refusal->message,
              "master speed (master end - master start) / motion time = " + c.speed +
                  " master units/s (master period " + master_value_text(c.axis.period) +
                  ", motion time 0.5 s) must be finite and in [1e-30, 1e+30] master units/s");
    try {
      (void)sample_master_cam_table(law, 0.1, c.axis);
      ADD_FAILURE() << "not refused";
    } catch (const MasterAxisError& e) {
      EXPECT_EQ(e.refusal().input, MasterAxisInput::kPeriod);
      EXPECT_TRUE(e.refusal().speed.has_value());
    }
  }
  // Just inside: 5e29 over 0.5 s is 1e30 master units/s, and every cell is finite.
  const MasterAxis fast{5e29, 0.0, 5e29, 5e27};
  EXPECT_FALSE(check_master_speed(fast, 0.5).has_value());
  for (const MasterCamSample& row : sample_master_cam_table(law, 0.1, fast)) {
    for (const double v : {row.master, row.position, row.velocity, row.acceleration, row.jerk}) {
      EXPECT_TRUE(std::isfinite(v));
    }
  }
  EXPECT_TRUE(check_master_speed({1e-6, 0.0, 1e-6, 1e-8}, 1e25).has_value());  // too slow
}

}  // namespace test_master_cam
}  // namespace slosh
