// Input that would be read wrongly or echoed harmfully: a JSON member given twice, control
// characters in recipe ids, formula-leading cells in CSV tables, request framings the HTTP layer
// must refuse before reading a body; and the plan warning kinds against the OpenAPI document.
// The HTTP cases run against the real `slosh serve` on loopback.

#include <httplib.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "http/gzip.hpp"
#include "jobs/plan_table.hpp"
#include "jobs/recipe_table.hpp"
#include "slosh/api/config_file.hpp"
#include "slosh/api/min_time_table.hpp"
#include "slosh/api/openapi.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/plan_warnings.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/process.hpp"
#include "support/raw_client.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_input_refusals {

using nlohmann::json;
using service::RecipeRow;
using service::TableFormat;

constexpr const char* kControl =
    " must not hold control characters (NUL, tab, line breaks, ...), got ";

std::string plan_text(const std::string& strategy_members) {
  return R"({"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82,
      "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}, )" +
         strategy_members + "}";
}

// ---- recipe ids ----

TEST(InputRefusals, ARecipeIdWithAControlCharacterIsTheRowsError) {
  const std::string header =
      "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n";
  const std::vector<RecipeRow> csv = service::read_recipe_table(
      header + "\"a\tb\",48.5,82,water,800,1,notch\nok,48.5,82,water,800,1,notch\n",
      TableFormat::kCsv);
  ASSERT_EQ(csv.size(), 2u);
  ASSERT_TRUE(csv[0].error.has_value());
  EXPECT_EQ(csv[0].error->field(), "recipe_id");
  EXPECT_EQ(std::string(csv[0].error->what()), std::string("recipe_id") + kControl + "\"a\\tb\"");
  EXPECT_EQ(csv[0].recipe_id, "");  // never written into the plan table
  EXPECT_FALSE(csv[1].error.has_value());
  EXPECT_EQ(csv[1].recipe_id, "ok");

  // JSON lines: a line break and a NUL, each its row's error; a printable id is kept.
  const std::string lines = R"({"recipe_id": "line1\nline2", "strategy": "notch"})"
                            "\n"
                            R"({"recipe_id": "\u0000nul"})"
                            "\n"
                            R"({"recipe_id": "=fine"})"
                            "\n";
  const std::vector<RecipeRow> jsonl = service::read_recipe_table(lines, TableFormat::kJsonLines);
  ASSERT_EQ(jsonl.size(), 3u);
  ASSERT_TRUE(jsonl[0].error.has_value());
  EXPECT_EQ(std::string(jsonl[0].error->what()),
            std::string("recipe_id") + kControl + "\"line1\\nline2\"");
  ASSERT_TRUE(jsonl[1].error.has_value());
  EXPECT_EQ(std::string(jsonl[1].error->what()),
            std::string("recipe_id") + kControl + "\"\\u0000nul\"");
  EXPECT_FALSE(jsonl[2].error.has_value());
  EXPECT_EQ(jsonl[2].recipe_id, "=fine");
}

// ---- CSV cells ----

// The plan-table row of a recipe with id `recipe_id` that failed (no solve needed).
api::PlanTableRow failed_row(const std::string& recipe_id) {
  RecipeRow recipe;
  recipe.row = 1;
  recipe.recipe_id = recipe_id;
  service::BatchResult result;
  result.error = api::ApiError(api::ErrorCode::kInvalidValue, "strategy", "strategy is wrong");
  return service::plan_row(recipe, result, std::nullopt);
}

// The recipe_id cell (the second) of a CSV plan table's only row.
std::string recipe_id_cell(const std::string& recipe_id) {
  std::ostringstream out;
  service::PlanTableWriter writer(out, TableFormat::kCsv);
  writer.write(failed_row(recipe_id));
  writer.finish();
  const std::string text = out.str();
  const std::string row = text.substr(text.find('\n') + 1);
  const std::size_t start = row.find(',') + 1;  // after the row number
  const std::size_t end = row.find(",\"error\"", start);
  return row.substr(start, end - start);
}

