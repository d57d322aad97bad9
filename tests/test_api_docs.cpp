// docs/api.md says what the service does: the ranges of the format table are the ones the parser
// enforces (api::ranges, the same constants the 422 messages quote), a duplicate member is
// refused as the doc says, and the plan request's members are the ones the parser accepts.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh {
namespace test_api_docs {

std::string api_doc() {
  std::ifstream in(std::string(SLOSH_SOURCE_DIR) + "/docs/api.md");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The range cell of `field`'s row of the format table ("| `field` | unit | range | meaning |").
std::string range_cell(const std::string& doc, const std::string& field) {
  const std::string start = "| `" + field + "` | ";
  const auto at = doc.find(start);
  if (at == std::string::npos) return "(no row)";
  const auto unit_end = doc.find(" | ", at + start.size());
  const auto range_end = doc.find(" | ", unit_end + 3);
  return doc.substr(unit_end + 3, range_end - unit_end - 3);
}

// describe() without its unit: the form the table writes.
std::string range_text(const api::Range& r) {
  std::string text = r.describe();
  if (!r.unit.empty()) text.erase(text.size() - r.unit.size() - 1);
  return text;
}

TEST(ApiDocs, TheFormatTableQuotesTheRangesTheParserEnforces) {
  const std::string doc = api_doc();
  namespace ranges = api::ranges;
  EXPECT_EQ(range_cell(doc, "format.container.radius_mm"), range_text(ranges::kRadiusMm));
  EXPECT_EQ(range_cell(doc, "format.fill_height_mm"), range_text(ranges::kFillHeightMm));
  EXPECT_EQ(range_cell(doc, "format.stroke_mm"), range_text(ranges::kStrokeMm));
  EXPECT_EQ(range_cell(doc, "format.motion_time_s"), range_text(ranges::kMotionTimeS));
  EXPECT_EQ(range_cell(doc, "format.container.height_mm")
                .rfind(range_text(ranges::kContainerHeightMm) + ", above the fill height", 0),
            0u)
      << range_cell(doc, "format.container.height_mm");
  const std::string fluid = "(density " + range_text(ranges::kDensity) + " kg/m³, viscosity " +
                            range_text(ranges::kViscosity) + " Pa·s)";
  EXPECT_NE(range_cell(doc, "format.fluid").find(fluid), std::string::npos)
      << range_cell(doc, "format.fluid");
}

const char* kFormat = R"("format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82,
    "fluid": "water", "stroke_mm": 800, "motion_time_s": 1})";

std::string refusal(const std::string& text) {
  try {
    (void)api::parse_plan_request(api::parse_json_body(text));
  } catch (const api::ApiError& e) {
    return e.field() + ": " + e.what();
  }
  return "(accepted)";
}

TEST(ApiDocs, AMemberGivenTwiceIsRefusedNamingItsPath) {
  EXPECT_EQ(refusal(R"({"format": {"container": {"radius_mm": 48, "radius_mm": 49},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1}})"),
            "format.container.radius_mm: format.container.radius_mm is given twice: give each "
            "member once (a repeated member would silently replace the first)");
  EXPECT_EQ(refusal(std::string("{") + kFormat + R"(, "strategy": "notch", "strategy": "auto"})"),
            "strategy: strategy is given twice: give each member once (a repeated member would "
            "silently replace the first)");
  // Inside arrays the element is named; the same key in two objects is no repeat.
  try {
    (void)api::parse_json_body(R"({"requests": [{"a": 1}, {"a": 2, "b": [{"c": 1, "c": 2}]}]})");
    ADD_FAILURE() << "accepted";
  } catch (const api::ApiError& e) {
    EXPECT_EQ(e.field(), "requests[1].b[0].c");
  }
  EXPECT_EQ(refusal(std::string("{") + kFormat + R"(, "options": {"limits": {"a_max": 9}}})"),
            "(accepted)");
}

TEST(ApiDocs, ThePlanRequestMembersAreTheOnesTheParserTakes) {
  const std::string doc = api_doc();
  EXPECT_NE(doc.find("Request members: `format` (above), `strategy` (default `auto`; "
                     "[strategies.md](strategies.md)),\n`options` (every member optional, table "
                     "below), `sample_period_s` (adds `series` of the planned\nlaw). The view"),
            std::string::npos);
  EXPECT_EQ(refusal(std::string("{") + kFormat + R"(, "view": "compact"})"),
            "view: view is not a known field; allowed here: format, strategy, options, "
            "sample_period_s");
}

// A fluid name is echoed into plans, tables and logs: control characters are refused.
TEST(ApiDocs, AFluidNameWithControlCharactersIsRefused) {
  const std::string body = R"({"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82,
      "fluid": {"density_kg_m3": 1000, "viscosity_pa_s": 0.001, "name": "a\u0000b"},
      "stroke_mm": 800, "motion_time_s": 1}})";
  EXPECT_EQ(refusal(body),
            "format.fluid.name: format.fluid.name must not hold control characters (NUL, tab, line "
            "breaks, ...), got \"a\\u0000b\"");
}

}  // namespace test_api_docs
}  // namespace slosh
