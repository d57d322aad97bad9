// POST /v1/plans and `slosh plan` along arcs and paths (SPEC §14), end to end on the real binary:
// the plan's figures are the planar models' of its law (recomputed here from the durations it
// returns), the compact view carries the motion, the recipe key holds the motion while stroke_mm
// and line motions keep theirs, and every refusal has its exact sentence.

#include <httplib.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/response/planar_response.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_path_plan_api {

using nlohmann::json;
using test::Server;

constexpr double kPi{std::numbers::pi};

json water_format() {
  return json{{"container", {{"radius_mm", 48.5}, {"height_mm", 150}}},
              {"fill_height_mm", 82},
              {"fluid", "water"},
              {"motion_time_s", 1.2}};
}

/// The 90-degree index of a 300 mm table.
json arc_plan(const std::string& strategy) {
  json format = water_format();
  format["motion"] = {{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}};
  return {{"format", format}, {"strategy", strategy}};
}

json stroke_plan(double stroke_mm) {
  json format = water_format();
  format["stroke_mm"] = stroke_mm;
  return {{"format", format}, {"strategy", "notch"}};
}

json post(Server& server, const std::string& route, const json& body, int status = 200) {
  auto client = server.client();
  const auto r = client.Post(route, body.dump(), "application/json");
  EXPECT_TRUE(r) << route;
  if (!r) return json::object();
  EXPECT_EQ(r->status, status) << r->body;
  return json::parse(r->body);
}

std::string error_of(const json& body) {
  try {
    (void)api::parse_plan_request(body);
  } catch (const api::ApiError& e) {
    return e.field() + " | " + e.what();
  }
  return "accepted";
}

TEST(PathPlanApi, AnArcPlansEndToEndWithThePlanarModelsFigures) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const json plan = post(server, "/v1/plans", arc_plan("notch"));
  // notch's law is worse_than_baseline on the arc (its normal acceleration is not shaped): the
  // plan is acceptable, not optimal, and says why first.
  ASSERT_EQ(plan["status"], "acceptable") << plan.dump();
  EXPECT_EQ(plan["message"].get<std::string>().rfind(
                "notch acceptable: not optimal: the law sloshes more than the uniform law "
                "(worse_than_baseline)",
                0),
            0u)
      << plan["message"];
  // The motion as planned, canonical: the defaults filled in.
  json canonical = arc_plan("notch")["format"]["motion"];
  canonical["container_turns"] = true;
  canonical["start_heading_deg"] = 0.0;
  EXPECT_EQ(plan["format"]["motion"], canonical);
  const double length_mm = 300.0 * kPi / 2.0;
  EXPECT_NEAR(plan["format"]["stroke_mm"].get<double>(), length_mm, 1e-9);
  EXPECT_EQ(plan["path"]["type"], "arc");
  EXPECT_EQ(plan["path"]["container_turns"], true);
  EXPECT_NE(plan["message"].get<std::string>().find(
                "the normal acceleration s'^2/rho on the arcs is not shaped"),
            std::string::npos)
      << plan["message"];
  // The figures are the planar models' of the returned law along the arc, computed here.
  const api::PlanRequest request = api::parse_plan_request(arc_plan("notch"));
  const SloshingModel model = make_sloshing_model(request.format, request.options.model);
  ASSERT_NEAR(plan["model"]["omega_rad_s"][0].get<double>(), model.omega1(), 1e-9);
  const Durations d = plan["durations_s"].get<Durations>();
  const PlanarPath arc = PlanarPath::arc(0.3, kPi / 2, true);
  const PlanarDrive drive(arc, SevenSegmentLaw(d, arc.length()).law());
  const PlanarPeaks nonlinear = planar_nonlinear_peaks(model, drive, 1.0);
  const PlanarPeaks linear = planar_linear_peaks(model, drive, 1.0);
  const json& p = plan["path"]["prediction"];
  EXPECT_NEAR(p["nonlinear"]["eta_motion_mm"].get<double>(), nonlinear.motion.value * 1e3, 1e-9);
  EXPECT_NEAR(p["nonlinear"]["eta_rest_mm"].get<double>(), nonlinear.rest.value * 1e3, 1e-9);
  EXPECT_NEAR(p["nonlinear"]["direction_motion_deg"].get<double>(),
              nonlinear.motion.direction * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(p["linear"]["eta_rest_mm"].get<double>(), linear.rest.value * 1e3, 1e-9);
  EXPECT_EQ(plan["prediction"]["nonlinear"]["eta_motion_mm"], p["nonlinear"]["eta_motion_mm"]);
  EXPECT_EQ(plan["prediction"]["linear"]["eta_rest_mm"], p["linear"]["eta_rest_mm"]);
  // The compact view carries the motion's type and the total acceleration's peak.
  const json compact = post(server, "/v1/plans?view=compact", arc_plan("notch"));
  EXPECT_EQ(compact["law"]["motion"], json({{"type", "arc"}}));
  EXPECT_EQ(compact["path"]["a_total_peak"],
            std::round(p["kinematics"]["a_total_peak"].get<double>() * 1e3) / 1e3);
}

