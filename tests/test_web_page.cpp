// The web page's server side against a real `slosh serve`: the embedded assets are every file of
// web/ (with ETag, Cache-Control and 304), and GET /v1/plans/{key}/cam.csv is `slosh export`'s
// file, with the exact error texts of its parameters. The page itself is tested in a real
// browser (tests/browser/test_page.py, ctest browser.page).

#include <httplib.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_web_page {

using nlohmann::json;

const char* const kThesis = R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
    "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
    "strategy": "multi_notch"})";

/// The media type the service sends for a file of web/, by its extension.
std::string content_type_of(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  return "";
}

TEST(WebPage, TheAssetsAreTheFilesOfWebWithETagsAndRevalidation) {
  test::Server server({"--workers", "1"});
  httplib::Client client = server.client();
  // Every file of web/ (the page's modules import each other by these names), index.html at /.
  std::vector<std::pair<std::string, std::filesystem::path>> assets;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(SLOSH_SOURCE_DIR) / "web")) {
    const std::string name = entry.path().filename().string();
    assets.emplace_back(name == "index.html" ? "/" : "/assets/" + name, entry.path());
  }
  std::sort(assets.begin(), assets.end());
  ASSERT_GE(assets.size(), 4u);
  for (const char* file : {"index.html", "style.css", "app.js", "plots.js", "form.js", "api.js"}) {
    EXPECT_TRUE(std::any_of(assets.begin(), assets.end(), [&](const auto& a) {
      return a.second.filename() == file;
    })) << file;
  }
  for (const auto& [path, file] : assets) {
    const auto res = client.Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 200) << path;
    EXPECT_EQ(res->body, test::read_file(file)) << path;
    EXPECT_EQ(res->get_header_value("Content-Type"), content_type_of(file)) << path;
    EXPECT_EQ(res->get_header_value("Cache-Control"), "no-cache") << path;
    const std::string tag = res->get_header_value("ETag");
    ASSERT_EQ(tag.size(), 66u) << path;  // the quoted SHA-256
    const auto again = client.Get(path, {{"If-None-Match", tag}});
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 304) << path;
    EXPECT_TRUE(again->body.empty());
  }
  const auto chart = client.Get("/assets/chart.min.js");
  ASSERT_TRUE(chart);
  EXPECT_EQ(chart->status, 200);
  EXPECT_NE(chart->body.find("Chart.js v3.9.1"), std::string::npos);
  const auto missing = client.Get("/assets/nope.js");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  EXPECT_EQ(json::parse(missing->body),
            json::parse(R"({"error": {"code": "not_found", "field": "name",
                                      "message": "no asset 'nope.js' of the web page"}})"));
}

TEST(WebPage, TheCamTableDownloadIsTheFileOfSloshExport) {
  test::Server server({"--workers", "1"});
  httplib::Client client = server.client();
  const auto planned = client.Post("/v1/plans", kThesis, "application/json");
  ASSERT_TRUE(planned);
  ASSERT_EQ(planned->status, 200) << planned->body;
  const std::string key = json::parse(planned->body)["key"];
  const test::TempDir dir;
  test::write_file(dir / "request.json", kThesis);
  for (const char* period : {"1", "2.5"}) {
    const auto res = client.Get("/v1/plans/" + key + "/cam.csv?period_ms=" + period);
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "text/csv; charset=utf-8");
    EXPECT_EQ(res->get_header_value("Content-Disposition"),
              "attachment; filename=\"cam-" + key + "-" + period + "ms.csv\"");
    const test::RunResult exported =
        test::run_slosh({"export", "--request", (dir / "request.json").string(), "--out",
                         (dir / "cam.csv").string(), "--period-ms", period, "--cache", ""});
    ASSERT_EQ(exported.exit_code, 0) << exported.err;
    EXPECT_EQ(res->body, test::read_file(dir / "cam.csv")) << period;
  }
  const auto by_default = client.Get("/v1/plans/" + key + "/cam.csv");
  ASSERT_TRUE(by_default);
  EXPECT_EQ(by_default->body, client.Get("/v1/plans/" + key + "/cam.csv?period_ms=1")->body);
}

