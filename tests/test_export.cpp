// Cam tables: `sample_cam_table` against a piecewise-constant-jerk integration coded here (seeded
// random laws and cycles, samples on switch times, the end on the first cycle at or after T), and
// `slosh export` end to end with the real binary: a notch plan's cam table against the core law
// and a central difference, the 7-segment table's kinematic identities, a poly5 law against its
// closed form, the cache, and the exit codes and messages of bad input.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/core/law/cam_table.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "support/fixtures.hpp"
#include "support/process.hpp"
#include "support/reference_seven_segment.hpp"

namespace slosh {
namespace test_export {

using nlohmann::json;
namespace fs = std::filesystem;
using test::read_file;
using test::run_slosh;
using test::RunResult;
using test::TempDir;
using test::write_file;

// ---------------------------------------------------------------------------------------------
// The reference law: tests/support/reference_seven_segment.hpp.
using Reference7 = test::ReferenceSevenSegment;
using State = test::LawState;

/// The number of cycles: the first k with k * period >= T (within 1e-12 s), counted up.
std::size_t expected_cycles(double T, double period) {
  std::size_t k = 0;
  while (static_cast<double>(k) * period < T - 1e-12) ++k;
  return k;
}

void expect_samples_match(const std::vector<CamSample>& table, const Reference7& ref, double stroke,
                          double period, double v_scale) {
  const std::size_t n = expected_cycles(ref.T(), period);
  ASSERT_EQ(table.size(), n + 1);
  const double a_scale = std::max(ref.A(), ref.B());
  const double j_scale = ref.max_jerk();
  for (std::size_t k = 0; k < table.size(); ++k) {
    const CamSample& got = table[k];
    // k x period up to its rounding (the sample holds the decimal k x cycle: the test below).
    const double t = got.t;
    ASSERT_NEAR(t, static_cast<double>(k) * period, 4e-16 * static_cast<double>(k) * period)
        << "sample " << k;
    const State want = ref.at(t);
    EXPECT_NEAR(got.position, want.s, 1e-11 * stroke) << "t = " << t;
    EXPECT_NEAR(got.velocity, want.v, 1e-11 * v_scale) << "t = " << t;
    EXPECT_NEAR(got.acceleration, want.a, 1e-11 * a_scale) << "t = " << t;
    EXPECT_NEAR(got.jerk, want.j, 1e-11 * j_scale) << "t = " << t;
  }
  // The last sample is on the stroke exactly, at rest; the one before is still moving.
  EXPECT_EQ(table.back().position, stroke);
  EXPECT_EQ(table.back().velocity, 0.0);
  EXPECT_EQ(table.back().acceleration, 0.0);
  EXPECT_EQ(table.back().jerk, 0.0);
  EXPECT_GE(table.back().t, ref.T() - 1e-12);
  if (table.size() >= 2) {
    EXPECT_LT(table[table.size() - 2].t, ref.T() - 1e-12);
  }
}

TEST(CamTable, RandomLawsMatchAnIndependentIntegration) {
  std::mt19937 rng(7301u);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const std::array<double, 7> periods{1e-3, 5e-4, 2e-3, 2.5e-4, 1.7e-3, 3.3e-3, 1e-4};
  for (int trial = 0; trial < 300; ++trial) {
    Durations d{};
    for (std::size_t i = 0; i < 7; ++i) {
      const bool ramp = i % 2 == 0;
      d[i] = ramp ? uniform(0.02, 0.3) : (uniform(0, 1) < 0.3 ? 0.0 : uniform(0.0, 0.4));
    }
    const double stroke = uniform(0.1, 1.5);
    const double period = periods[static_cast<std::size_t>(trial) % periods.size()];
    SCOPED_TRACE("trial " + std::to_string(trial));
    const Reference7 ref(d, stroke);
    const SevenSegmentLaw law(d, stroke);
    // The core's plateau levels and jerks agree with the rebuilt law.
    EXPECT_NEAR(law.A(), ref.A(), 1e-12 * ref.A());
    EXPECT_NEAR(law.B(), ref.B(), 1e-12 * ref.B());
    for (std::size_t i = 0; i < 7; ++i) {
      EXPECT_NEAR(law.jerks()[i], ref.jerk(i), 1e-12 * ref.max_jerk()) << i;
    }
    const std::vector<CamSample> table = sample_cam_table(law.law(), stroke, period);
    expect_samples_match(table, ref, stroke, period, law.v_peak());
    if (::testing::Test::HasFailure()) return;
  }
}

TEST(CamTable, SamplesOnSwitchTimesTakeTheJerkOfTheStartingSegment) {
  const double period = 0.01;
  const std::array<Durations, 3> cases{
      Durations{0.08, 0.12, 0.06, 0.0, 0.1, 0.05, 0.09},
      Durations{0.05, 0.0, 0.07, 0.11, 0.05, 0.02, 0.1},
      Durations{0.1, 0.3, 0.2, 0.1, 0.1, 0.0, 0.2},
  };
  for (const Durations& d : cases) {
    const double stroke = 0.4;
    const Reference7 ref(d, stroke);
    const SevenSegmentLaw law(d, stroke);
    const std::vector<CamSample> table = sample_cam_table(law.law(), stroke, period);
    expect_samples_match(table, ref, stroke, period, law.v_peak());
    // Every switch time before T lands on a sample: its jerk is the one of the segment of positive
    // duration starting there (the plateau's 0 after a ramp, the next ramp after a plateau).
    std::size_t on_switch = 0;
    for (std::size_t i = 0; i < 7; ++i) {
      if (d[i] == 0.0) continue;
      const double t = ref.switches()[i];
      const auto k = static_cast<std::size_t>(std::lround(t / period));
      ASSERT_LT(k, table.size());
      ASSERT_NEAR(table[k].t, t, 1e-12);
      EXPECT_EQ(table[k].jerk, law.jerks()[i]) << "switch " << i << " at " << t;
      ++on_switch;
    }
    EXPECT_GE(on_switch, 5u);
    // t = 0 starts the law: the jerk of the first ramp.
    EXPECT_EQ(table[0].jerk, law.jerks()[0]);
    EXPECT_EQ(table[0].position, 0.0);
  }
}

// A plateau shorter than the time tolerance ending on a sample: the motion continues with the
// next ramp, whose jerk the sample must carry (the planner returns such plateaus, e.g. 1.7e-15 s
// for notch on the thesis format).
TEST(CamTable, PlateauShorterThanTheToleranceOnASampleGivesTheNextRampsJerk) {
  const Durations d{0.1, 0.1, 0.1, 1e-15, 0.1, 0.1, 0.1};
  const double stroke = 0.5;
  const SevenSegmentLaw law(d, stroke);
  const std::vector<CamSample> table = sample_cam_table(law.law(), stroke, 0.01);
  ASSERT_EQ(table.size(), 61u);
  EXPECT_NEAR(table[30].t, 0.3, 1e-15);
  EXPECT_EQ(table[30].jerk, law.jerks()[4]);
  EXPECT_EQ(table[31].jerk, law.jerks()[4]);
}

TEST(CamTable, CyclesAndLimits) {
  EXPECT_EQ(cam_cycles(1.0, 1e-3), 1000u);
  EXPECT_EQ(cam_cycles(0.9995, 1e-3), 1000u);
  EXPECT_EQ(cam_cycles(1.0005, 1e-3), 1001u);
  EXPECT_EQ(cam_cycles(1.0 + 1e-13, 1e-3), 1000u);  // within the time tolerance
  EXPECT_EQ(cam_cycles(0.7, 1e-3), 700u);           // 0.7 / 0.001 = 699.9999999999999
  EXPECT_THROW((void)cam_cycles(1.0, 5e-6), std::invalid_argument);
  EXPECT_THROW((void)cam_cycles(1.0e3, 1e-5), std::invalid_argument);  // 1e8 samples
  const MotionLaw law = make_poly5_law(0.5, 1.0);
  EXPECT_THROW((void)sample_cam_table(law, 0.5, 0.0), std::invalid_argument);
  EXPECT_THROW((void)sample_cam_table(law, 0.5, std::nan("")), std::invalid_argument);
  EXPECT_EQ(sample_cam_table(law, 0.5, 1e-3).size(), 1001u);
}

// A sample's time is the decimal k x cycle (the double nearest it), not the product k x 0.001
// with its rounding (9 x 0.001 = 0.009000000000000001, 1400 x 0.001 = 1.4000000000000001): the
// shortest text of each time is the decimal a controller's own table holds.
TEST(CamTable, SampleTimesAreTheDecimalMultiplesOfTheCycle) {
  const MotionLaw law = make_poly5_law(0.5, 1.4);
  for (const auto& [period, places] : {std::pair{1e-3, 3}, {2e-3, 3}, {5e-4, 4}, {0.004, 3}}) {
    SCOPED_TRACE(period);
    const std::vector<CamSample> table = sample_cam_table(law, 0.5, period);
    const auto step = static_cast<long long>(std::llround(period * std::pow(10.0, places)));
    for (std::size_t k = 0; k < table.size(); ++k) {
      // The decimal text k x step / 10^places, parsed: the double nearest that decimal.
      const long long units = static_cast<long long>(k) * step;
      const std::string whole =
          std::to_string(units / static_cast<long long>(std::pow(10, places)));
      std::string frac = std::to_string(units % static_cast<long long>(std::pow(10, places)));
      frac.insert(0, static_cast<std::size_t>(places) - frac.size(), '0');
      const double decimal = std::stod(whole + "." + frac);
      ASSERT_EQ(table[k].t, decimal) << k;
    }
    EXPECT_EQ(table.back().t, 1.4);
  }
}

// ---------------------------------------------------------------------------------------------
// `slosh export` end to end.

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> text;
  std::vector<std::vector<double>> value;
};

CsvTable read_numeric_csv(const std::string& content) {
  CsvTable table;
  std::size_t at = 0;
  bool first = true;
  while (at < content.size()) {
    const std::size_t end = content.find('\n', at);
    if (end == std::string::npos) {
      ADD_FAILURE() << "unterminated last line";
      break;
    }
    const std::string line = content.substr(at, end - at);
    at = end + 1;
    std::vector<std::string> cells;
    std::size_t from = 0;
    while (true) {
      const std::size_t comma = line.find(',', from);
      cells.push_back(line.substr(from, comma == std::string::npos ? comma : comma - from));
      if (comma == std::string::npos) break;
      from = comma + 1;
    }
    if (first) {
      table.header = cells;
      first = false;
      continue;
    }
    if (cells.size() != table.header.size()) {
      ADD_FAILURE() << "line with " << cells.size() << " cells: " << line;
      continue;
    }
    std::vector<double> values;
    for (const std::string& c : cells) {
      double v = std::nan("");
      const auto [ptr, ec] = std::from_chars(c.data(), c.data() + c.size(), v);
      if (ec != std::errc() || ptr != c.data() + c.size()) ADD_FAILURE() << "not a number: " << c;
      values.push_back(v);
    }
    table.text.push_back(cells);
    table.value.push_back(values);
  }
  return table;
}

const std::vector<std::string> kCamHeader{"t_s", "position_mm", "velocity_mm_s",
                                          "acceleration_mm_s2", "jerk_mm_s3"};
const std::vector<std::string> kSegmentHeader{
    "segment",     "t_start_s",    "t_end_s",    "duration_s", "jerk_mm_s3", "a_start_mm_s2",
    "a_end_mm_s2", "v_start_mm_s", "v_end_mm_s", "s_start_mm", "s_end_mm"};

json notch_request(double motion_time_s) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82,
      "fluid": "water", "stroke_mm": 650, "motion_time_s": 1.0}, "strategy": "notch"})");
  body["format"]["motion_time_s"] = motion_time_s;
  return body;
}