TEST(PathPlanApi, RecipeKeysHoldTheMotionAndLinesKeepTheirs) {
  const std::string stroke = api::recipe_key(api::parse_plan_request(stroke_plan(800)));
  for (double direction : {0.0, 37.0}) {
    json line = stroke_plan(800);
    line["format"].erase("stroke_mm");
    line["format"]["motion"] = {{"type", "line"}, {"length_mm", 800}, {"direction_deg", direction}};
    EXPECT_EQ(api::recipe_key(api::parse_plan_request(line)), stroke) << direction;
  }
  EXPECT_FALSE(api::canonical_recipe(api::parse_plan_request(stroke_plan(800))).contains("motion"));
  const api::PlanRequest arc = api::parse_plan_request(arc_plan("notch"));
  const json recipe = api::canonical_recipe(arc);
  ASSERT_TRUE(recipe.contains("motion"));
  EXPECT_EQ(recipe["motion"]["type"], "arc");
  EXPECT_EQ(recipe["motion"]["container_turns"], true);
  // The arc moves as far as a straight stroke of its length: another answer, another key.
  const std::string arc_key = api::recipe_key(arc);
  EXPECT_NE(arc_key, api::recipe_key(api::parse_plan_request(stroke_plan(300.0 * kPi / 2.0))));
  json keeps = arc_plan("notch");
  keeps["format"]["motion"]["container_turns"] = false;
  EXPECT_NE(api::recipe_key(api::parse_plan_request(keeps)), arc_key);
}

TEST(PathPlanApi, RefusalsNameTheMember) {
  json uncertain = arc_plan("auto");
  uncertain["options"] = {{"uncertainty", {{"omega_error_pct", 10}}}};
  EXPECT_EQ(error_of(uncertain),
            "options.uncertainty.omega_error_pct | options.uncertainty.omega_error_pct is not "
            "available along an arc or a path yet: a plan along a path is verified at the "
            "nominal model (leave options.uncertainty out, or plan on a straight line)");
  json fill_range = arc_plan("notch");
  fill_range["options"] = {{"uncertainty", {{"fill_height_mm", {70, 90}}}}};
  EXPECT_EQ(error_of(fill_range).substr(0, 37), "options.uncertainty.fill_height_mm | ");
  json trajectory = arc_plan("auto");
  trajectory["format"]["motion"] = {{"type", "trajectory"},
                                    {"t_s", {0, 1, 2, 3}},
                                    {"x_mm", {0, 1, 2, 3}},
                                    {"y_mm", {0, 0, 0, 0}}};
  EXPECT_EQ(error_of(trajectory),
            "format.motion.type | format.motion.type = \"trajectory\" is not allowed in a plan: a "
            "plan moves the container along a \"line\", an \"arc\" or a \"path\" (a trajectory is "
            "simulated, POST /v1/simulate)");
  json both = arc_plan("auto");
  both["format"]["stroke_mm"] = 471;
  EXPECT_EQ(error_of(both),
            "format.stroke_mm | format.stroke_mm and format.motion both give the move: give one "
            "of them (stroke_mm is the short form of a motion of type \"line\")");
  json flat = arc_plan("auto");
  flat["format"]["motion"]["angle_deg"] = 0;
  EXPECT_EQ(error_of(flat),
            "format.motion.angle_deg | format.motion.angle_deg = 0 is not allowed: an arc turns, "
            "allowed -3600 to 3600 deg except 0 (signed, left positive)");
  json kinked = arc_plan("auto");
  kinked["format"]["motion"] = {{"type", "path"},
                                {"segments",
                                 {{{"line_mm", 200}},
                                  {{"arc", {{"radius_mm", 100}, {"angle_deg", 90}}}},
                                  {{"line_mm", 200}, {"heading_deg", 0}}}}};
  EXPECT_EQ(error_of(kinked).substr(0, 38), "format.motion.segments[2] | format.mot");
}

