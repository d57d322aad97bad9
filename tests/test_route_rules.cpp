// The rules every route of the real `slosh serve` follows, whatever its handler: a query parameter
// the route does not take is refused with a 422 naming it and the accepted ones (as unknown JSON
// members are), a '/' sent as %2F never splits a path segment, and every method's requests are
// counted, timed and logged under their route.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "slosh/api/openapi.hpp"
#include "slosh/api/routes.hpp"
#include "support/raw_client.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_route_rules {

using nlohmann::json;
using test::Server;

json plan_body() {
  return json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "strategy": "baseline"})");
}

// The cached plan's key (planned once on `server`).
std::string planned_key(const Server& server) {
  auto client = server.client();
  const auto r = client.Post("/v1/plans", plan_body().dump(), "application/json");
  EXPECT_TRUE(r && r->status == 200);
  return json::parse(r->body).at("key");
}

json error_of(const httplib::Result& r) {
  EXPECT_TRUE(r);
  return r ? json::parse(r->body).at("error") : json();
}

// The query parameters of each route, written out here (not read from the route table): a route
// added without its entry fails EveryRouteRefusesAParameterItDoesNotTake.
const std::map<std::string, std::string>& accepted_query() {
  static const std::map<std::string, std::string> m{
      {"POST /v1/plans", "view"},
      {"POST /v1/plans/batch", "view"},
      {"GET /v1/plans/{key}", "view"},
      {"POST /v1/min-time", ""},
      {"POST /v1/simulate", ""},
      {"POST /v1/calibrations", ""},
      {"GET /v1/calibrations/{name}", ""},
      {"GET /v1/fluids", ""},
      {"GET /v1/openapi.json", ""},
      {"GET /healthz", ""},
      {"GET /readyz", ""},
      {"GET /metrics", ""},
      {"GET /v1/plans/{key}/cam.csv",
       "period_ms, master_period, master_start, master_end, master_step, allow_infeasible"},
      {"GET /v1/plans/{key}/cam.st",
       "period_ms, master_period, master_start, master_end, master_step, allow_infeasible, "
       "st_name"},
      {"POST /v1/batches", ""},
      {"GET /v1/batches/{id}", "offset, limit"},
      {"DELETE /v1/batches/{id}", ""},
      {"GET /v1/batches/{id}/results.csv", "partial"},
      {"GET /v1/batches/{id}/results.jsonl", "partial"},
      {"GET /assets/{name}", ""},
  };
  return m;
}

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string refusal(const std::string& name, const std::string& route) {
  const std::string& list = accepted_query().at(route);
  return name + " is not a query parameter of " + route +
         (list.empty() ? "; this route takes no query parameters" : "; allowed here: " + list);
}

httplib::Result send(httplib::Client& client, const std::string& method, const std::string& path) {
  if (method == "POST") return client.Post(path, "{}", "application/json");
  if (method == "DELETE") return client.Delete(path);
  return client.Get(path);
}

// The document lists what the rule accepts: a client reading it is never refused.
TEST(QueryRule, TheOpenApiDocumentListsTheAcceptedParameters) {
  const json doc = api::openapi_document("test");
  for (const auto& [route, list] : accepted_query()) {
    const std::string method = route.substr(0, route.find(' '));
    const std::string path = route.substr(route.find(' ') + 1);
    std::string documented;
    for (const json& p : doc["paths"][path][lower(method)].value("parameters", json::array())) {
      if (p["in"] == "query")
        documented += (documented.empty() ? "" : ", ") + p["name"].get<std::string>();
    }
    EXPECT_EQ(documented, list) << route;
  }
}

