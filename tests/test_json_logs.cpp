// `slosh serve --log-format json`: the real binary's every log line (stdout and stderr) is one JSON
// object with time and level; the access lines carry the request's fields and, for plans, the plan
// key, strategy, plan status and cached flag. Refusals of other formats name the source.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_json_logs {

using nlohmann::json;
using test::Server;

json plan_request() {
  return json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "strategy": "baseline"})");
}

std::vector<json> json_lines(const std::string& text) {
  std::vector<json> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    EXPECT_NO_THROW(lines.push_back(json::parse(line))) << line;
  }
  return lines;
}

// The access line of request `id`.
json access_line(const std::vector<json>& lines, const std::string& id) {
  for (const json& l : lines) {
    if (l.value("msg", "") == "request" && l.value("request_id", "") == id) return l;
  }
  return nullptr;
}

TEST(JsonLogs, EveryLineIsAnObjectWithTheRequestFields) {
  Server server({"--log-format", "json", "--workers", "1"});
  auto client = server.client();
  const httplib::Headers id1{{"X-Request-Id", "plan-1"}};
  const auto miss = client.Post("/v1/plans", id1, plan_request().dump(), "application/json");
  ASSERT_TRUE(miss && miss->status == 200);
  const std::string key = json::parse(miss->body).at("key");
  const std::string status = json::parse(miss->body).at("status");
  const httplib::Headers id2{{"X-Request-Id", "plan-2"}};
  ASSERT_TRUE(client.Post("/v1/plans", id2, plan_request().dump(), "application/json"));
  ASSERT_TRUE(client.Get("/v1/plans/" + key, {{"X-Request-Id", "get-3"}}));
  ASSERT_TRUE(
      client.Post("/v1/plans", {{"X-Request-Id", "bad-4"}}, "{\"format\": 1}", "application/json"));
  ASSERT_TRUE(client.Get("/no/such\"path", {{"X-Request-Id", "lost-5"}}));
  ASSERT_EQ(server.stop(), 0);

  const std::vector<json> lines = json_lines(server.log());
  ASSERT_GE(lines.size(), 8u);  // listening, 5 requests, signal, stopped
  const std::regex iso(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z)");
  for (const json& l : lines) {
    ASSERT_TRUE(l.is_object());
    EXPECT_TRUE(std::regex_match(l.at("time").get<std::string>(), iso)) << l;
    EXPECT_EQ(l.at("level"), "info") << l;
    EXPECT_TRUE(l.at("msg").is_string()) << l;
  }
  EXPECT_NE(lines.front().at("msg").get<std::string>().find("listening on"), std::string::npos);
  EXPECT_EQ(lines.back().at("msg"), "slosh stopped");

  const json first = access_line(lines, "plan-1");
  ASSERT_TRUE(first.is_object());
  EXPECT_EQ(first.at("method"), "POST");
  EXPECT_EQ(first.at("route"), "/v1/plans");
  EXPECT_EQ(first.at("path"), "/v1/plans");
  EXPECT_EQ(first.at("status"), 200);
  EXPECT_EQ(first.at("bytes"), miss->body.size());
  EXPECT_GT(first.at("ms").get<double>(), 0.0);
  EXPECT_EQ(first.at("plan_key"), key);
  EXPECT_EQ(first.at("strategy"), "baseline");
  EXPECT_EQ(first.at("plan_status"), status);
  EXPECT_EQ(first.at("cached"), false);
  const json second = access_line(lines, "plan-2");
  EXPECT_EQ(second.at("cached"), true);
  EXPECT_EQ(second.at("plan_key"), key);
  const json get = access_line(lines, "get-3");
  EXPECT_EQ(get.at("route"), "/v1/plans/{key}");
  EXPECT_EQ(get.at("path"), "/v1/plans/" + key);
  EXPECT_EQ(get.at("cached"), true);
  const json bad = access_line(lines, "bad-4");
  EXPECT_EQ(bad.at("status"), 422);
  EXPECT_FALSE(bad.contains("plan_key"));
  const json lost = access_line(lines, "lost-5");
  EXPECT_EQ(lost.at("status"), 404);
  EXPECT_EQ(lost.at("route"), "other");
  EXPECT_EQ(lost.at("path"), "/no/such\"path");
}

TEST(JsonLogs, TextStaysTheDefault) {
  Server server;
  auto client = server.client();
  ASSERT_TRUE(client.Get("/healthz", {{"X-Request-Id", "h-1"}}));
  ASSERT_EQ(server.stop(), 0);
  EXPECT_TRUE(std::regex_search(
      server.log(),
      std::regex(R"(request id=h-1 method=GET path=/healthz status=200 cache=- ms=[0-9.]+ )"
                 R"(bytes=\d+ route=/healthz)")))
      << server.log();
}

TEST(JsonLogs, OtherFormatsAreRefusedNamingTheSource) {
  const test::RunResult flag = test::run_slosh({"serve", "--port", "0", "--log-format", "yaml"});
  EXPECT_EQ(flag.exit_code, 2);
  EXPECT_EQ(flag.err, "slosh serve: --log-format = yaml is not a log format: allowed text, json\n");
  ::setenv("SLOSH_LOG_FORMAT", "logfmt", 1);
  const test::RunResult env = test::run_slosh({"serve", "--port", "0"});
  ::unsetenv("SLOSH_LOG_FORMAT");
  EXPECT_EQ(env.exit_code, 2);
  EXPECT_EQ(env.err,
            "slosh serve: SLOSH_LOG_FORMAT = logfmt is not a log format: allowed text, json\n");
}

TEST(ReplicaHeader, NamesTheReplicaOrTheHost) {
  Server named({"--replica-id", "line-7"});
  auto client = named.client();
  const auto r = client.Get("/healthz");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->get_header_value("X-Slosh-Replica"), "line-7");
  const auto lost = client.Get("/nowhere");
  ASSERT_TRUE(lost);
  EXPECT_EQ(lost->get_header_value("X-Slosh-Replica"), "line-7");
  Server unnamed;
  auto c2 = unnamed.client();
  char host[256] = {};
  ASSERT_EQ(::gethostname(host, sizeof host - 1), 0);
  EXPECT_EQ(c2.Get("/healthz")->get_header_value("X-Slosh-Replica"), host);
}

}  // namespace test_json_logs
}  // namespace slosh
