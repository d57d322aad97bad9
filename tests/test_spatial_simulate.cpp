// POST /v1/simulate and `slosh simulate` with format.motion (SPEC §14), end to end on the real
// binary: an arc's answer equals the core's planar models called here, a line motion gives the
// straight line's wave in any direction, every bad motion is refused with its exact sentence,
// and `slosh simulate --trajectory` on a measured run gives the core's peaks. (Plans, min-time
// and cam export along paths: test_path_plan.cpp, test_min_time_path.cpp,
// test_path_cam_export.cpp.)

#include <httplib.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/format_json.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/motion/sampled_trajectory.hpp"
#include "slosh/core/response/planar_response.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_spatial_simulate {

using nlohmann::json;
using test::Server;

constexpr double kPi{std::numbers::pi};

json format_json_of(double stroke_mm) {
  return json{{"container", {{"radius_mm", 48.5}, {"height_mm", 150}}},
              {"fill_height_mm", 82},
              {"fluid", "water"},
              {"stroke_mm", stroke_mm},
              {"motion_time_s", 1.2}};
}

json arc_body() {
  json format = format_json_of(0);
  format.erase("stroke_mm");
  format["motion"] = {
      {"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}, {"container_turns", true}};
  return {{"format", format}, {"law", {{"type", "seven_segment_uniform"}}}};
}

json post(Server& server, const std::string& route, const json& body, int status = 200) {
  auto client = server.client();
  const auto r = client.Post(route, body.dump(), "application/json");
  EXPECT_TRUE(r) << route;
  if (!r) return json::object();
  EXPECT_EQ(r->status, status) << r->body;
  return json::parse(r->body);
}

// The model the API builds by default (3 modes, thesis damping, default alpha) on the format.
SloshingModel default_model(const json& format) {
  json plain = format;
  plain.erase("motion");
  if (!plain.contains("stroke_mm")) plain["stroke_mm"] = 1.0;
  ModelOptions options;
  options.modes = 3;
  return make_sloshing_model(api::parse_format(plain), options);
}

void expect_peaks(const json& got, const PlanarPeaks& want, double rel) {
  auto near = [&](const char* key, double value) {
    EXPECT_NEAR(got[key].get<double>(), value, rel * std::max(1.0, std::abs(value))) << key;
  };
  near("eta_motion_mm", want.motion.value * 1e3);
  near("eta_rest_mm", want.rest.value * 1e3);
  near("t_motion_s", want.motion.time);
  near("t_rest_s", want.rest.time);
  near("direction_motion_deg", want.motion.direction * 180 / kPi);
  near("direction_rest_deg", want.rest.direction * 180 / kPi);
}

TEST(SpatialSimulate, ArcAnswerEqualsTheCorePlanarModels) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const json body = arc_body();
  const json r = post(server, "/v1/simulate", body);
  ASSERT_TRUE(r.contains("prediction")) << r.dump();

  const PlanarPath path = PlanarPath::arc(0.3, kPi / 2, true);
  const SevenSegmentLaw law(uniform_durations(1.2), path.length());
  const PlanarDrive drive(path, law.law());
  const SloshingModel model = default_model(body["format"]);
  expect_peaks(r["prediction"]["linear"], planar_linear_peaks(model, drive, 1.0), 1e-10);
  expect_peaks(r["prediction"]["nonlinear"], planar_nonlinear_peaks(model, drive, 1.0), 1e-10);
  EXPECT_NEAR(r["motion"]["length_mm"].get<double>(), 300 * kPi / 2, 1e-9);
  EXPECT_EQ(r["motion"]["type"], "arc");
  // The motion as simulated, canonical (the start heading filled in).
  json canonical = body["format"]["motion"];
  canonical["start_heading_deg"] = 0.0;
  EXPECT_EQ(r["format"]["motion"], canonical);
  // The normal acceleration turns the wave off the tangent: not the straight line's answer.
  const SevenSegmentLaw straight(uniform_durations(1.2), path.length());
  const PlanarDrive line(PlanarPath::line(path.length()), straight.law());
  EXPECT_GT(std::abs(r["prediction"]["linear"]["eta_motion_mm"].get<double>() -
                     planar_linear_peaks(model, line, 1.0).motion.value * 1e3),
            0.1);
}

TEST(SpatialSimulate, LineMotionGivesTheStrokesWaveInAnyDirection) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const json law{{"type", "seven_segment_uniform"}};
  const json straight =
      post(server, "/v1/simulate", {{"format", format_json_of(800)}, {"law", law}});
  for (const double direction : {0.0, 37.0}) {
    json format = format_json_of(0);
    format.erase("stroke_mm");
    format["motion"] = {{"type", "line"}, {"length_mm", 800}, {"direction_deg", direction}};
    const json r = post(server, "/v1/simulate", {{"format", format}, {"law", law}});
    for (const char* model : {"linear", "nonlinear"}) {
      const json& got = r["prediction"][model];
      const json& want = straight["prediction"][model];
      for (const char* key : {"eta_motion_mm", "eta_rest_mm"}) {
        EXPECT_NEAR(got[key].get<double>(), want[key].get<double>(), 1e-7 * want[key].get<double>())
            << model << ' ' << key << " at " << direction << " deg";
      }
      EXPECT_NEAR(got["t_motion_s"].get<double>(), want["t_motion_s"].get<double>(), 1e-6);
      // The wave peaks on the wall along the line (ahead or behind the container).
      const double d = std::remainder(got["direction_motion_deg"].get<double>() - direction, 180.0);
      EXPECT_NEAR(d, 0.0, 1e-6) << model;
    }
  }
}

