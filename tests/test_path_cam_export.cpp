// Cam tables along a path (SPEC §14): the pose columns of cam_along_path and the table rotation
// of table_rotation_rows against the circle and the line written out here, and `slosh export`
// of a law along an arc and a path end to end with the real binary (a poly5 law, whose s(t) is
// a closed form, so every column has an independent value), and the refusals.

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/core/law/path_cam_table.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_path_cam_export {

using nlohmann::json;
using test::read_file;
using test::run_slosh;
using test::RunResult;
using test::TempDir;
using test::write_file;

constexpr double kPi = std::numbers::pi;

/// The pose on an arc of radius R from the origin heading +x, turning `sign` (+1 left, -1
/// right), at arc length s: centre (0, sign R).
struct ArcPose {
  double x, y, heading;
};
ArcPose arc_pose(double R, double sign, double s) {
  const double phi = s / R;
  return {R * std::sin(phi), sign * R * (1.0 - std::cos(phi)), sign * phi};
}

TEST(PathCam, ArcPoseIsOnTheCircleWithTheHeadingOfTheTable) {
  const double R = 0.3;
  for (const double sign : {1.0, -1.0}) {
    for (const bool turns : {true, false}) {
      SCOPED_TRACE(testing::Message() << "sign " << sign << " turns " << turns);
      const PlanarPath path = PlanarPath::arc(R, sign * kPi / 2, turns);
      const SevenSegmentLaw law(uniform_durations(1.2), path.length());
      const std::vector<CamSample> cam = sample_cam_table(law.law(), path.length(), 1e-3);
      const std::vector<PathCamSample> rows = cam_along_path(cam, path);
      ASSERT_EQ(rows.size(), cam.size());
      for (std::size_t k = 0; k < rows.size(); ++k) {
        const ArcPose want = arc_pose(R, sign, cam[k].position);
        EXPECT_EQ(rows[k].s, cam[k].position);
        EXPECT_EQ(rows[k].t, cam[k].t);
        EXPECT_NEAR(rows[k].x, want.x, 1e-14) << k;
        EXPECT_NEAR(rows[k].y, want.y, 1e-14) << k;
        EXPECT_NEAR(rows[k].theta, turns ? want.heading : 0.0, 1e-13) << k;
      }
      EXPECT_NEAR(rows.back().x, R, 1e-15);
      EXPECT_NEAR(rows.back().y, sign * R, 1e-15);
    }
  }
}

TEST(PathCam, LineThenArcThenLineFollowsEachElement) {
  // 200 mm along +x, a left quarter of radius 100 mm, 150 mm along +y.
  const PlanarPath path(
      {PathElement::line(0.2), PathElement::arc(0.1, kPi / 2), PathElement::line(0.15)}, 0.0, true);
  const double L = path.length();
  ASSERT_NEAR(L, 0.35 + 0.1 * kPi / 2, 1e-15);
  const SevenSegmentLaw law(uniform_durations(1.5), L);
  const std::vector<PathCamSample> rows =
      cam_along_path(sample_cam_table(law.law(), L, 5e-4), path);
  const double arc_end = 0.2 + 0.1 * kPi / 2;
  for (const PathCamSample& r : rows) {
    double x = 0, y = 0, th = 0;
    if (r.s <= 0.2) {
      x = r.s;
    } else if (r.s <= arc_end) {
      const ArcPose p = arc_pose(0.1, 1.0, r.s - 0.2);
      x = 0.2 + p.x;
      y = p.y;
      th = p.heading;
    } else {
      x = 0.3;
      y = 0.1 + (r.s - arc_end);
      th = kPi / 2;
    }
    EXPECT_NEAR(r.x, x, 1e-13) << r.t;
    EXPECT_NEAR(r.y, y, 1e-13) << r.t;
    EXPECT_NEAR(r.theta, th, 1e-12) << r.t;
  }
  EXPECT_NEAR(rows.back().x, 0.3, 1e-15);
  EXPECT_NEAR(rows.back().y, 0.25, 1e-15);
}

TEST(PathCam, TableRotationIsTheArcAngleOfTheDistanceAndEndsOnTheAngleExactly) {
  const double R = 0.3;
  const PlanarPath path = PlanarPath::arc(R, -kPi / 3, true);  // a 60 degree right turn
  ASSERT_TRUE(table_rotation_deg(path).has_value());
  EXPECT_NEAR(*table_rotation_deg(path), -60.0, 1e-12);
  const SevenSegmentLaw law(uniform_durations(0.9), path.length());
  const MasterAxis axis{360.0, 30.0, 300.0, 0.5};
  const std::vector<MasterCamSample> mm = sample_master_cam_table(law.law(), path.length(), axis);
  const std::vector<MasterCamSample> deg = table_rotation_rows(mm, path);
  ASSERT_EQ(deg.size(), mm.size());
  const double per_m = -60.0 / (R * kPi / 3);  // degrees of table per metre along the arc
  for (std::size_t k = 0; k < deg.size(); ++k) {
    EXPECT_EQ(deg[k].master, mm[k].master);
    EXPECT_NEAR(deg[k].position, mm[k].position * per_m, 1e-12) << k;
    EXPECT_NEAR(deg[k].velocity, mm[k].velocity * per_m, 1e-12 * std::abs(per_m)) << k;
    EXPECT_NEAR(deg[k].acceleration, mm[k].acceleration * per_m, 1e-12 * std::abs(per_m)) << k;
  }
  EXPECT_EQ(deg.back().position, *table_rotation_deg(path));
  EXPECT_FALSE(table_rotation_deg(PlanarPath::line(0.5)).has_value());
  EXPECT_THROW((void)table_rotation_rows(mm, PlanarPath::line(0.5)), std::invalid_argument);
}

// The rotation is the degrees the request gave (read as deg * pi / 180), not radians * 180 / pi:
// -120 deg ends the table on -120, which a PLC's in-position check compares with (it was
// -119.99999999999999). Seeded random angles to 6 decimals, as a drawing gives them.
TEST(PathCam, TableRotationIsTheGivenDegreesExactly) {
  constexpr double kRadPerDeg = kPi / 180.0;
  std::vector<double> angles{-120.0, 90.0, 33.333333, -270.0, 3600.0, 0.1};
  std::uint64_t state = 20261127;
  for (int i = 0; i < 200; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const double u = static_cast<double>(state >> 11) / 9007199254740992.0;  // [0, 1)
    angles.push_back(std::round((u * 720.0 - 360.0) * 1e6) / 1e6);
  }
  for (const double angle : angles) {
    if (angle == 0.0) continue;
    const PlanarPath path = PlanarPath::arc(0.3, angle * kRadPerDeg, true);
    ASSERT_EQ(*table_rotation_deg(path), angle) << angle;
  }
  const PlanarPath path = PlanarPath::arc(0.3, -120.0 * kRadPerDeg, true);
  const SevenSegmentLaw law(uniform_durations(0.8), path.length());
  const std::vector<MasterCamSample> deg = table_rotation_rows(
      sample_master_cam_table(law.law(), path.length(), MasterAxis{360.0, 30.0, 210.0, 1.0}), path);
  EXPECT_EQ(deg.back().position, -120.0);
}

// ---------------------------------------------------------------------------------------------
// `slosh export` along a motion.

struct Csv {
  std::string header;
  std::vector<std::vector<double>> rows;
};

Csv read_csv(const std::string& text) {
  Csv out;
  std::istringstream in(text);
  std::getline(in, out.header);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::stod(cell));
    out.rows.push_back(row);
  }
  return out;
}