TEST(InputRefusals, FormulaLeadingCellsAreNeutralisedInCsvTables) {
  // OWASP's CSV injection list: '=', '+', '-', '@', tab and carriage return lead a formula.
  EXPECT_EQ(recipe_id_cell(R"(=HYPERLINK("http://evil","x"))"),
            R"x("'=HYPERLINK(""http://evil"",""x"")")x");
  EXPECT_EQ(recipe_id_cell("+1"), "\"'+1\"");
  EXPECT_EQ(recipe_id_cell("-2"), "\"'-2\"");
  EXPECT_EQ(recipe_id_cell("@SUM(A1)"), "\"'@SUM(A1)\"");
  // Text that does not lead with one is written as before (quoted, RFC 4180).
  EXPECT_EQ(recipe_id_cell("a=b"), "\"a=b\"");
  EXPECT_EQ(recipe_id_cell("p-1"), "\"p-1\"");
  // JSON tables keep the text as given: only a spreadsheet runs formulas.
  std::ostringstream jsonl;
  service::PlanTableWriter writer(jsonl, TableFormat::kJsonLines);
  writer.write(failed_row("=1+1"));
  EXPECT_EQ(json::parse(jsonl.str())["recipe_id"], "=1+1");

  // Min-time tables: the same rule (cells quoted only when needed otherwise).
  const api::ApiError error(api::ErrorCode::kInvalidValue, "", "no search");
  EXPECT_EQ(api::min_time_csv_line(api::min_time_error_row(3, "=1+1", false, error)).substr(0, 13),
            "3,\"'=1+1\",err");
  EXPECT_EQ(api::min_time_csv_line(api::min_time_error_row(3, "a-1", false, error)).substr(0, 10),
            "3,a-1,erro");
}

// ---- duplicate members and null ----

TEST(InputRefusals, AConfigFileMemberGivenTwiceIsRefused) {
  std::string refusal = "accepted";
  try {
    (void)api::parse_config_file("s.json", R"({"workers": 1, "workers": 2})");
  } catch (const std::runtime_error& e) {
    refusal = e.what();
  }
  EXPECT_EQ(refusal,
            "config file 's.json': workers is given twice: give each member once (a repeated "
            "member would silently replace the first)");
}

TEST(InputRefusals, DuplicateMembersAreRefusedAlsoWhenAModelIsNamedAndNullIsAbsent) {
  test::Server server({"--workers", "1"});
  httplib::Client c = server.client();
  // A stored-model name is resolved before the request is read: the body with its repeated
  // member must still reach the parser as sent.
  const auto twice = c.Post(
      "/v1/plans", plan_text(R"("strategy": "notch", "options": {"model": "a", "model": "b"})"),
      "application/json");
  ASSERT_TRUE(twice);
  EXPECT_EQ(twice->status, 422);
  EXPECT_EQ(twice->body,
            R"({"error":{"code":"invalid_value","field":"options.model","message":"options.model )"
            R"(is given twice: give each member once (a repeated member would silently replace )"
            R"x(the first)"}})x");
  const auto batch =
      c.Post("/v1/plans/batch",
             R"({"requests": [)" + plan_text(R"("strategy": "notch", "options": {"model": "a"})") +
                 R"(], "view": "full", "view": "compact"})",
             "application/json");
  ASSERT_TRUE(batch);
  EXPECT_EQ(batch->status, 422);
  EXPECT_NE(batch->body.find(R"("field":"view","message":"view is given twice)"), std::string::npos)
      << batch->body;
  // null for an optional member is the member left out: the same plan, the same key.
  const auto with_null =
      c.Post("/v1/plans", plan_text(R"("strategy": "notch", "options": null)"), "application/json");
  const auto without = c.Post("/v1/plans", plan_text(R"("strategy": "notch")"), "application/json");
  ASSERT_TRUE(with_null && without);
  ASSERT_EQ(with_null->status, 200) << with_null->body.substr(0, 300);
  EXPECT_EQ(json::parse(with_null->body)["key"], json::parse(without->body)["key"]);
  // A member the request does not know is refused whatever its value, null included.
  const auto view =
      c.Post("/v1/plans", plan_text(R"("strategy": "notch", "view": null)"), "application/json");
  ASSERT_TRUE(view);
  EXPECT_EQ(view->status, 422);
  EXPECT_EQ(json::parse(view->body)["error"]["field"], "view");
}