TEST(WebPage, CamTableParametersAreRefusedByName) {
  test::Server server({"--workers", "1"});
  httplib::Client client = server.client();
  const std::string key =
      json::parse(client.Post("/v1/plans", kThesis, "application/json")->body)["key"];
  auto error_of = [&](const std::string& query) {
    const auto res = client.Get("/v1/plans/" + key + "/cam.csv" + query);
    EXPECT_TRUE(res);
    EXPECT_EQ(res->status, 422) << query;
    return json::parse(res->body)["error"];
  };
  EXPECT_EQ(error_of("?period_ms=0"), json::parse(R"({"code": "invalid_value", "field": "period_ms",
                "message": "period_ms = 0 is out of range [0.01, 1000] ms"})"));
  EXPECT_EQ(error_of("?period_ms=abc"),
            json::parse(R"({"code": "invalid_value", "field": "period_ms",
                "message": "period_ms = abc is not a decimal number [ms]"})"));
  EXPECT_EQ(error_of("?allow_infeasible=yes"),
            json::parse(R"({"code": "invalid_value", "field": "allow_infeasible",
                "message": "allow_infeasible = yes is not allowed: one of \"true\", \"false\""})"));
  const auto unknown = client.Get("/v1/plans/0123456789abcdef/cam.csv");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
  EXPECT_EQ(json::parse(unknown->body)["error"]["field"], "key");
}

TEST(WebPage, ACamTableOfMoreThanTheServedRowsIsRefusedNotBuilt) {
  // 60 s at 0.01 ms would be 6 000 001 rows (355 MB built in memory per request).
  test::Server server({"--workers", "1"});
  httplib::Client client = server.client();
  json request = json::parse(kThesis);
  request["strategy"] = "baseline";
  request["format"]["motion_time_s"] = 60;
  const auto planned = client.Post("/v1/plans", request.dump(), "application/json");
  ASSERT_TRUE(planned);
  const std::string key = json::parse(planned->body)["key"];
  const auto refused = client.Get("/v1/plans/" + key + "/cam.csv?period_ms=0.01");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 422);
  // 60 s / 199 998 intervals = 0.30000300003 ms, rounded up to the microsecond.
  EXPECT_EQ(json::parse(refused->body)["error"],
            json::parse(R"j({"code": "invalid_value", "field": "period_ms",
                "message": "period_ms = 0.01 gives more than 200000 rows over the 60 s motion: allowed >= 0.301 ms here (slosh export writes longer tables)"
})j"));
  const auto served = client.Get("/v1/plans/" + key + "/cam.csv?period_ms=0.301");
  ASSERT_TRUE(served);
  EXPECT_EQ(served->status, 200);
  std::size_t rows = 0;
  for (const char c : served->body) rows += c == '\n' ? 1 : 0;
  EXPECT_LE(rows, 200000u + 1u);  // with the header
  EXPECT_GT(rows, 199000u);
  EXPECT_EQ(served->get_header_value("X-Content-Type-Options"), "");  // only the page's assets
  const auto page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->get_header_value("X-Content-Type-Options"), "nosniff");
  EXPECT_EQ(page->get_header_value("Content-Security-Policy"), "frame-ancestors 'none'");
}

TEST(WebPage, AnInfeasiblePlanIsExportedOnlyWhenAskedFor) {
  test::Server server({"--workers", "1"});
  httplib::Client client = server.client();
  json request = json::parse(kThesis);
  request["strategy"] = "fir_chain";
  request["options"] = {{"limits", {{"a_max", 7}}}};  // the chain needs more: infeasible
  const auto planned = client.Post("/v1/plans", request.dump(), "application/json");
  ASSERT_TRUE(planned);
  const json plan = json::parse(planned->body);
  ASSERT_EQ(plan["status"], "infeasible") << planned->body;
  const std::string path = "/v1/plans/" + plan["key"].get<std::string>() + "/cam.csv";
  const auto refused = client.Get(path);
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 422);
  const json error = json::parse(refused->body)["error"];
  EXPECT_EQ(error["field"], "allow_infeasible");
  EXPECT_EQ(error["message"], "the plan is infeasible, its law misses the requested limits: " +
                                  plan["message"].get<std::string>() +
                                  ". Not exported; add allow_infeasible=true to export the best "
                                  "reachable law anyway");
  const auto forced = client.Get(path + "?allow_infeasible=true");
  ASSERT_TRUE(forced);
  EXPECT_EQ(forced->status, 200);
  EXPECT_EQ(forced->body.rfind("t_s,position_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3\n", 0),
            0u);
}

}  // namespace test_web_page
}  // namespace slosh