/// The plan of `request` by `slosh plan`.
json plan_of(const json& request) {
  const RunResult r = run_slosh({"plan", "--request", "-"}, request.dump());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return json::parse(r.out);
}

/// |printed - exact| within the 12 significant digits printed (and the scale of the column for
/// values crossing zero).
void expect_printed(double printed, double exact, double scale, const std::string& what) {
  EXPECT_NEAR(printed, exact, 6e-12 * std::abs(exact) + 1e-12 * scale) << what;
}

class ExportNotch : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    request_ = notch_request(1.0);
    plan_ = plan_of(request_);
    write_file(*dir_ / "request.json", request_.dump());
    run_ = run_slosh({"export", "--request", (*dir_ / "request.json").string(), "--out",
                      (*dir_ / "cam.csv").string(), "--segments", (*dir_ / "seg.csv").string(),
                      "--cache", ""});
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static Durations durations() { return plan_["durations_s"].get<Durations>(); }

  static std::unique_ptr<TempDir> dir_;
  static json request_;
  static json plan_;
  static RunResult run_;
};
std::unique_ptr<TempDir> ExportNotch::dir_;
json ExportNotch::request_;
json ExportNotch::plan_;
RunResult ExportNotch::run_;

TEST_F(ExportNotch, CamTableMatchesTheCoreLawOfThePlannedDurations) {
  ASSERT_EQ(run_.exit_code, 0) << run_.err;
  EXPECT_EQ(run_.err, "");
  const json summary = json::parse(run_.out);
  EXPECT_EQ(summary["source"], "plan");
  EXPECT_EQ(summary["key"], plan_["key"]);
  EXPECT_EQ(summary["status"], plan_["status"]);
  EXPECT_EQ(summary["durations_s"], plan_["durations_s"]);
  EXPECT_EQ(summary["samples"], 1001);
  EXPECT_EQ(summary["period_s"], 0.001);
  EXPECT_EQ(summary["end_time_s"], 1.0);
  EXPECT_EQ(summary["warnings"], json::array());
  EXPECT_NEAR(summary["A_mm_s2"].get<double>(), plan_["kinematics"]["a_max"].get<double>() * 1e3,
              1e-9);

  const CsvTable cam = read_numeric_csv(read_file(*dir_ / "cam.csv"));
  EXPECT_EQ(cam.header, kCamHeader);
  ASSERT_EQ(cam.value.size(), 1001u);
  const double stroke = 0.65;
  const SevenSegmentLaw law(durations(), stroke);
  const double v_scale = law.v_peak() * 1e3;
  const double a_scale = std::max(law.A(), law.B()) * 1e3;
  double j_max = 0.0;
  for (double j : law.jerks()) j_max = std::max(j_max, std::abs(j) * 1e3);
  for (std::size_t k = 0; k < cam.value.size(); ++k) {
    const auto& row = cam.value[k];
    const double t = static_cast<double>(k) * 1e-3;
    const std::string where = "t = " + cam.text[k][0];
    expect_printed(row[0], t, 1.0, where);
    if (k == 0 || k + 1 == cam.value.size()) continue;  // the ends: below
    const KinematicState s = law.law().at(t);
    expect_printed(row[1], s.position * 1e3, 650.0, where + " position");
    expect_printed(row[2], s.velocity * 1e3, v_scale, where + " velocity");
    expect_printed(row[3], s.acceleration * 1e3, a_scale, where + " acceleration");
    expect_printed(row[4], s.jerk * 1e3, j_max, where + " jerk");
  }
  // t = 0: at rest, with the first ramp's jerk; t = T: the stroke exactly, at rest.
  EXPECT_EQ(cam.text.front(), (std::vector<std::string>{"0", "0", "0", "0", cam.text[0][4]}));
  expect_printed(cam.value[0][4], law.jerks()[0] * 1e3, j_max, "jerk at 0");
  EXPECT_EQ(cam.text.back(), (std::vector<std::string>{"1", "650", "0", "0", "0"}));
  EXPECT_EQ(cam.value.back()[1], 650.0);

  // Velocity = the central difference of the position column, within h^2/6 max|j| (the Taylor
  // remainder of a piecewise cubic) and the printed precision of the position.
  const double h = 1e-3;
  for (std::size_t k = 1; k + 1 < cam.value.size(); ++k) {
    const double diff = (cam.value[k + 1][1] - cam.value[k - 1][1]) / (2 * h);
    EXPECT_NEAR(cam.value[k][2], diff, h * h / 6 * j_max * 1.001 + 1e-5)
        << "t = " << cam.text[k][0];
  }
}