TEST(QueryRule, CamTablesRefuseAParameterTheyDoNotTake) {
  Server server;
  const std::string key = planned_key(server);
  auto client = server.client();
  const std::string cam = "/v1/plans/" + key + "/cam";
  // A misspelt period would otherwise give the default 1 ms table without a word.
  const auto typo = client.Get(cam + ".csv?periodms=5");
  ASSERT_TRUE(typo);
  EXPECT_EQ(typo->status, 422);
  const json e = error_of(typo);
  EXPECT_EQ(e.at("code"), "invalid_value");
  EXPECT_EQ(e.at("field"), "periodms");
  EXPECT_EQ(e.at("message"), refusal("periodms", "GET /v1/plans/{key}/cam.csv"));
  // With accepted parameters before it: still refused, naming the unknown one.
  const auto st =
      client.Get(cam + ".st?master_period=360&master_start=0&master_end=180&master_stp=1");
  ASSERT_TRUE(st);
  EXPECT_EQ(st->status, 422);
  EXPECT_EQ(error_of(st).at("message"), refusal("master_stp", "GET /v1/plans/{key}/cam.st"));
  // A parameter of another route says which one takes it.
  const auto view = client.Get("/v1/batches/no-such-job?view=compact");
  ASSERT_TRUE(view);
  EXPECT_EQ(view->status, 422);
  EXPECT_EQ(error_of(view).at("message"),
            "view is not a query parameter of GET /v1/batches/{id} (POST /v1/plans takes it); "
            "allowed here: offset, limit");
  // Names are compared decoded: period%5Fms is period_ms.
  const auto encoded = client.Get(cam + ".csv?period%5Fms=2");
  ASSERT_TRUE(encoded);
  EXPECT_EQ(encoded->status, 200) << encoded->body;
  EXPECT_TRUE(encoded->body.starts_with("t_s,position_mm")) << encoded->body.substr(0, 80);
  // A name that is not a plain word is quoted as received.
  const auto odd = client.Get(cam + ".csv?%22x%20y=1");
  ASSERT_TRUE(odd);
  EXPECT_EQ(odd->status, 422);
  EXPECT_EQ(error_of(odd).at("message"), refusal("\"\\\"x y\"", "GET /v1/plans/{key}/cam.csv"));
}

TEST(QueryRule, EveryRouteRefusesAParameterItDoesNotTake) {
  Server server;
  const std::string key = planned_key(server);
  auto client = server.client();
  int checked = 0;
  for (const api::Route& route : api::routes()) {
    const std::string name = std::string(route.method) + " " + std::string(route.path);
    if (route.path == "/") continue;  // the page's query string is its own state (below)
    ASSERT_TRUE(accepted_query().contains(name)) << name << " has no entry in this test";
    std::string path(route.path);
    path = std::regex_replace(path, std::regex("\\{key\\}"), key);
    path = std::regex_replace(path, std::regex("\\{id\\}"), "no-such-job");
    path = std::regex_replace(path, std::regex("\\{name\\}"), "app.js");
    const auto r = send(client, std::string(route.method), path + "?bogus=1");
    ASSERT_TRUE(r) << name;
    EXPECT_EQ(r->status, 422) << name << ": " << r->body;
    const json e = error_of(r);
    EXPECT_EQ(e.value("field", ""), "bogus") << name;
    EXPECT_EQ(e.value("message", ""), refusal("bogus", name)) << name;
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(accepted_query().size()));
  // The accepted ones still work, and the page takes its own state.
  const auto compact =
      client.Post("/v1/plans?view=compact", plan_body().dump(), "application/json");
  ASSERT_TRUE(compact);
  EXPECT_EQ(compact->status, 200);
  EXPECT_EQ(json::parse(compact->body).at("view"), "compact");
  const auto page = client.Get("/?r=48.5&h=150&strategy=notch&anything=1");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
}