TEST(SpatialSimulate, PlansTakeALineMotionAsTheStroke) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  json by_stroke{{"format", format_json_of(800)}, {"strategy", "baseline"}};
  json by_line = by_stroke;
  by_line["format"].erase("stroke_mm");
  by_line["format"]["motion"] = {{"type", "line"}, {"length_mm", 800}, {"direction_deg", 90}};
  const json a = post(server, "/v1/plans", by_stroke);
  const json b = post(server, "/v1/plans", by_line);
  EXPECT_EQ(a["key"], b["key"]);
  EXPECT_EQ(a["prediction"], b["prediction"]);
}

struct Refusal {
  const char* what;
  json body;
  const char* field;
  const char* message;
};

json with_motion(const json& motion, bool path_motion = true) {
  json body = arc_body();
  body["format"]["motion"] = motion;
  if (!path_motion) {
    body["format"].erase("motion_time_s");
    body.erase("law");
  }
  return body;
}

json trajectory(std::vector<double> t, std::vector<double> x) {
  std::vector<double> y(x.size(), 0.0);
  return {{"type", "trajectory"}, {"t_s", t}, {"x_mm", x}, {"y_mm", y}};
}

TEST(SpatialSimulate, BadMotionsAreRefusedNamingTheMember) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const json arc{{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}};
  json radius = arc;
  radius["radius_mm"] = -5;
  json angle = arc;
  angle["angle_deg"] = 0;
  const json joined{{"type", "path"},
                    {"segments",
                     {{{"line_mm", 200}},
                      {{"arc", {{"radius_mm", 100}, {"angle_deg", 90}}}},
                      {{"line_mm", 100}, {"heading_deg", 45}}}}};
  const json bad_radius_in_path{
      {"type", "path"},
      {"segments",
       {{{"line_mm", 200}}, {{"line_mm", 10}}, {{"arc", {{"radius_mm", 0}, {"angle_deg", 30}}}}}}};
  std::vector<double> fine_t, fine_x;
  for (int i = 0; i <= 400; ++i) {
    fine_t.push_back(i * 0.005);
    fine_x.push_back(100.0 * std::sin(i * 0.005));
  }
  std::vector<double> same_t = fine_t;
  same_t[13] = same_t[12];
  json with_null = trajectory(fine_t, fine_x);
  with_null["x_mm"][7] = nullptr;
  json both = arc_body();
  both["format"]["stroke_mm"] = 800;
  const std::vector<Refusal> refusals{
      {"radius <= 0", with_motion(radius), "format.motion.radius_mm",
       "format.motion.radius_mm = -5 is out of range: allowed > 0 and <= 100000 mm"},
      {"angle 0", with_motion(angle), "format.motion.angle_deg",
       "format.motion.angle_deg = 0 is not allowed: an arc turns, allowed -3600 to 3600 deg "
       "except 0 (signed, left positive)"},
      {"radius 0 in a path", with_motion(bad_radius_in_path),
       "format.motion.segments[2].arc.radius_mm",
       "format.motion.segments[2].arc.radius_mm = 0 is out of range: allowed > 0 and <= 100000 "
       "mm"},
      {"no common tangent", with_motion(joined), "format.motion.segments[2]",
       "format.motion.segments[2] starts at heading 45 deg but the path arrives at heading 90 deg: "
       "lines and arcs must join with a common tangent (within 1e-6 rad)"},
      {"times not increasing", with_motion(trajectory(same_t, fine_x), false),
       "format.motion.t_s[13]",
       "format.motion.t_s[13] = 0.06 s must be greater than t[12] = 0.06 s (times strictly "
       "increasing)"},
      {"null sample", with_motion(with_null, false), "format.motion.x_mm[7]",
       "format.motion.x_mm[7] is required: a number, allowed -1000000000 to 1000000000"},
      {"three samples", with_motion(trajectory({0, 0.1, 0.2}, {0, 1, 2}), false),
       "format.motion.t_s", "format.motion.t_s: a trajectory needs at least 4 samples, got 3"},
      {"too coarse", with_motion(trajectory({0, 0.1, 0.2, 0.3, 0.4}, {0, 1, 2, 3, 4}), false),
       "format.motion.t_s[1]",
       "format.motion.t_s[1]: samples 0 and 1 are 0.1 s apart; the first sloshing mode "
       "(3.065303562 Hz) needs at least 61.30607125 samples per second (a spacing of at most "
       "0.01631159818 s)"},
      {"stroke and motion", both, "format.stroke_mm",
       "format.stroke_mm and format.motion both give the move: give one of them (stroke_mm is the "
       "short form of a motion of type \"line\")"},
  };
  for (const Refusal& r : refusals) {
    const json e = post(server, "/v1/simulate", r.body, 422);
    ASSERT_TRUE(e.contains("error")) << r.what << ": " << e.dump();
    EXPECT_EQ(e["error"]["field"], r.field) << r.what;
    EXPECT_EQ(e["error"]["message"], r.message) << r.what;
  }
}