TEST_F(ExportNotch, SegmentTableIsKinematicallyConsistent) {
  ASSERT_EQ(run_.exit_code, 0) << run_.err;
  EXPECT_EQ(json::parse(run_.out)["segment_table"], (*dir_ / "seg.csv").string());
  const CsvTable seg = read_numeric_csv(read_file(*dir_ / "seg.csv"));
  EXPECT_EQ(seg.header, kSegmentHeader);
  ASSERT_EQ(seg.value.size(), 7u);
  const Durations d = durations();
  const double A = plan_["kinematics"]["a_max"].get<double>() * 1e3;  // mm/s^2
  const double B = plan_["kinematics"]["a_min"].get<double>() * 1e3;
  double sum = 0.0;
  for (std::size_t i = 0; i < 7; ++i) {
    const auto& r = seg.value[i];
    SCOPED_TRACE("segment " + std::to_string(i + 1));
    EXPECT_EQ(seg.text[i][0], std::to_string(i + 1));
    const double duration = r[3];
    const double jerk = r[4], a0 = r[5], a1 = r[6], v0 = r[7], v1 = r[8], s0 = r[9], s1 = r[10];
    expect_printed(duration, d[i], 1.0, "duration");
    EXPECT_NEAR(r[2] - r[1], duration, 1e-11);
    sum += duration;
    EXPECT_NEAR(a1, a0 + jerk * duration, 1e-9 * A);
    EXPECT_NEAR(v1, v0 + a0 * duration + jerk * duration * duration / 2, 1e-9 * A);
    EXPECT_NEAR(s1,
                s0 + v0 * duration + a0 * duration * duration / 2 +
                    jerk * duration * duration * duration / 6,
                1e-9 * 650.0);
    if (i > 0) {
      // Continuity: each segment starts where the previous one ended.
      EXPECT_EQ(seg.text[i][1], seg.text[i - 1][2]);
      EXPECT_EQ(seg.text[i][5], seg.text[i - 1][6]);
      EXPECT_EQ(seg.text[i][7], seg.text[i - 1][8]);
      EXPECT_EQ(seg.text[i][9], seg.text[i - 1][10]);
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-9);
  // Plateau levels in mm/s^2 = the plan's A and B in m/s^2.
  expect_printed(seg.value[0][6], A, A, "A");
  expect_printed(seg.value[1][5], A, A, "A");
  expect_printed(seg.value[4][6], -B, B, "-B");
  expect_printed(seg.value[5][6], -B, B, "-B");
  // And the levels of the durations from the independent integration.
  const Reference7 ref(d, 0.65);
  EXPECT_NEAR(seg.value[0][6], ref.A() * 1e3, 1e-8 * A);
  EXPECT_NEAR(seg.value[5][5], -ref.B() * 1e3, 1e-8 * B);
  // Starts at rest at 0, ends at rest on the stroke exactly.
  EXPECT_EQ(seg.text[0][7], "0");
  EXPECT_EQ(seg.text[0][9], "0");
  EXPECT_EQ(seg.text[6][8], "0");
  EXPECT_EQ(seg.text[6][10], "650");
  EXPECT_EQ(seg.text[6][2], "1");
}

TEST(ExportCli, MotionTimeNotAMultipleOfTheCycleEndsOnTheNextCycleWithAWarning) {
  const TempDir dir;
  write_file(dir / "request.json", notch_request(0.9995).dump());
  const RunResult r = run_slosh({"export", "--request", (dir / "request.json").string(), "--out",
                                 (dir / "cam.csv").string(), "--cache", ""});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json summary = json::parse(r.out);
  EXPECT_EQ(summary["motion_time_s"], 0.9995);
  EXPECT_EQ(summary["end_time_s"], 1.0);
  EXPECT_EQ(summary["samples"], 1001);
  ASSERT_EQ(summary["warnings"].size(), 1u) << r.out;
  const std::string warning = summary["warnings"][0];
  EXPECT_NE(warning.find("0.9995 s"), std::string::npos) << warning;
  EXPECT_NE(warning.find("not a multiple"), std::string::npos) << warning;
  EXPECT_NE(warning.find("0.5 ms"), std::string::npos) << warning;
  const CsvTable cam = read_numeric_csv(read_file(dir / "cam.csv"));
  ASSERT_EQ(cam.value.size(), 1001u);
  EXPECT_EQ(cam.text.back(), (std::vector<std::string>{"1", "650", "0", "0", "0"}));
  // 0.999 s is still inside the motion: short of the stroke, still moving.
  EXPECT_EQ(cam.text[999][0], "0.999");
  EXPECT_LT(cam.value[999][1], 650.0);
  EXPECT_GT(cam.value[999][2], 0.0);
  const SevenSegmentLaw law(summary["durations_s"].get<Durations>(), 0.65);
  expect_printed(cam.value[999][1], law.law().at(0.999).position * 1e3, 650.0, "position");
}

TEST(ExportCli, Poly5LawMatchesTheClosedForm) {
  const TempDir dir;
  const json request = json::parse(R"({"format": {"container": {"radius_mm": 40},
      "fill_height_mm": 70, "fluid": "water", "stroke_mm": 500, "motion_time_s": 0.8},
      "law": {"type": "poly5"}})");
  write_file(dir / "law.json", request.dump());
  const RunResult r = run_slosh({"export", "--request", (dir / "law.json").string(), "--out",
                                 (dir / "cam.csv").string(), "--period-ms", "0.5"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json summary = json::parse(r.out);
  EXPECT_EQ(summary["source"], "law");
  EXPECT_EQ(summary["law"], "poly5");
  EXPECT_EQ(summary["samples"], 1601);
  EXPECT_FALSE(summary.contains("segments"));
  const CsvTable cam = read_numeric_csv(read_file(dir / "cam.csv"));
  EXPECT_EQ(cam.header, kCamHeader);
  ASSERT_EQ(cam.value.size(), 1601u);
  const double S = 500.0, T = 0.8;  // mm, s
  for (std::size_t k = 0; k + 1 < cam.value.size(); ++k) {
    const double t = static_cast<double>(k) * 5e-4;
    const double u = t / T;
    const double s = S * (10 * u * u * u - 15 * u * u * u * u + 6 * u * u * u * u * u);
    const double v = S / T * (30 * u * u - 60 * u * u * u + 30 * u * u * u * u);
    const double a = S / (T * T) * (60 * u - 180 * u * u + 120 * u * u * u);
    const double j = S / (T * T * T) * (60 - 360 * u + 360 * u * u);
    const auto& row = cam.value[k];
    const std::string where = "t = " + cam.text[k][0];
    expect_printed(row[0], t, 1.0, where);
    EXPECT_NEAR(row[1], s, 6e-12 * s + 1e-10 * S) << where;
    EXPECT_NEAR(row[2], v, 6e-12 * std::abs(v) + 1e-10 * S / T) << where;
    EXPECT_NEAR(row[3], a, 6e-12 * std::abs(a) + 1e-10 * S / (T * T)) << where;
    EXPECT_NEAR(row[4], j, 6e-12 * std::abs(j) + 1e-10 * S / (T * T * T)) << where;
  }
  EXPECT_EQ(cam.text.back(), (std::vector<std::string>{"0.8", "500", "0", "0", "0"}));
}

TEST(ExportCli, SevenSegmentLawRequestWritesItsSegmentTable) {
  const TempDir dir;
  json request = json::parse(R"({"format": {"container": {"radius_mm": 48.5},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "law": {"type": "seven_segment"}})");
  request["law"]["durations_s"] = test::kAsymmetricDurations;
  write_file(dir / "law.json", request.dump());
  const RunResult r = run_slosh({"export", "--request", (dir / "law.json").string(), "--out", "-",
                                 "--segments", (dir / "seg.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // --out -: the cam table alone on stdout (no summary).
  const CsvTable cam = read_numeric_csv(r.out);
  EXPECT_EQ(cam.header, kCamHeader);
  ASSERT_EQ(cam.value.size(), 1001u);
  const Reference7 ref(test::kAsymmetricDurations, 0.8);
  for (std::size_t k = 1; k + 1 < cam.value.size(); ++k) {
    const State s = ref.at(static_cast<double>(k) * 1e-3);
    EXPECT_NEAR(cam.value[k][1], s.s * 1e3, 1e-8) << k;
    EXPECT_NEAR(cam.value[k][3], s.a * 1e3, 1e-8 * ref.A() * 1e3) << k;
  }
  const CsvTable seg = read_numeric_csv(read_file(dir / "seg.csv"));
  ASSERT_EQ(seg.value.size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) {
    expect_printed(seg.value[i][3], test::kAsymmetricDurations[i], 1.0, "duration");
    expect_printed(seg.value[i][4], ref.jerk(i) * 1e3, ref.max_jerk() * 1e3, "jerk");
  }
  expect_printed(seg.value[1][5], ref.A() * 1e3, ref.A() * 1e3, "A");
  expect_printed(seg.value[5][5], -ref.B() * 1e3, ref.B() * 1e3, "B");
  EXPECT_EQ(seg.text[6][10], "800");
}

TEST(ExportCli, CacheFileServesTheSamePlanTheSecondTime) {
  const TempDir dir;
  write_file(dir / "request.json", notch_request(1.0).dump());
  const std::vector<std::string> base{"export",
                                      "--request",
                                      (dir / "request.json").string(),
                                      "--cache",
                                      (dir / "plans.sqlite").string(),
                                      "--out"};
  auto with_out = [&](const std::string& name) {
    std::vector<std::string> args = base;
    args.push_back((dir / name).string());
    return args;
  };
  const RunResult first = run_slosh(with_out("a.csv"));
  const RunResult second = run_slosh(with_out("b.csv"));
  ASSERT_EQ(first.exit_code, 0) << first.err;
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(json::parse(first.out)["cached"], false);
  EXPECT_EQ(json::parse(second.out)["cached"], true);
  EXPECT_EQ(json::parse(second.out)["key"], json::parse(first.out)["key"]);
  EXPECT_EQ(read_file(dir / "b.csv"), read_file(dir / "a.csv"));
  EXPECT_FALSE(read_file(dir / "a.csv").empty());
}

// ---------------------------------------------------------------------------------------------
// Bad input: exit 2, the error envelope on stderr, no cam table.

json error_of(const RunResult& r) {
  try {
    return json::parse(r.err);
  } catch (const json::exception&) {
    ADD_FAILURE() << "stderr is not JSON: " << r.err;
  }
  return json::object();
}

TEST(ExportCli, PeriodOutOfRangeIsRejected) {
  const TempDir dir;
  write_file(dir / "request.json", notch_request(1.0).dump());
  for (const std::string& period : {std::string("0.001"), std::string("0"), std::string("2000")}) {
    SCOPED_TRACE(period);
    const RunResult r =
        run_slosh({"export", "--request", (dir / "request.json").string(), "--out",
                   (dir / "cam.csv").string(), "--period-ms", period, "--cache", ""});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(
        error_of(r),
        json({{"error",
               {{"code", "invalid_value"},
                {"field", "--period-ms"},
                {"message", "--period-ms = " + period + " is out of range [0.01, 1000] ms"}}}}));
    EXPECT_FALSE(fs::exists(dir / "cam.csv"));
  }
}

TEST(ExportCli, SegmentsOfANonSevenSegmentLawAreRejected) {
  const TempDir dir;
  write_file(dir / "law.json", R"({"format": {"container": {"radius_mm": 40},
      "fill_height_mm": 70, "fluid": "water", "stroke_mm": 500, "motion_time_s": 0.8},
      "law": {"type": "poly5"}})");
  const RunResult r =
      run_slosh({"export", "--request", (dir / "law.json").string(), "--out",
                 (dir / "cam.csv").string(), "--segments", (dir / "seg.csv").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(
      error_of(r),
      json({{"error",
             {{"code", "invalid_value"},
              {"field", "--segments"},
              {"message",
               "--segments: the law poly5 is not a 7-segment law; it has no segment table"}}}}));
  EXPECT_FALSE(fs::exists(dir / "cam.csv"));
  EXPECT_FALSE(fs::exists(dir / "seg.csv"));
}

TEST(ExportCli, InvalidPlanRequestNamesTheField) {
  json request = notch_request(1.0);
  request["format"]["container"]["radius_mm"] = -3;
  const TempDir dir;
  const RunResult r =
      run_slosh({"export", "--request", "-", "--out", (dir / "cam.csv").string(), "--cache", ""},
                request.dump());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(error_of(r), json::parse(R"({"error": {"code": "invalid_value",
      "message": "format.container.radius_mm = -3 is out of range: allowed 1 to 2000 mm",
      "field": "format.container.radius_mm"}})"));
  EXPECT_FALSE(fs::exists(dir / "cam.csv"));

  json option = notch_request(1.0);
  option["options"] = {{"p_notch", 2}};
  const RunResult o =
      run_slosh({"export", "--request", "-", "--out", (dir / "cam.csv").string(), "--cache", ""},
                option.dump());
  EXPECT_EQ(o.exit_code, 2) << o.err;
  EXPECT_EQ(error_of(o)["error"]["field"], "options.p_notch");

  const RunResult malformed =
      run_slosh({"export", "--request", "-", "--out", (dir / "cam.csv").string()}, "{\"format\":");
  EXPECT_EQ(malformed.exit_code, 2) << malformed.err;
  EXPECT_EQ(error_of(malformed)["error"]["code"], "malformed_json");
}

TEST(ExportCli, WarningsGoToStderrWhenTheCamTableGoesToStdout) {
  const RunResult r = run_slosh({"export", "--request", "-", "--out", "-", "--cache", ""},
                                notch_request(0.9995).dump());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(
      r.err.rfind("slosh export: warning: the motion time 0.9995 s is not a multiple of the 1 ms "
                  "cycle",
                  0),
      0u)
      << r.err;
  EXPECT_EQ(r.out.rfind("t_s,position_mm,", 0), 0u);
}

// The summary carries the plan's own warnings (plan_warnings) beside the cam table's: the README
// cup in 55 mm of height spills, and the export says so as the plan does.
TEST(ExportCli, TheSummaryCarriesThePlansWarnings) {
  const json request = json::parse(R"({"format": {"container": {"shape": "rectangular",
      "length_mm": 120, "width_mm": 80, "height_mm": 55}, "fill_height_mm": 50,
      "fluid": "water", "stroke_mm": 200, "motion_time_s": 1.0}, "strategy": "notch",
      "options": {"robustness": false}})");
  const RunResult planned = run_slosh({"plan", "--request", "-"}, request.dump());
  ASSERT_EQ(planned.exit_code, 0) << planned.err;
  const json plan = json::parse(planned.out);
  ASSERT_FALSE(plan["warnings"].empty()) << planned.out;
  const TempDir dir;
  write_file(dir / "request.json", request.dump());
  const RunResult r = run_slosh({"export", "--request", (dir / "request.json").string(), "--out",
                                 (dir / "cam.csv").string(), "--cache", "", "--allow-infeasible"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json summary = json::parse(r.out);
  EXPECT_EQ(summary["plan_warnings"], plan["warnings"]);
}

TEST(ExportCli, AnInfeasiblePlanIsExportedOnlyWhenAllowed) {
  // a_max = 0.5 m/s^2 cannot move 650 mm in 1 s: the plan is infeasible, its law misses a_max.
  json request = notch_request(1.0);
  request["options"]["limits"]["a_max"] = 0.5;
  const TempDir dir;
  write_file(dir / "request.json", request.dump());
  const RunResult refused = run_slosh({"export", "--request", (dir / "request.json").string(),
                                       "--out", (dir / "cam.csv").string(), "--cache", ""});
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_FALSE(fs::exists(dir / "cam.csv"));
  const std::string message = error_of(refused)["error"]["message"];
  // The service's refusal (a 422 naming allow_infeasible), not an internal error.
  EXPECT_EQ(error_of(refused)["error"]["code"], "invalid_value");
  EXPECT_EQ(error_of(refused)["error"]["field"], "allow_infeasible");
  EXPECT_EQ(message.find(".."), std::string::npos) << message;
  EXPECT_EQ(message.rfind("the plan is infeasible, its law misses the requested limits: ", 0), 0u)
      << message;
  EXPECT_NE(message.find("pass --allow-infeasible"), std::string::npos) << message;

  const RunResult allowed =
      run_slosh({"export", "--request", (dir / "request.json").string(), "--out",
                 (dir / "cam.csv").string(), "--cache", "", "--allow-infeasible"});
  ASSERT_EQ(allowed.exit_code, 0) << allowed.err;
  const json summary = json::parse(allowed.out);
  EXPECT_EQ(summary["status"], "infeasible");
  const CsvTable cam = read_numeric_csv(read_file(dir / "cam.csv"));
  EXPECT_EQ(cam.text.back()[1], "650");
}

TEST(ExportCli, MissingOutIsAUsageError) {
  const RunResult r = run_slosh({"export", "--request", "-"}, notch_request(1.0).dump());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err.rfind("--out is required\n", 0), 0u) << r.err;
}

}  // namespace test_export
}  // namespace slosh