// A repeated view is refused as every repeated parameter is, the same value twice included (the
// HTTP library keeps one of two identical pairs).
TEST(QueryRule, ARepeatedViewIsRefusedLikeEveryRepeatedParameter) {
  Server server;
  const std::string key = planned_key(server);
  auto client = server.client();
  const auto cam = client.Get("/v1/plans/" + key + "/cam.csv?period_ms=1&period_ms=1");
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->status, 422);
  EXPECT_EQ(error_of(cam).at("message"),
            "period_ms is given twice (1 and 1): give each query parameter once");
  const std::string twice =
      R"(view is given twice (full and full): give each query parameter once, one of "full", )"
      R"("compact")";
  const auto get = client.Get("/v1/plans/" + key + "?view=full&view=full");
  const auto post =
      client.Post("/v1/plans?view=full&view=full", plan_body().dump(), "application/json");
  const auto batch =
      client.Post("/v1/plans/batch?view=compact&view=full&view=compact",
                  json{{"requests", json::array({plan_body()})}}.dump(), "application/json");
  for (const auto* r : {&get, &post}) {
    ASSERT_TRUE(*r);
    EXPECT_EQ((*r)->status, 422) << (*r)->body;
    const json e = error_of(*r);
    EXPECT_EQ(e.at("field"), "view");
    EXPECT_EQ(e.at("message"), twice);
  }
  ASSERT_TRUE(batch);
  EXPECT_EQ(batch->status, 422) << batch->body;
  EXPECT_EQ(error_of(batch).at("message"),
            R"(view is given 3 times (compact, full and compact): give each query parameter )"
            R"(once, one of "full", "compact")");
}

TEST(EncodedSlash, IsPartOfTheSegmentNeverASeparator) {
  Server server;
  const std::string key = planned_key(server);
  auto client = server.client();
  // Decoded before routing, this was the cam table of `key`.
  const auto cam = client.Get("/v1/plans/" + key + "%2Fcam.csv");
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->status, 404) << cam->body.substr(0, 80);
  json e = error_of(cam);
  EXPECT_EQ(e.at("code"), "not_found");
  EXPECT_EQ(e.at("field"), "key");
  EXPECT_EQ(e.at("message"), "key \"" + key +
                                 "/cam.csv\" holds a '/' (sent as %2F) and no key of GET "
                                 "/v1/plans/{key} does");
  // Lower-case escapes too, and the route of the request's method is named.
  const auto job = client.Delete("/v1/batches/x%2fresults.csv");
  ASSERT_TRUE(job);
  EXPECT_EQ(job->status, 404);
  EXPECT_EQ(error_of(job).at("message"),
            "id \"x/results.csv\" holds a '/' (sent as %2F) and no id of DELETE "
            "/v1/batches/{id} does");
  // A path of no route's shape.
  const auto none = client.Get("/v1%2Ffluids");
  ASSERT_TRUE(none);
  EXPECT_EQ(none->status, 404);
  EXPECT_EQ(error_of(none).at("message"),
            "no endpoint GET /v1%2Ffluids: a '/' sent as %2F is part of a path segment; see "
            "/v1/openapi.json");
  // A request with a body: refused before the body is read, and the connection is closed.
  const auto posted = client.Post("/v1/plans%2Fbatch", "{\"requests\": []}", "application/json");
  ASSERT_TRUE(posted);
  EXPECT_EQ(posted->status, 404);
  EXPECT_EQ(posted->get_header_value("Connection"), "close");
  EXPECT_EQ(error_of(posted).at("message"),
            "no endpoint POST /v1/plans%2Fbatch: a '/' sent as %2F is part of a path segment; see "
            "/v1/openapi.json");
  // A key without an encoded '/' is routed as before.
  const auto plain = client.Get("/v1/plans/" + key);
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->status, 200);
}