std::string num(double v) {
  return json(v).dump();
}

// The measured run's commanded trajectory through the CLI gives the peaks of the core's models
// on the same file, at the measured first mode and the JDSMC damping (as test_planar_measured).
TEST(SpatialSimulate, CliTrajectoryOfAMeasuredRunGivesTheCorePeaks) {
  const std::string csv = std::string(SLOSH_SOURCE_DIR) +
                          "/tests/data/bologna-4d/TRD_2D_0.3m_2.2s_270deg.trajectory.csv";
  const double omega_scale = 18.961 / natural_frequency(0.049, 0.080, 1);
  const json request{
      {"format", {{"container", {{"radius_mm", 49}}}, {"fill_height_mm", 80}, {"fluid", "water"}}},
      {"rest_time_s", 4},
      {"options", {{"damping", "paper"}, {"model", {{"omega_scale", omega_scale}}}}}};
  const test::TempDir dir;
  test::write_file(dir / "request.json", request.dump());
  const test::RunResult run = test::run_slosh(
      {"simulate", "--request", (dir / "request.json").string(), "--trajectory", csv});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json r = json::parse(run.out);

  std::ifstream in(csv);
  TrajectorySamples samples = read_pose_csv(in, "run");
  // The CLI puts the samples in the request in mm and degrees, read back as m and rad: the
  // same round trip here, so the answers are equal to the last bits.
  for (std::vector<double>* v : {&samples.x, &samples.y, &samples.z}) {
    for (double& value : *v) value = value * 1e3 * 1e-3;
  }
  for (double& value : samples.theta) value = value * (1.0 / (kPi / 180.0)) * (kPi / 180.0);
  const SampledTrajectory trajectory(std::move(samples));
  Format f;
  f.container.radius = 0.049;
  f.fill_height = 0.080;
  ModelOptions options;
  options.damping = DampingCorrelation::kPaper;
  options.omega_scale = omega_scale;
  const SloshingModel model = make_sloshing_model(f, options);
  const PlanarDrive drive(trajectory);
  expect_peaks(r["prediction"]["linear"], planar_linear_peaks(model, drive, 4.0), 1e-12);
  expect_peaks(r["prediction"]["nonlinear"], planar_nonlinear_peaks(model, drive, 4.0), 1e-12);
  EXPECT_EQ(r["motion"]["samples"], trajectory.size());
  EXPECT_FALSE(r["format"].contains("stroke_mm"));
}