json law_request(const json& motion, double T) {
  json r = json::parse(R"({"format": {"container": {"radius_mm": 40}, "fill_height_mm": 70,
      "fluid": "water"}, "law": {"type": "poly5"}})");
  r["format"]["motion"] = motion;
  r["format"]["motion_time_s"] = T;
  return r;
}

/// s(t) of poly5 over L in T [same unit as L].
double poly5(double L, double T, double t) {
  const double u = std::min(t / T, 1.0);
  return L * u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
}

json error_of(const RunResult& r) {
  try {
    return json::parse(r.err);
  } catch (const json::exception&) {
    ADD_FAILURE() << "stderr is not JSON: " << r.err;
  }
  return json::object();
}

TEST(PathCamCli, ArcTableHasThePoseAndTheTableRotation) {
  const TempDir dir;
  for (const bool turns : {true, false}) {
    SCOPED_TRACE(turns);
    const json motion{
        {"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}, {"container_turns", turns}};
    write_file(dir / "law.json", law_request(motion, 1.2).dump());
    const RunResult r = run_slosh(
        {"export", "--request", (dir / "law.json").string(), "--out", (dir / "cam.csv").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json summary = json::parse(r.out);
    EXPECT_EQ(summary["motion"]["type"], "arc");
    EXPECT_NEAR(summary["motion"]["length_mm"].get<double>(), 150.0 * kPi, 1e-9);
    EXPECT_NEAR(summary["motion"]["table_rotation_deg"].get<double>(), 90.0, 1e-12);
    EXPECT_EQ(summary["samples"], 1201);
    const Csv cam = read_csv(read_file(dir / "cam.csv"));
    EXPECT_EQ(cam.header,
              "t_s,s_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3,x_mm,y_mm,theta_deg,"
              "table_deg");
    ASSERT_EQ(cam.rows.size(), 1201u);
    const double L = 150.0 * kPi;  // mm
    for (const std::vector<double>& row : cam.rows) {
      ASSERT_EQ(row.size(), 9u);
      const double s = poly5(L, 1.2, row[0]);
      const double phi = s / 300.0;
      EXPECT_NEAR(row[1], s, 1e-9) << row[0];
      EXPECT_NEAR(row[5], 300.0 * std::sin(phi), 1e-9) << row[0];
      EXPECT_NEAR(row[6], 300.0 * (1.0 - std::cos(phi)), 1e-9) << row[0];
      EXPECT_NEAR(row[7], turns ? phi * 180.0 / kPi : 0.0, 1e-9) << row[0];
      EXPECT_NEAR(row[8], phi * 180.0 / kPi, 1e-9) << row[0];
    }
    EXPECT_EQ(cam.rows.back()[8], 90.0);
  }
}

// A table turning a container that starts at 37 deg through 90 deg ends at a heading of 127 deg,
// written 127: the pose is given to 1e-10 of its unit, not with its radians' round-off.
TEST(PathCamCli, TheLastHeadingIsTheStartPlusTheArcExactly) {
  const TempDir dir;
  const json motion{{"type", "arc"},
                    {"radius_mm", 300},
                    {"angle_deg", 90},
                    {"start_heading_deg", 37},
                    {"container_turns", true}};
  write_file(dir / "law.json", law_request(motion, 1.2).dump());
  const RunResult r = run_slosh({"export", "--request", (dir / "law.json").string(), "--out", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv cam = read_csv(r.out);
  ASSERT_FALSE(cam.rows.empty());
  EXPECT_EQ(cam.rows.front()[7], 37.0);
  EXPECT_EQ(cam.rows.back()[7], 127.0);
  EXPECT_NE(r.out.find(",127,90\n"), std::string::npos);
}

TEST(PathCamCli, RotaryTableMasterCamIsInDegreesOfTableRotation) {
  const TempDir dir;
  const json motion{{"type", "arc"}, {"radius_mm", 250}, {"angle_deg", -45}};
  write_file(dir / "law.json", law_request(motion, 0.8).dump());
  const RunResult r =
      run_slosh({"export", "--request", (dir / "law.json").string(), "--out", "-",
                 "--master-period", "360", "--master-start", "20", "--master-end", "200"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv cam = read_csv(r.out);
  EXPECT_EQ(cam.header,
            "master,table_deg,velocity_deg_per_unit,acceleration_deg_per_unit2,"
            "jerk_deg_per_unit3");
  ASSERT_EQ(cam.rows.size(), 361u);
  for (const std::vector<double>& row : cam.rows) {
    // The law's time at master position m: (m - 20) / 180 of 0.8 s; the table turns -45 deg.
    const double t = std::clamp((row[0] - 20.0) / 180.0, 0.0, 1.0) * 0.8;
    EXPECT_NEAR(row[1], poly5(-45.0, 0.8, t), 1e-11) << row[0];
  }
  EXPECT_EQ(cam.rows.back()[1], -45.0);
}

TEST(PathCamCli, PathMasterCamHasThePoseAtEachRow) {
  const TempDir dir;
  const json motion = json::parse(R"({"type": "path", "segments": [{"line_mm": 200},
      {"arc": {"radius_mm": 100, "angle_deg": 90}}], "container_turns": true})");
  write_file(dir / "law.json", law_request(motion, 1.0).dump());
  const RunResult r =
      run_slosh({"export", "--request", (dir / "law.json").string(), "--out", "-",
                 "--master-period", "100", "--master-start", "0", "--master-end", "100"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv cam = read_csv(r.out);
  EXPECT_EQ(cam.header,
            "master,s_mm,velocity_mm_per_unit,acceleration_mm_per_unit2,jerk_mm_per_unit3,x_mm,"
            "y_mm,theta_deg");
  const double L = 200.0 + 50.0 * kPi;
  for (const std::vector<double>& row : cam.rows) {
    const double s = poly5(L, 1.0, row[0] / 100.0);
    EXPECT_NEAR(row[1], s, 1e-9) << row[0];
    const double x = s <= 200.0 ? s : 200.0 + 100.0 * std::sin((s - 200.0) / 100.0);
    const double y = s <= 200.0 ? 0.0 : 100.0 * (1.0 - std::cos((s - 200.0) / 100.0));
    EXPECT_NEAR(row[5], x, 1e-9) << row[0];
    EXPECT_NEAR(row[6], y, 1e-9) << row[0];
    EXPECT_NEAR(row[7], s <= 200.0 ? 0.0 : (s - 200.0) / 100.0 * 180.0 / kPi, 1e-9) << row[0];
  }
}

// theta_deg is the world heading in both tables: a path that starts at 30 deg reads 30 at its
// start and 30 + 90 at its end in the master table as in the time table (the master table read
// 0 and 90 before, the time table 30 and 120).
TEST(PathCamCli, BothTablesGiveTheWorldHeading) {
  const TempDir dir;
  json motion = json::parse(R"({"type": "path", "segments": [{"line_mm": 200},
      {"arc": {"radius_mm": 100, "angle_deg": 90}}, {"line_mm": 200}],
      "start_heading_deg": 30, "container_turns": true})");
  for (const bool turns : {true, false}) {
    motion["container_turns"] = turns;
    write_file(dir / "law.json", law_request(motion, 1.0).dump());
    const RunResult timed =
        run_slosh({"export", "--request", (dir / "law.json").string(), "--out", "-"});
    const RunResult master =
        run_slosh({"export", "--request", (dir / "law.json").string(), "--out", "-",
                   "--master-period", "360", "--master-start", "0", "--master-end", "360"});
    ASSERT_EQ(timed.exit_code, 0) << timed.err;
    ASSERT_EQ(master.exit_code, 0) << master.err;
    const Csv t = read_csv(timed.out), m = read_csv(master.out);
    ASSERT_FALSE(t.rows.empty());
    ASSERT_FALSE(m.rows.empty());
    const double end = turns ? 120.0 : 30.0;
    EXPECT_EQ(t.rows.front()[7], 30.0);
    EXPECT_EQ(t.rows.back()[7], end);
    EXPECT_EQ(m.rows.front()[7], 30.0);
    EXPECT_EQ(m.rows.back()[7], end);
  }
}

TEST(PathCamCli, APlanAlongAnArcExportsItsLawWithThePose) {
  const TempDir dir;
  json request = law_request({{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}}, 1.2);
  request.erase("law");
  request["strategy"] = "min_jerk_band";
  write_file(dir / "plan.json", request.dump());
  const RunResult r = run_slosh({"export", "--request", (dir / "plan.json").string(), "--out",
                                 (dir / "cam.csv").string(), "--cache", ""});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json summary = json::parse(r.out);
  EXPECT_EQ(summary["source"], "plan");
  EXPECT_EQ(summary["motion"]["type"], "arc");
  const Csv cam = read_csv(read_file(dir / "cam.csv"));
  EXPECT_EQ(cam.header,
            "t_s,s_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3,x_mm,y_mm,theta_deg,"
            "table_deg");
  for (const std::vector<double>& row : cam.rows) {
    const double phi = row[1] / 300.0;
    EXPECT_NEAR(row[5], 300.0 * std::sin(phi), 1e-9) << row[0];
    EXPECT_NEAR(row[6], 300.0 * (1.0 - std::cos(phi)), 1e-9) << row[0];
    EXPECT_NEAR(row[7], phi * 180.0 / kPi, 1e-9) << row[0];
  }
  EXPECT_EQ(cam.rows.back()[8], 90.0);
}

TEST(PathCamCli, ALineMotionExportsTheStraightLineTableUnchanged) {
  const TempDir dir;
  json plain = law_request(json(), 0.8);
  plain["format"].erase("motion");
  plain["format"]["stroke_mm"] = 500;
  json line = law_request({{"type", "line"}, {"length_mm", 500}, {"direction_deg", 30}}, 0.8);
  write_file(dir / "plain.json", plain.dump());
  write_file(dir / "line.json", line.dump());
  const RunResult a =
      run_slosh({"export", "--request", (dir / "plain.json").string(), "--out", "-"});
  const RunResult b =
      run_slosh({"export", "--request", (dir / "line.json").string(), "--out", "-"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_EQ(a.out, b.out);
}

TEST(PathCamCli, RefusalsNameTheMemberOrTheOption) {
  const TempDir dir;
  json trajectory = law_request(json::parse(R"({"type": "trajectory", "t_s": [0, 0.01, 0.02, 0.03],
          "x_mm": [0, 1, 2, 3], "y_mm": [0, 0, 0, 0]})"),
                                1.0);
  trajectory["format"].erase("motion_time_s");
  write_file(dir / "trajectory.json", trajectory.dump());
  RunResult r = run_slosh({"export", "--request", (dir / "trajectory.json").string(), "--out",
                           (dir / "cam.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(error_of(r)["error"]["field"], "format.motion");
  EXPECT_EQ(error_of(r)["error"]["message"],
            "format.motion: a trajectory cannot be exported: its samples are the motion already "
            "(export a law along a line, an arc or a path)");

  // A simulate request of a trajectory has no law: it is refused as a trajectory, not as a plan.
  trajectory.erase("law");
  write_file(dir / "trajectory-simulate.json", trajectory.dump());
  r = run_slosh({"export", "--request", (dir / "trajectory-simulate.json").string(), "--out",
                 (dir / "cam.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(error_of(r)["error"]["message"],
            "format.motion: a trajectory cannot be exported: its samples are the motion already "
            "(export a law along a line, an arc or a path)");

  write_file(dir / "bad.json",
             law_request({{"type", "arc"}, {"radius_mm", 0}, {"angle_deg", 90}}, 1.0).dump());
  r = run_slosh({"export", "--request", (dir / "bad.json").string(), "--out", "-"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(error_of(r)["error"]["field"], "format.motion.radius_mm");
}

// The rows of an ST cam table: each "(a := 1.0, b := 2.0)" initialiser as its numbers, and the
// member names of its first row.
struct StRows {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
};

StRows read_st_rows(const std::string& text) {
  StRows out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t open = line.find("    (");
    if (open != 0) continue;
    std::vector<double> row;
    std::size_t at = 0;
    while ((at = line.find(" := ", at)) != std::string::npos) {
      if (out.rows.empty()) {
        const std::size_t name_start = line.find_last_of("(, ", at - 1) + 1;
        out.names.push_back(line.substr(name_start, at - name_start));
      }
      at += 4;
      row.push_back(std::stod(line.substr(at)));
    }
    out.rows.push_back(row);
  }
  return out;
}

// The structured text along an arc and along a path: the CSV's columns as the structure's
// members (a type of their own, declared in the file), the same rows to the ST literal's 15
// digits; the header names the path.
TEST(PathCamCli, StructuredTextHasTheCsvColumnsAndRows) {
  const TempDir dir;
  const json arc{{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}};
  const json path = json::parse(R"({"type": "path", "segments": [{"line_mm": 200},
      {"arc": {"radius_mm": 100, "angle_deg": 90}}], "container_turns": true})");
  struct Case {
    json motion;
    std::vector<std::string> extra;
    std::string type;
    std::string dwell;  // where a master cam's slave dwells, as the header says
  };
  // The path's length, 200 mm and a quarter circle of 100 mm, to 10 digits as headers print.
  const std::string path_mm = "357.0796327";
  for (const Case& c :
       {Case{arc, {}, "SLOSH_TABLE_CAM_POINT", ""}, Case{path, {}, "SLOSH_PATH_CAM_POINT", ""},
        Case{arc,
             {"--master-period", "360", "--master-start", "30", "--master-end", "210"},
             "SLOSH_TABLE_MASTER_CAM_POINT",
             "the slave dwells at 0 deg before the start and at 90 deg (the table's rotation) "
             "from the end on"},
        Case{path,
             {"--master-period", "100", "--master-start", "0", "--master-end", "100"},
             "SLOSH_PATH_MASTER_CAM_POINT",
             "the slave dwells at s = 0 mm before the start and at s = " + path_mm +
                 " mm (the path's end) from the end on"}}) {
    SCOPED_TRACE(c.type);
    write_file(dir / "law.json", law_request(c.motion, 1.0).dump());
    std::vector<std::string> csv_args{"export", "--request", (dir / "law.json").string(), "--out",
                                      "-"};
    csv_args.insert(csv_args.end(), c.extra.begin(), c.extra.end());
    std::vector<std::string> st_args = csv_args;
    st_args.insert(st_args.end(), {"--format", "st", "--st-name", "TABLE_INDEX"});
    const RunResult csv = run_slosh(csv_args);
    const RunResult st = run_slosh(st_args);
    ASSERT_EQ(csv.exit_code, 0) << csv.err;
    ASSERT_EQ(st.exit_code, 0) << st.err;
    const Csv table = read_csv(csv.out);
    const StRows rows = read_st_rows(st.out);
    std::string names;
    for (const std::string& n : rows.names) names += (names.empty() ? "" : ",") + n;
    EXPECT_EQ(names, table.header);
    EXPECT_NE(st.out.find("TYPE\n  " + c.type + " :\n  STRUCT\n"), std::string::npos) << st.out;
    EXPECT_NE(st.out.find("TABLE_INDEX : ARRAY[0.." + std::to_string(table.rows.size() - 1) +
                          "] OF " + c.type + " := ["),
              std::string::npos);
    EXPECT_NE(
        st.out.find(c.motion["type"] == "arc" ? "   path: one arc (a rotary table), rotation 90 deg"
                                              : "   path: a path of 2 segments (lines and arcs)"),
        std::string::npos)
        << st.out.substr(0, 800);
    if (!c.dwell.empty()) {
      EXPECT_NE(st.out.find(c.dwell), std::string::npos) << st.out.substr(0, 800);
    }
    ASSERT_EQ(rows.rows.size(), table.rows.size());
    for (std::size_t k = 0; k < table.rows.size(); ++k) {
      ASSERT_EQ(rows.rows[k].size(), table.rows[k].size()) << k;
      for (std::size_t i = 0; i < table.rows[k].size(); ++i) {
        EXPECT_NEAR(rows.rows[k][i], table.rows[k][i], 1e-13 * (1.0 + std::abs(table.rows[k][i])))
            << k << " " << i;
      }
    }
  }
  // An arc whose container keeps its heading is a carriage on a curved track, not a table.
  json track = arc;
  track["container_turns"] = false;
  write_file(dir / "track.json", law_request(track, 1.0).dump());
  const RunResult st = run_slosh(
      {"export", "--request", (dir / "track.json").string(), "--out", "-", "--format", "st"});
  ASSERT_EQ(st.exit_code, 0) << st.err;
  EXPECT_NE(st.out.find("   path: one arc (a curved track), angle 90 deg, length "),
            std::string::npos)
      << st.out.substr(0, 800);
  EXPECT_NE(st.out.find("the container keeps its heading"), std::string::npos);
}

// GET /v1/plans/{key}/cam.csv and cam.st of a plan along an arc: the bytes `slosh export`
// writes for the same plan request and options (the pose, the table's rotation, and the
// master-axis cam in degrees of table rotation). Before, the routes wrote s alone.
TEST(PathCamHttp, CamRoutesOfAnArcPlanAreTheCliExport) {
  const TempDir dir;
  json request = law_request({{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}}, 1.2);
  request.erase("law");
  request["strategy"] = "min_jerk_band";
  write_file(dir / "plan.json", request.dump());
  test::Server server({"--cache", ""});
  auto client = server.client();
  const auto posted = client.Post("/v1/plans", request.dump(), "application/json");
  ASSERT_TRUE(posted);
  ASSERT_EQ(posted->status, 200) << posted->body;
  const std::string key = json::parse(posted->body)["key"];
  struct Case {
    std::string route;
    std::vector<std::string> flags;
  };
  for (const Case& c :
       {Case{"cam.csv", {}}, Case{"cam.st", {"--format", "st"}},
        Case{"cam.csv?master_period=360&master_start=30&master_end=210",
             {"--master-period", "360", "--master-start", "30", "--master-end", "210"}},
        Case{"cam.st?master_period=360&master_start=30&master_end=210",
             {"--format", "st", "--master-period", "360", "--master-start", "30", "--master-end",
              "210"}}}) {
    SCOPED_TRACE(c.route);
    const auto got = client.Get("/v1/plans/" + key + "/" + c.route);
    ASSERT_TRUE(got);
    ASSERT_EQ(got->status, 200) << got->body;
    std::vector<std::string> args{
        "export", "--request", (dir / "plan.json").string(), "--out", "-", "--cache", ""};
    args.insert(args.end(), c.flags.begin(), c.flags.end());
    const RunResult cli = run_slosh(args);
    ASSERT_EQ(cli.exit_code, 0) << cli.err;
    EXPECT_EQ(cli.out, got->body);
    if (c.route == "cam.csv") {
      EXPECT_EQ(got->body.substr(0, got->body.find('\n')),
                "t_s,s_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3,x_mm,y_mm,theta_deg,"
                "table_deg");
      const Csv cam = read_csv(got->body);
      EXPECT_EQ(cam.rows.back()[8], 90.0);
      for (const std::vector<double>& row : cam.rows) {
        const double phi = row[1] / 300.0;
        EXPECT_NEAR(row[5], 300.0 * std::sin(phi), 1e-9) << row[0];
        EXPECT_NEAR(row[6], 300.0 * (1.0 - std::cos(phi)), 1e-9) << row[0];
      }
    }
  }
}

}  // namespace test_path_cam_export
}  // namespace slosh