TEST(RouteLabels, EveryMethodIsCountedTimedAndLoggedUnderItsRoute) {
  Server server;
  auto client = server.client();
  // One connection: the server logs and times a request before it reads the next one on it, so
  // /metrics below holds every request before it.
  client.set_keep_alive(true);
  ASSERT_TRUE(client.Get("/healthz", {{"X-Request-Id", "get-1"}}));
  ASSERT_TRUE(client.Head("/healthz", {{"X-Request-Id", "head-2"}}));
  ASSERT_TRUE(client.Post("/v1/plans", {{"X-Request-Id", "post-3"}}, plan_body().dump(),
                          "application/json"));
  const auto deleted = client.Delete("/v1/batches/no-such-job", {{"X-Request-Id", "delete-4"}});
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 404);
  // A method the route does not answer: 405, under the route of its path.
  const auto put = client.Put("/healthz", {{"X-Request-Id", "put-5"}}, "", "application/json");
  ASSERT_TRUE(put);
  EXPECT_EQ(put->status, 405);
  const std::map<std::string, std::string> expected{{"GET", "/healthz"},
                                                    {"HEAD", "/healthz"},
                                                    {"POST", "/v1/plans"},
                                                    {"DELETE", "/v1/batches/{id}"},
                                                    {"PUT", "/healthz"}};
  // The PUT's connection is closed (its body is never read): it is timed after its answer, on its
  // own thread, while /metrics comes on a new connection; read until it has landed.
  std::string metrics;
  for (const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);;) {
    metrics = client.Get("/metrics")->body;
    if (test::metric(metrics,
                     "slosh_http_request_duration_seconds_count{route=\"/healthz\","
                     "method=\"PUT\"}") >= 1 ||
        std::chrono::steady_clock::now() > deadline) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  for (const auto& [method, route] : expected) {
    EXPECT_EQ(test::metric(metrics, "slosh_http_request_duration_seconds_count{route=\"" + route +
                                        "\",method=\"" + method + "\"}"),
              1)
        << method;
  }
  EXPECT_EQ(test::metric(metrics,
                         "slosh_http_requests_total{route=\"/v1/batches/{id}\",status="
                         "\"404\"}"),
            1);
  EXPECT_EQ(test::metric(metrics,
                         "slosh_http_request_duration_seconds_count{route=\"other\","
                         "method=\"DELETE\"}"),
            -1);
  ASSERT_EQ(server.stop(), 0);
  const std::string log = server.log();
  for (const auto& [id, line] : std::map<std::string, std::string>{
           {"get-1", "method=GET path=/healthz status=200"},
           {"head-2", "method=HEAD path=/healthz status=200"},
           {"post-3", "method=POST path=/v1/plans status=200"},
           {"delete-4", "method=DELETE path=/v1/batches/no-such-job status=404"},
           {"put-5", "method=PUT path=/healthz status=405"}}) {
    const std::string route = expected.at(line.substr(7, line.find(' ') - 7));
    const std::regex access("request id=" + id + " " + line +
                            " cache=\\S+ ms=[0-9.]+ bytes=\\d+ route=" +
                            std::regex_replace(route, std::regex("[{}]"), "\\$&") + "(\\s|$)");
    EXPECT_TRUE(std::regex_search(log, access)) << id << " in\n" << log;
  }
}