// ---- HTTP framing ----

// The answer to `request` sent on a raw connection ("Connection: close" in the request lets the
// server close it at once).
std::string raw_answer(int port, const std::string& request) {
  test::Raw raw(port);
  EXPECT_TRUE(raw.connected());
  raw.send(request);
  return raw.read_all();
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(InputRefusals, ADeclaredBodyTheServiceRefusesIsRefusedBeforeItIsRead) {
  // A read timeout longer than the raw client waits (10 s): an answer that waited for the body
  // would not arrive at all.
  test::TempDir dir;
  test::write_file(dir / "slosh.json", R"({"read_timeout_s": 30})");
  test::Server server(
      {"--workers", "1", "--replica-id", "r-7", "--config", (dir / "slosh.json").string()});
  const std::string head =
      "POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n";
  const std::string large =
      raw_answer(server.port(), head + "Connection: close\r\nContent-Length: 2000000\r\n\r\n{");
  EXPECT_EQ(large.rfind("HTTP/1.1 413", 0), 0u) << large.substr(0, 300);
  EXPECT_NE(large.find(R"({"error":{"code":"payload_too_large","field":null,"message":"the body )"
                       R"(is larger than the limit of 1048576 bytes (max_body_bytes); )"),
            std::string::npos)
      << large;
  EXPECT_EQ(count_of(large, "Connection: close\r\n"), 1u) << large;
  EXPECT_NE(large.find("X-Slosh-Replica: r-7\r\n"), std::string::npos) << large;

  const std::string negative =
      raw_answer(server.port(), head + "Connection: close\r\nContent-Length: -1\r\n\r\n");
  EXPECT_EQ(negative.rfind("HTTP/1.1 400", 0), 0u) << negative.substr(0, 300);
  EXPECT_NE(negative.find(R"("message":"Content-Length = \"-1\" is not a length: a whole number )"
                          R"(of bytes, at most 1048576")"),
            std::string::npos)
      << negative;
  EXPECT_EQ(count_of(negative, "Connection: close\r\n"), 1u) << negative;

  const std::string both = raw_answer(
      server.port(),
      head +
          "Connection: close\r\nContent-Length: 5\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n");
  EXPECT_EQ(both.rfind("HTTP/1.1 400", 0), 0u) << both.substr(0, 300);
  EXPECT_NE(both.find(R"("message":"the request declares both Content-Length and )"
                      R"x(Transfer-Encoding: send one of them (RFC 9112 6.3)")x"),
            std::string::npos)
      << both;
}

TEST(InputRefusals, ABodyThatStopsArrivingIsA408) {
  test::TempDir dir;
  test::write_file(dir / "slosh.json", R"({"read_timeout_s": 1})");
  test::Server server({"--workers", "1", "--config", (dir / "slosh.json").string()});
  const std::string answer =
      raw_answer(server.port(),
                 "POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                 "Connection: close\r\nContent-Length: 10\r\n\r\n{\"");
  EXPECT_EQ(answer.rfind("HTTP/1.1 408", 0), 0u) << answer.substr(0, 300);
  EXPECT_NE(answer.find(R"({"error":{"code":"request_timeout","field":null,"message":"the body )"
                        R"(stopped arriving: nothing came for read_timeout_s = 1 s"}})"),
            std::string::npos)
      << answer;
}

TEST(InputRefusals, AnUnreadableQualityValueIsNoConsentToGzip) {
  EXPECT_FALSE(service::accepts_gzip("gzip;q=abc"));
  EXPECT_FALSE(service::accepts_gzip("gzip;q=1.5"));
  EXPECT_FALSE(service::accepts_gzip("gzip;q=0.5000"));
  EXPECT_FALSE(service::accepts_gzip("*;q=x"));
  EXPECT_TRUE(service::accepts_gzip("gzip;q=0.5"));
  EXPECT_TRUE(service::accepts_gzip("gzip;q=1.000"));
  EXPECT_TRUE(service::accepts_gzip("gzip;q=1"));
}