// A rectangular container is planned along arcs and paths on its own models
// (test_rectangular_spatial.cpp checks their figures).
TEST(PathPlanApi, ARectangularContainerIsPlannedAlongAnArcAndAPath) {
  json cup = arc_plan("auto");
  cup["format"]["container"] = {
      {"shape", "rectangular"}, {"length_mm", 120}, {"width_mm", 80}, {"height_mm", 150}};
  EXPECT_EQ(error_of(cup), "accepted");
  cup["format"]["motion"] = {{"type", "path"}, {"segments", {{{"line_mm", 200}}}}};
  EXPECT_EQ(error_of(cup), "accepted");
  cup["format"]["motion"] = {{"type", "line"}, {"length_mm", 200}};
  EXPECT_EQ(error_of(cup), "accepted");
}

TEST(PathPlanApi, TheCliPlansAlongAnArcAndRefusesConflictingFlags) {
  const std::vector<std::string> format{"plan", "--radius",   "48.5",  "--fill",
                                        "82",   "--fluid",    "water", "--time",
                                        "1.2",  "--strategy", "notch"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = format;
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_slosh(args);
  };
  const test::RunResult run =
      with({"--arc-radius", "300", "--arc-angle", "90", "--turns", "false", "--format", "json"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json plan = json::parse(run.out);
  EXPECT_EQ(plan["format"]["motion"], json({{"type", "arc"},
                                            {"radius_mm", 300.0},
                                            {"angle_deg", 90.0},
                                            {"start_heading_deg", 0.0},
                                            {"container_turns", false}}));
  EXPECT_EQ(plan["path"]["container_turns"], false);
  // --motion FILE: a path of lines and arcs.
  const test::TempDir dir;
  const json track{
      {"type", "path"},
      {"segments", {{{"line_mm", 200}}, {{"arc", {{"radius_mm", 500}, {"angle_deg", -90}}}}}}};
  test::write_file(dir / "track.json", track.dump());
  const test::RunResult from_file = with({"--motion", (dir / "track.json").string()});
  ASSERT_EQ(from_file.exit_code, 0) << from_file.err;
  EXPECT_TRUE(from_file.out.find("status      optimal") != std::string::npos ||
              from_file.out.find("status      acceptable") != std::string::npos)
      << from_file.out;
  // Conflicts: one line each on stderr, exit 2.
  const test::RunResult both =
      with({"--stroke", "800", "--arc-radius", "300", "--arc-angle", "90"});
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_EQ(both.err,
            "slosh plan: --stroke cannot be combined with --arc-radius/--arc-angle: the law moves "
            "along the arc, its length is the stroke\n");
  const test::RunResult turns = with({"--stroke", "800", "--turns", "false"});
  EXPECT_EQ(turns.exit_code, 2);
  EXPECT_EQ(turns.err,
            "slosh plan: --turns applies to an arc: give --arc-radius and --arc-angle\n");
  const test::RunResult half = with({"--arc-radius", "300"});
  EXPECT_EQ(half.exit_code, 2);
  EXPECT_NE(half.err.find("missing --arc-angle"), std::string::npos) << half.err;
  const test::RunResult zero = with({"--arc-radius", "300", "--arc-angle", "0"});
  EXPECT_EQ(zero.exit_code, 2);
  EXPECT_NE(zero.err.find("(flag --arc-angle)"), std::string::npos) << zero.err;
}

}  // namespace test_path_plan_api
}  // namespace slosh