// PUT and PATCH are answered by no route: without a body (no Content-Length) they are refused at
// once with 405 and Allow, not read until the read times out.
TEST(MethodRule, PutAndPatchWithoutABodyAreRefusedAtOnce) {
  Server server;
  const std::vector<std::tuple<std::string, std::string, std::string>> cases{
      {"PUT", "/v1/plans", "HTTP/1.1 405 "},
      {"PATCH", "/v1/plans/abc", "HTTP/1.1 405 "},
      {"PUT", "/nothing", "HTTP/1.1 404 "}};
  for (const auto& [method, path, status_line] : cases) {
    test::Raw raw(server.port());
    ASSERT_TRUE(raw.connected());
    // The client keeps its end open (it only asks the server to close after the answer): a server
    // waiting for a body would wait until its read timeout and answer 400.
    ASSERT_TRUE(
        raw.send(method + " " + path + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"));
    const std::string answer = raw.read_all();
    EXPECT_TRUE(answer.starts_with(status_line)) << method << " " << path << ":\n" << answer;
    if (status_line.find("405") != std::string::npos) {
      EXPECT_NE(
          answer.find(path == "/v1/plans" ? "\r\nAllow: POST\r\n" : "\r\nAllow: GET, HEAD\r\n"),
          std::string::npos)
          << answer;
      EXPECT_NE(answer.find("\"" + method + " is not allowed on " + path), std::string::npos)
          << answer;
    }
    EXPECT_NE(answer.find("\r\nConnection: close\r\n"), std::string::npos) << answer;
  }
}

// The text log line of request `id` (empty when there is none), without spdlog's time and level.
std::string access_line(const std::string& log, const std::string& id) {
  const std::string start = "request id=" + id + " ";
  const std::size_t at = log.find(start);
  if (at == std::string::npos) return "";
  return log.substr(at, log.find('\n', at) - at);
}

// A request refused before or instead of its handler (405, 413, a %2F 404) is counted, timed and
// logged under the route of its path; "other" is only a path no route has.
TEST(RouteLabels, RefusalsCarryTheRouteOfTheirPath) {
  test::TempDir dir;
  test::write_file(dir / "config.json", R"({"max_body_bytes": 1024})");
  Server server({"--config", (dir / "config.json").string()});
  ASSERT_GT(server.port(), 0) << server.log();
  auto client = server.client();
  client.set_keep_alive(true);
  struct Case {
    std::string id, method, path;
    int status;
    std::string route;
  };
  const std::vector<Case> cases{
      {"del-1", "DELETE", "/v1/plans/abc", 405, "/v1/plans/{key}"},
      {"opt-2", "OPTIONS", "/v1/plans/abc", 405, "/v1/plans/{key}"},
      {"pat-3", "PATCH", "/v1/plans/abc", 405, "/v1/plans/{key}"},
      {"put-4", "PUT", "/v1/plans", 405, "/v1/plans"},
      {"opt-5", "OPTIONS", "/v1/plans", 405, "/v1/plans"},
      {"pat-6", "PATCH", "/v1/plans", 405, "/v1/plans"},
      {"get-7", "GET", "/v1/plans/batch", 405, "/v1/plans/batch"},
      {"slash-8", "GET", "/v1/plans/a%2Fb", 404, "/v1/plans/{key}"},
      {"none-9", "OPTIONS", "/nothing", 404, "other"},
      {"big-10", "POST", "/v1/plans", 413, "/v1/plans"},
  };
  const std::string big = "{\"x\": \"" + std::string(4096, 'a') + "\"}";
  for (const Case& c : cases) {
    const httplib::Headers id{{"X-Request-Id", c.id}};
    const httplib::Result r =
        c.method == "DELETE"    ? client.Delete(c.path, id)
        : c.method == "OPTIONS" ? client.Options(c.path, id)
        : c.method == "PATCH"   ? client.Patch(c.path, id, "{}", "application/json")
        : c.method == "PUT"     ? client.Put(c.path, id, "{}", "application/json")
        : c.method == "POST"    ? client.Post(c.path, id, big, "application/json")
                                : client.Get(c.path, id);
    ASSERT_TRUE(r) << c.id;
    EXPECT_EQ(r->status, c.status) << c.id;
  }
  // An oversized body announced with Expect: 100-continue is refused before any handler runs.
  const std::vector<Case> raw_cases{
      {"big-11", "POST", "/v1/plans/batch", 413, "/v1/plans/batch"},
      {"big-12", "POST", "/v1/plans", 413, "/v1/plans"},
  };
  for (const Case& c : raw_cases) {
    test::Raw raw(server.port());
    ASSERT_TRUE(raw.connected());
    ASSERT_TRUE(raw.send(c.method + " " + c.path + " HTTP/1.1\r\nHost: x\r\nX-Request-Id: " + c.id +
                         "\r\nContent-Type: application/json\r\nContent-Length: 100000\r\n"
                         "Expect: 100-continue\r\nConnection: close\r\n\r\n"));
    EXPECT_TRUE(raw.read_all().starts_with("HTTP/1.1 413 ")) << c.id;
  }
  std::map<std::pair<std::string, std::string>, int> counted;
  for (const Case& c : cases) ++counted[{c.route, c.method}];
  for (const Case& c : raw_cases) ++counted[{c.route, c.method}];
  const auto count_of = [](const std::string& text, const std::pair<std::string, std::string>& k) {
    return test::metric(text, "slosh_http_request_duration_seconds_count{route=\"" + k.first +
                                  "\",method=\"" + k.second + "\"}");
  };
  // A refusal that closes its connection (a %2F path, an oversized body) is timed by the server
  // after its answer is sent, on that connection's thread, while the client already sends the
  // next request on a new connection: /metrics is read until those observations have landed.
  std::string metrics;
  for (const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);;) {
    metrics = client.Get("/metrics")->body;
    const bool all = std::all_of(counted.begin(), counted.end(), [&](const auto& kv) {
      return count_of(metrics, kv.first) >= kv.second;
    });
    if (all || std::chrono::steady_clock::now() > deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  for (const auto& [key, n] : counted) {
    EXPECT_EQ(count_of(metrics, key), n) << key.first << " " << key.second;
  }
  EXPECT_EQ(test::metric(metrics, "slosh_http_requests_total{route=\"/v1/plans\",status=\"413\"}"),
            2);
  ASSERT_EQ(server.stop(), 0);
  const std::string log = server.log();
  std::vector<Case> all = cases;
  all.insert(all.end(), raw_cases.begin(), raw_cases.end());
  for (const Case& c : all) {
    const std::string line = access_line(log, c.id);
    const std::string head = "request id=" + c.id + " method=" + c.method + " path=" + c.path +
                             " status=" + std::to_string(c.status) + " cache=- ms=";
    EXPECT_EQ(line.substr(0, head.size()), head) << log;
    const std::regex tail("^[0-9]+\\.[0-9]{3} bytes=[0-9]+ route=(\\S+)$");
    std::smatch m;
    const std::string rest = line.substr(std::min(head.size(), line.size()));
    ASSERT_TRUE(std::regex_match(rest, m, tail)) << line;
    EXPECT_EQ(m[1], c.route) << line;
  }
}

TEST(AccessLog, WritesThePathAsSentSoNoRequestForgesALine) {
  Server server;
  auto client = server.client();
  client.set_keep_alive(true);
  const std::string forged =
      "/v1/plans/x%0D%0A%5B2026-11-26%2022%3A00%3A00.000%5D%20%5Binfo%5D%20request%20id%3D1%20"
      "method%3DDELETE%20path%3D%2Fadmin%20status%3D200";
  ASSERT_TRUE(client.Get(forged, {{"X-Request-Id", "forged-1"}}));
  ASSERT_TRUE(client.Get("/v1/plans/a%2Fb", {{"X-Request-Id", "slash-2"}}));
  ASSERT_TRUE(client.Get("/v1/plans/a%00b?view=full", {{"X-Request-Id", "nul-3"}}));
  {
    // Bytes no client library sends unescaped: non-ASCII, a control byte, a backslash.
    test::Raw raw(server.port());
    ASSERT_TRUE(raw.connected());
    ASSERT_TRUE(
        raw.send("GET /caf\xc3\xa9\x01\\x HTTP/1.1\r\nHost: x\r\nX-Request-Id: raw-4\r\n"
                 "Connection: close\r\n\r\n"));
    raw.read_all();
  }
  ASSERT_EQ(server.stop(), 0);
  const std::string log = server.log();
  const std::regex tail(" cache=- ms=[0-9]+\\.[0-9]{3} bytes=[0-9]+ route=\\S+$");
  const std::map<std::string, std::string> expected{
      {"forged-1", "request id=forged-1 method=GET path=" + forged + " status=404"},
      {"slash-2", "request id=slash-2 method=GET path=/v1/plans/a%2Fb status=404"},
      {"nul-3", "request id=nul-3 method=GET path=/v1/plans/a%00b status=404"},
      {"raw-4", "request id=raw-4 method=GET path=/caf\\xc3\\xa9\\x01\\x5cx status=404"}};
  for (const auto& [id, head] : expected) {
    const std::string line = access_line(log, id);
    EXPECT_EQ(line.substr(0, head.size()), head) << log;
    EXPECT_TRUE(std::regex_search(line.substr(std::min(head.size(), line.size())), tail)) << line;
  }
  // No line of the log was started by a request: each begins with spdlog's "[date time]".
  EXPECT_EQ(log.find("[2026-11-26 22:00:00.000]"), std::string::npos);
  EXPECT_EQ(log.find("path=/admin"), std::string::npos);
}

}  // namespace test_route_rules
}  // namespace slosh