TEST(InputRefusals, AnswersOfTheHttpLibraryNameTheReplica) {
  test::Server server({"--workers", "1", "--replica-id", "r-9"});
  for (const std::string& request :
       {std::string("GARBAGE\r\n\r\n"),
        std::string("GET /healthz HTTP/2.0\r\nHost: x\r\nConnection: close\r\n\r\n")}) {
    const std::string answer = raw_answer(server.port(), request);
    EXPECT_EQ(answer.rfind("HTTP/1.1 4", 0) == 0 || answer.rfind("HTTP/1.1 5", 0) == 0, true)
        << answer.substr(0, 200);
    EXPECT_NE(answer.find("X-Slosh-Replica: r-9\r\n"), std::string::npos) << answer;
  }
}

TEST(InputRefusals, AnAddressThatIsNoneIsSaidSoWhenBindingFails) {
  test::TempDir dir;
  test::write_file(dir / "stdin", "");
  test::Child child(test::spawn({"serve", "--host", "999.1.1.1", "--port", "0", "--cache", ""},
                                dir / "stdin", dir / "stdout", dir / "stderr"));
  const std::optional<int> code = child.wait_for(std::chrono::seconds(30));
  ASSERT_TRUE(code.has_value());
  EXPECT_NE(*code, 0);
  const std::string log = test::read_file(dir / "stdout") + test::read_file(dir / "stderr");
  EXPECT_NE(log.find("cannot bind 999.1.1.1:0: the host 999.1.1.1 is not an address (an IPv4 or "
                     "IPv6 address, or a name that resolves): "),
            std::string::npos)
      << log;
  EXPECT_EQ(log.find("using the port"), std::string::npos) << log;
}

// ---- plan warnings ----

TEST(InputRefusals, EveryPlanWarningKindIsInTheOpenApiDocument) {
  const json schemas = api::openapi_document("test")["components"]["schemas"];
  const std::string full = schemas["PlanResponse"]["properties"]["warnings"]["description"];
  const std::string compact = schemas["CompactPlan"]["properties"]["warnings"]["description"];
  ASSERT_FALSE(api::plan_warning_kinds().empty());
  for (const api::PlanWarningKind& kind : api::plan_warning_kinds()) {
    EXPECT_NE(full.find("\"" + std::string(kind.prefix) + "...\" (" + std::string(kind.code) +
                        "): " + std::string(kind.meaning)),
              std::string::npos)
        << kind.code << " in " << full;
    EXPECT_NE(compact.find(std::string(kind.code)), std::string::npos) << kind.code;
  }
  EXPECT_NE(full.find("time_limited_candidates"), std::string::npos);
}

TEST(InputRefusals, EveryWarningTheModelsAndThePlannerWriteIsAKindOfTheTable) {
  // The kind is set where a warning is made; its sentence begins as the table (and so the OpenAPI
  // description) says.
  // Every validity limit at once: a 10 mm radius filled 2 mm, a 1 mm free board, 50 m/s^2, a
  // 20 mm wave on a 2 mm fill.
  Format format;
  format.container.radius = 0.010;
  format.container.height = 0.003;
  format.fill_height = 0.002;
  const std::vector<Warning> validity = validity_warnings(format, 50.0, 0.02, 0.01);
  EXPECT_EQ(
      warning_codes(validity),
      (std::vector<std::string>{"linear_model_unreliable", "models_out_of_range", "surface_tension",
                                "shallow_fill", "wave_exceeds_fill", "spill"}));
  for (const Warning& w : validity) {
    EXPECT_TRUE(w.text.starts_with(warning_kind_info(w.kind).prefix)) << w.text;
  }
  // The planner's own: a worse law than the baseline, and the budget of auto's candidates.
  EXPECT_EQ(warning_kind_info(WarningKind::kWorseThanBaseline).prefix,
            std::string(name_of(CandidateLoss::kWorseThanBaseline)) + ": ");
  EXPECT_EQ(warning_kind_info(WarningKind::kTimeLimitedCandidates).prefix,
            std::string(api::kTimeLimitedCandidates) + ": ");
  // Every code once.
  std::set<std::string_view> codes;
  for (const api::PlanWarningKind& kind : api::plan_warning_kinds()) {
    EXPECT_TRUE(codes.insert(kind.code).second) << kind.code;
  }
}

}  // namespace test_input_refusals
}  // namespace slosh