// A plain CSV in mm and degrees (with a byte order mark) is the same trajectory as the JSON
// samples; a bad line is named.
TEST(SpatialSimulate, CliPlainCsvEqualsTheJsonTrajectoryAndNamesABadLine) {
  std::vector<double> t, x, y, theta;
  std::string text = "t_s,x_mm,y_mm,theta_deg\n";
  for (int i = 0; i <= 300; ++i) {
    const double ti = i * 0.004;
    const double phi = kPi / 2 * ti * ti * (3 - 2 * ti / 1.2) / 1.44;  // smooth 0 -> 90 deg
    t.push_back(ti);
    x.push_back(std::round(3e5 * std::sin(phi)) / 1e3);
    y.push_back(std::round(3e5 * (1 - std::cos(phi))) / 1e3);
    theta.push_back(std::round(phi * 180 / kPi * 1e6) / 1e6);
    text +=
        num(t.back()) + "," + num(x.back()) + "," + num(y.back()) + "," + num(theta.back()) + "\n";
  }
  json request{
      {"format",
       {{"container", {{"radius_mm", 48.5}}}, {"fill_height_mm", 82}, {"fluid", "water"}}}};
  const test::TempDir dir;
  test::write_file(dir / "request.json", request.dump());
  // Saved as a spreadsheet's "CSV UTF-8" does: a byte order mark before the header.
  test::write_file(dir / "run.csv", "\xEF\xBB\xBF" + text);
  const test::RunResult run =
      test::run_slosh({"simulate", "--request", (dir / "request.json").string(), "--trajectory",
                       (dir / "run.csv").string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  request["format"]["motion"] = {
      {"type", "trajectory"}, {"t_s", t}, {"x_mm", x}, {"y_mm", y}, {"theta_deg", theta}};
  const json posted = post(server, "/v1/simulate", request);
  const json cli = json::parse(run.out)["prediction"];
  for (const char* model : {"linear", "nonlinear"}) {
    for (const auto& [key, value] : posted["prediction"][model].items()) {
      // The CLI's samples go through SI and back to mm: equal to round-off. The wall direction
      // of a peak where the wave swirls (|E| nearly flat over its maximum) turns with the
      // peak's time, which that round-off moves by ~1e-10 s: ~1e-7 deg at omega_1 = 19 rad/s.
      const bool direction = key.rfind("direction", 0) == 0;
      EXPECT_NEAR(cli[model][key].get<double>(), value.get<double>(),
                  direction ? 1e-5 : 1e-9 * std::max(1.0, std::abs(value.get<double>())))
          << model << ' ' << key;
    }
  }

  test::write_file(dir / "bad.csv", "t_s,x_mm,y_mm\n0,0,0\n0.1,nan,0\n");
  const test::RunResult bad =
      test::run_slosh({"simulate", "--request", (dir / "request.json").string(), "--trajectory",
                       (dir / "bad.csv").string()});
  EXPECT_EQ(bad.exit_code, 2);
  const json e = json::parse(bad.err);
  EXPECT_EQ(e["error"]["field"], "--trajectory");
  EXPECT_EQ(e["error"]["message"], "--trajectory " + (dir / "bad.csv").string() +
                                       " line 3: x_mm = \"nan\" must be a finite number");

  // A sample the checks of the motion refuse is named by its line of the file, not by the
  // request's format.motion (which the user did not write): a row repeated on line 5, after a
  // blank line 3, is sample 2.
  test::write_file(dir / "repeat.csv", "t_s,x_mm,y_mm\n0,0,0\n\n0.004,0,0\n0.004,0,0\n" +
                                           std::string("0.008,0,0\n0.012,0,0\n"));
  const test::RunResult repeat =
      test::run_slosh({"simulate", "--request", (dir / "request.json").string(), "--trajectory",
                       (dir / "repeat.csv").string()});
  EXPECT_EQ(repeat.exit_code, 2);
  const json r = json::parse(repeat.err);
  EXPECT_EQ(r["error"]["field"], "--trajectory");
  EXPECT_EQ(r["error"]["message"].get<std::string>().rfind(
                "--trajectory " + (dir / "repeat.csv").string() +
                    " line 5 (sample 2, from 0): t_s[2] = 0.004 s must be ",
                0),
            0U)
      << r["error"]["message"];
}

// One sample out of line with its neighbours (a logger's extra sample 1 ns after another and
// 1 um off) makes the samples' spline accelerate beyond anything the models describe: the
// refusal names that sample and the acceleration (it said only "outside what the model
// describes").
TEST(SpatialSimulate, ADivergingTrajectoryIsRefusedAtItsSample) {
  std::vector<double> t, x, y;
  for (int i = 0; i <= 600; ++i) {
    t.push_back(i * 0.002);
    x.push_back(150.0 * (1.0 - std::cos(kPi * t.back() / 1.2)));
    y.push_back(0.0);
    if (i == 300) {
      t.push_back(0.600000001);
      x.push_back(x.back() + 1e-3);
      y.push_back(0.0);
    }
  }
  json request{{"format",
                {{"container", {{"radius_mm", 48.5}, {"height_mm", 150}}},
                 {"fill_height_mm", 82},
                 {"fluid", "water"},
                 {"motion", {{"type", "trajectory"}, {"t_s", t}, {"x_mm", x}, {"y_mm", y}}}}}};
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const json e = post(server, "/v1/simulate", request, 422)["error"];
  const std::string field = e["field"];
  EXPECT_TRUE(field == "format.motion.x_mm[300]" || field == "format.motion.x_mm[301]") << field;
  const std::string message = e["message"];
  EXPECT_EQ(message.rfind(field + ": the ", 0), 0U) << message;
  EXPECT_NE(message.find(" diverges for this motion on this format: the motion is outside what "
                         "the model describes (the samples' spline accelerates at "),
            std::string::npos)
      << message;
  EXPECT_NE(message.find(" m/s^2 horizontally there, t = 0.6"), std::string::npos) << message;
}

// The models take a trajectory at rest before its first sample and after its last: one that
// starts or ends moving gets a warning naming the end, its sample and the speed. The samples are
// cubics in t, which the not-a-knot splines reproduce, so the speeds are the cubics' own.
TEST(SpatialSimulate, ATrajectoryThatStartsOrEndsMovingIsWarnedOf) {
  // x(u) = a u + b u^2 mm, theta(u) = c u^2 deg, u = t - 0.5 s over 0.8 s at 5 ms.
  auto cubic = [](double a, double b, double c) {
    std::vector<double> t, x, y, theta;
    for (int i = 0; i <= 160; ++i) {
      const double u = 0.005 * i;
      t.push_back(0.5 + u);
      x.push_back(a * u + b * u * u);
      y.push_back(0.0);
      theta.push_back(c * u * u);
    }
    return json{{"type", "trajectory"}, {"t_s", t}, {"x_mm", x}, {"y_mm", y}, {"theta_deg", theta}};
  };
  auto body = [](const json& motion, bool rectangular) {
    json format{{"container", {{"radius_mm", 48.5}}}, {"fill_height_mm", 82}, {"fluid", "water"}};
    if (rectangular) {
      format["container"] = {{"shape", "rectangular"}, {"length_mm", 100}, {"width_mm", 60}};
    }
    format["motion"] = motion;
    return json{{"format", format}};
  };
  auto moving = [](const json& answer) {
    std::vector<std::string> out;
    for (const json& w : answer["warnings"]) {
      if (w.get<std::string>().rfind("the trajectory ", 0) == 0) out.push_back(w);
    }
    return out;
  };
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  // Starts at dx/du = 300 mm/s, ends at 300 - 2 * 187.5 * 0.8 = 0, turning at 0 deg/s first.
  const json starts = post(server, "/v1/simulate", body(cubic(300.0, -187.5, 0.0), false));
  EXPECT_EQ(moving(starts),
            std::vector<std::string>{
                "the trajectory starts moving: at its first sample (t_s[0] = 0.5 s) the container "
                "moves at 300 mm/s and turns at 0 deg/s; the models take the liquid at rest "
                "there, as if the container had always moved at that speed: the wave of the "
                "acceleration that brought it to that speed is not in the prediction; start the "
                "trajectory at rest"});
  // Ends at 2 * 250 * 0.8 = 400 mm/s turning at 2 * 45 * 0.8 = 72 deg/s; starts at rest. A
  // rectangular tank's answer warns alike.
  for (const bool rectangular : {false, true}) {
    const json ends = post(server, "/v1/simulate", body(cubic(0.0, 250.0, 45.0), rectangular));
    EXPECT_EQ(moving(ends),
              std::vector<std::string>{
                  "the trajectory ends moving: at its last sample (t_s[160] = 1.3 s) the "
                  "container moves at 400 mm/s and turns at 72 deg/s; the models see no "
                  "acceleration after it, as if the container went on at that speed through "
                  "the rest window: the wave of stopping it is not in the prediction (eta_rest "
                  "in particular); the models stop its turning at once at that sample: the rest "
                  "window holds the liquid's spin running down after that sudden stop, not the "
                  "turning going on nor a real stop of it; end the trajectory at rest"})
        << rectangular;
  }
  // At rest at both ends (x = 3 u^2 - 2 u^3 scaled: zero slope at 0 and 0.8 s): no warning.
  json rest = cubic(0.0, 0.0, 0.0);
  for (std::size_t i = 0; i < rest["t_s"].size(); ++i) {
    const double u = 0.005 * static_cast<double>(i) / 0.8;
    rest["x_mm"][i] = 200.0 * u * u * (3.0 - 2.0 * u);
  }
  EXPECT_TRUE(moving(post(server, "/v1/simulate", body(rest, false))).empty());
}

/// A 500 Hz trajectory of `duration` s whose clock starts at t0: x(u), theta(u) of the time u
/// since its first sample.
json clocked_trajectory(double t0, double duration, const std::function<double(double)>& x,
                        const std::function<double(double)>& theta) {
  std::vector<double> t, xs, ys, th;
  const int n = static_cast<int>(std::lround(duration * 500.0));
  for (int i = 0; i <= n; ++i) {
    const double u = i / 500.0;
    t.push_back(t0 + u);
    xs.push_back(x(u));
    ys.push_back(0.0);
    th.push_back(theta(u));
  }
  return json{{"type", "trajectory"}, {"t_s", t}, {"x_mm", xs}, {"y_mm", ys}, {"theta_deg", th}};
}

// One clock for the whole answer: a log whose samples start at 0.5 s or at 1e6 s (a machine's
// clock) has the peaks of the same log started at 0 (the core's planar models on it), with
// t_motion_s, t_rest_s and the series' t_s shifted by exactly its first sample's time, as the
// samples and the warnings name them. Before, the peaks and the series counted from the first
// sample while the warnings quoted the samples' times.
TEST(SpatialSimulate, ATrajectorysTimesAreOnItsSamplesClock) {
  const auto x = [](double u) { return 100.0 * (1.0 - std::cos(kPi * std::min(u, 0.8) / 0.8)); };
  const auto still = [](double) { return 0.0; };
  json format{{"container", {{"radius_mm", 48.5}}}, {"fill_height_mm", 82}, {"fluid", "water"}};
  format["motion"] = clocked_trajectory(0.0, 1.0, x, still);
  std::vector<double> t, xs, ys;
  for (const json& v : format["motion"]["t_s"]) t.push_back(v.get<double>());
  for (const json& v : format["motion"]["x_mm"]) xs.push_back(v.get<double>() * 1e-3);
  ys.assign(t.size(), 0.0);
  const SampledTrajectory samples(TrajectorySamples{t, xs, ys, {}, {}});
  json timed = format;  // the model's format needs a motion time, which a trajectory has not
  timed["motion_time_s"] = 1.0;
  const SloshingModel model = default_model(timed);
  const PlanarDrive drive(samples);
  const PlanarPeaks linear = planar_linear_peaks(model, drive, 1.0);
  const PlanarPeaks nonlinear = planar_nonlinear_peaks(model, drive, 1.0);
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const json origin = post(server, "/v1/simulate", {{"format", format}, {"sample_period_s", 0.01}});
  for (const double t0 : {0.5, 1e6}) {
    format["motion"] = clocked_trajectory(t0, 1.0, x, still);
    const json answer =
        post(server, "/v1/simulate", {{"format", format}, {"sample_period_s", 0.01}});
    // The clock's rounding at 1e6 s (1e-10 s) moves the samples by ~1e-11 m.
    const double rel = t0 > 1.0 ? 1e-4 : 1e-9, dt = t0 > 1.0 ? 1e-6 : 1e-9;
    for (const auto& [name, want] : {std::pair{"linear", &linear}, {"nonlinear", &nonlinear}}) {
      const json& got = answer["prediction"][name];
      EXPECT_NEAR(got["eta_motion_mm"].get<double>(), want->motion.value * 1e3, rel) << name;
      EXPECT_NEAR(got["eta_rest_mm"].get<double>(), want->rest.value * 1e3, rel) << name;
      EXPECT_NEAR(got["t_motion_s"].get<double>() - t0, want->motion.time, dt) << name << t0;
      EXPECT_NEAR(got["t_rest_s"].get<double>() - t0, want->rest.time, dt) << name << t0;
      // Within the samples' span, and the rest window after the last sample, on their clock.
      EXPECT_GE(got["t_motion_s"].get<double>(), t0) << name;
      EXPECT_GT(got["t_rest_s"].get<double>(), t0 + 1.0) << name;
    }
    const json& series = answer["series"]["t_s"];
    ASSERT_EQ(series.size(), origin["series"]["t_s"].size());
    EXPECT_EQ(series[0].get<double>(), t0);
    for (std::size_t k = 0; k < series.size(); k += 17) {
      EXPECT_NEAR(series[k].get<double>(), t0 + 0.01 * static_cast<double>(k), 1e-9 * t0) << k;
      EXPECT_NEAR(answer["series"]["eta_linear_mm"][k].get<double>(),
                  origin["series"]["eta_linear_mm"][k].get<double>(), rel)
          << k;
    }
  }
}

// A container spinning in place at 600 deg/s from its first sample to its last: the spin term
// takes the turning rate, 0 outside the samples, so the models start the turning at once at the
// first sample and stop it at once at the last, and the warnings say so. What they say is what
// was computed: the rest window's peak is the vortex at the stop (t_rest_s the last sample's
// time, the motion's peak there too), running down after it, not a turning that goes on (whose
// vortex would keep rising as the liquid spins up).
TEST(SpatialSimulate, ATurningEndSaysTheModelsStopTheTurning) {
  const auto spin = [](double u) { return 600.0 * u; };
  json format{{"container", {{"radius_mm", 48.5}}}, {"fill_height_mm", 82}, {"fluid", "water"}};
  format["motion"] = clocked_trajectory(
      0.0, 1.0, [](double) { return 0.0; }, spin);
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const json answer =
      post(server, "/v1/simulate", {{"format", format}, {"sample_period_s", 0.001}});
  EXPECT_EQ(answer["warnings"],
            json::array(
                {"the trajectory starts moving: at its first sample (t_s[0] = 0 s) the container "
                 "moves at 0 mm/s and turns at 600 deg/s; the models start its turning at once at "
                 "that sample with the liquid at rest: the liquid's spin-up from that sudden "
                 "start is in the prediction, not the turning before it; start the trajectory at "
                 "rest",
                 "the trajectory ends moving: at its last sample (t_s[500] = 1 s) the container "
                 "moves at 0 mm/s and turns at 600 deg/s; the models stop its turning at once at "
                 "that sample: the rest window holds the liquid's spin running down after that "
                 "sudden stop, not the turning going on nor a real stop of it; end the trajectory "
                 "at rest"}));
  for (const char* name : {"linear", "nonlinear"}) {
    const json& p = answer["prediction"][name];
    EXPECT_NEAR(p["t_rest_s"].get<double>(), 1.0, 1e-6) << name;
    EXPECT_NEAR(p["eta_rest_mm"].get<double>(), p["eta_motion_mm"].get<double>(), 1e-9) << name;
  }
  // The series falls from the stop on (the spin runs down); a turning that went on would rise.
  const json& eta = answer["series"]["eta_linear_mm"];
  EXPECT_GT(eta[1000].get<double>(), 0.0);
  EXPECT_LT(eta[1500].get<double>(), eta[1000].get<double>());
  EXPECT_LT(eta[2000].get<double>(), eta[1500].get<double>());
}

}  // namespace test_spatial_simulate
}  // namespace slosh
