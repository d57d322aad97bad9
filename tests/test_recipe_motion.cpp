// The motion columns of CSV recipe tables (SPEC §14): the cells of a row become format.motion of
// its request (an arc, a path from its JSON), a line row stays the stroke_mm request it always
// was, misplaced motion cells are refused naming their column with the exact sentence, and a
// request's motion member maps back to its column.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/plan.hpp"
#include "slosh/api/recipe_motion.hpp"
#include "slosh/api/recipe_row.hpp"

namespace slosh::api {
namespace test_recipe_motion {

using nlohmann::json;

const std::vector<std::string> kHeader{"recipe_id",       "radius_mm",     "fill_height_mm",
                                       "fluid",           "stroke_mm",     "motion_time_s",
                                       "motion_type",     "arc_radius_mm", "arc_angle_deg",
                                       "container_turns", "path_json",     "strategy"};

json request_of(const std::vector<std::string>& cells) {
  return RecipeHeader(kHeader).request(cells).body();
}

CellError error_of(const std::vector<std::string>& cells) {
  try {
    (void)request_of(cells);
  } catch (const CellError& e) {
    return e;
  }
  ADD_FAILURE() << "not refused";
  return {};
}

TEST(RecipeMotion, AnArcRowGivesTheArcMotionWithoutAStroke) {
  const json r = request_of(
      {"t1", "48.5", "82", "water", "", "1.2", "arc", "300", "-90", "yes", "", "time_domain"});
  EXPECT_EQ(r["format"]["motion"], json::parse(R"({"type": "arc", "radius_mm": 300,
      "angle_deg": -90, "container_turns": true})"));
  EXPECT_FALSE(r["format"].contains("stroke_mm"));
  EXPECT_EQ(r["strategy"], "time_domain");
}

TEST(RecipeMotion, APathRowReadsItsSegmentsFromJson) {
  const json r =
      request_of({"p", "48.5", "82", "water", "", "1.2", "path", "", "", "false",
                  R"([{"line_mm": 200}, {"arc": {"radius_mm": 100, "angle_deg": 90}}])", "notch"});
  EXPECT_EQ(r["format"]["motion"], json::parse(R"({"type": "path", "container_turns": false,
      "segments": [{"line_mm": 200}, {"arc": {"radius_mm": 100, "angle_deg": 90}}]})"));
}

TEST(RecipeMotion, ALineRowIsTheStrokeRequestAsWithoutTheColumns) {
  const json with_type =
      request_of({"l", "48.5", "82", "water", "800", "1", "line", "", "", "", "", "notch"});
  const json without =
      request_of({"l", "48.5", "82", "water", "800", "1", "", "", "", "", "", "notch"});
  EXPECT_EQ(with_type, without);
  EXPECT_FALSE(with_type["format"].contains("motion"));
  EXPECT_EQ(with_type["format"]["stroke_mm"], 800);
}

TEST(RecipeMotion, MisplacedCellsNameTheirColumn) {
  struct Case {
    std::vector<std::string> cells;
    std::string column, message;
  };
  const std::vector<Case> cases{
      {{"a", "48.5", "82", "water", "", "1", "path", "300", "", "", "[]", "notch"},
       "arc_radius_mm",
       "arc_radius_mm is given but motion_type is \"path\": leave it empty"},
      {{"a", "48.5", "82", "water", "", "1", "arc", "300", "90", "", "[]", "notch"},
       "path_json",
       "path_json is given but motion_type is \"arc\": leave it empty"},
      {{"a", "48.5", "82", "water", "800", "1", "line", "", "", "true", "", "notch"},
       "container_turns",
       "container_turns is given but motion_type is \"line\": leave it empty"},
      {{"a", "48.5", "82", "water", "", "1", "", "300", "90", "", "", "notch"},
       "arc_radius_mm",
       "arc_radius_mm is given but motion_type is not: give motion_type arc or path with it"},
      {{"a", "48.5", "82", "water", "800", "1", "arc", "300", "90", "", "", "notch"},
       "stroke_mm",
       "stroke_mm is given but motion_type is arc: the arc's length is the stroke; leave it "
       "empty"},
      {{"a", "48.5", "82", "water", "", "1", "ARC", "300", "90", "", "", "notch"},
       "motion_type",
       "motion_type = \"ARC\" is not allowed: one of \"line\", \"arc\", \"path\""},
      {{"a", "48.5", "82", "water", "", "1", "trajectory", "", "", "", "", "notch"},
       "motion_type",
       "motion_type = \"trajectory\" is not allowed: one of \"line\", \"arc\", \"path\""},
      {{"a", "48.5", "82", "water", "", "1", "path", "", "", "", "[{\"line_mm\": 2", "notch"},
       "path_json",
       "path_json = \"[{\\\"line_mm\\\": 2\" is not JSON"},
  };
  for (const Case& c : cases) {
    const CellError e = error_of(c.cells);
    EXPECT_EQ(e.column, c.column) << c.message;
    EXPECT_EQ(e.message, c.message);
  }
}

TEST(RecipeMotion, StrokeColumnIsOptionalWithAMotionTypeAndMembersMapToColumns) {
  const std::vector<std::string> arcs{"recipe_id",     "radius_mm",     "fill_height_mm",
                                      "fluid",         "motion_time_s", "motion_type",
                                      "arc_radius_mm", "arc_angle_deg", "strategy"};
  EXPECT_NO_THROW(RecipeHeader{arcs});
  std::vector<std::string> plain = arcs;
  plain.erase(plain.begin() + 5, plain.begin() + 8);
  try {
    RecipeHeader{plain};
    ADD_FAILURE() << "a table without stroke_mm and motion_type was accepted";
  } catch (const RecipeTableError& e) {
    EXPECT_NE(std::string(e.what()).find("missing column \"stroke_mm\""), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(column_of_field("format.motion.radius_mm"), "arc_radius_mm");
  EXPECT_EQ(column_of_field("format.motion.angle_deg"), "arc_angle_deg");
  EXPECT_EQ(column_of_field("format.motion.segments[1].arc.radius_mm"), "path_json");
  EXPECT_EQ(in_column_terms("format.motion.radius_mm",
                            "format.motion.radius_mm = -5 is out of range: allowed > 0"),
            "arc_radius_mm = -5 is out of range: allowed > 0");
}

TEST(RecipeMotion, PlanRowsCarryTheMotion) {
  const json arc_row =
      request_of({"t1", "48.5", "82", "water", "", "1.2", "arc", "300", "90", "", "", "baseline"});
  const json arc = plan_row_figures(run_plan(parse_plan_request(arc_row)));
  EXPECT_EQ(arc["motion_type"], "arc");
  EXPECT_EQ(arc["arc_radius_mm"], 300);
  EXPECT_EQ(arc["arc_angle_deg"], 90);
  EXPECT_EQ(arc["container_turns"], true);  // an arc's default
  EXPECT_NEAR(arc["path_length_mm"].get<double>(), 150.0 * 3.141592653589793, 1e-9);
  const json line_row =
      request_of({"l", "48.5", "82", "water", "800", "1.2", "", "", "", "", "", "baseline"});
  const json line = plan_row_figures(run_plan(parse_plan_request(line_row)));
  EXPECT_EQ(line["motion_type"], "line");
  EXPECT_EQ(line["arc_radius_mm"], nullptr);
  EXPECT_EQ(line["container_turns"], nullptr);
  EXPECT_EQ(line["path_length_mm"], 800);
  EXPECT_EQ(line["path_json"], nullptr);  // only a path echoes its segments
  EXPECT_EQ(arc["path_json"], nullptr);
  EXPECT_EQ(motion_row_figures(json::object())["motion_type"], nullptr);
}

// A plan's warnings are in its row, as the compact view's codes: a table row that reads
// `optimal` says that its law spills or sloshes more than the uniform law.
TEST(RecipeMotion, PlanRowsCarryTheWarningsCodes) {
  const json plan{{"status", "optimal"},
                  {"warnings",
                   {"predicted sloshing height during the motion 34.7 mm exceeds the free board "
                    "20 mm: liquid will spill",
                    "worse_than_baseline: eta_rest 28.9 mm against the uniform law's 15.7 mm"}},
                  {"warning_codes", {"spill", "worse_than_baseline"}}};
  EXPECT_EQ(plan_row_figures(plan)["warnings"], "spill; worse_than_baseline");
  EXPECT_EQ(plan_row_figures(json{{"status", "optimal"}, {"warnings", json::array()}})["warnings"],
            nullptr);
  const json line_row =
      request_of({"l", "48.5", "82", "water", "800", "1.2", "", "", "", "", "", "baseline"});
  EXPECT_EQ(plan_row_figures(run_plan(parse_plan_request(line_row)))["warnings"], nullptr);
}

}  // namespace test_recipe_motion
}  // namespace slosh::api
