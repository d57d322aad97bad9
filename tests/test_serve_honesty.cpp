// What the serving layer says about an answer is true of the bytes it sent (docs/service.md):
// an answer cut short by its time budget carries no validator a complete answer could carry, so
// a conditional request never keeps it; a request never waits on a solve or search with a larger
// budget than its own; a batch whose client hung up stops its queued items; a 304 carries no
// Content-Length other than its 200's; field lines of one header combine; and the counters name
// the true cause of work that was stopped or skipped. Real server on loopback.

#include <httplib.h>

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/process.hpp"
#include "support/raw_client.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_serve_honesty {

using nlohmann::json;

// The thesis format (SPEC §7's example) planned with `strategy`.
json thesis_plan(const std::string& strategy) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}})");
  body["strategy"] = strategy;
  return body;
}

// The thesis format's min-time search of notch (about 25 plans) with `time_limit_s`.
json thesis_min_time(double time_limit_s) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800},
      "motion_time_max_s": 2, "eta_rest_max_mm": 3, "strategies": ["notch"]})");
  body["options"] = {{"time_limit_s", time_limit_s}};
  return body;
}

// A client that sends exactly the headers given (no Accept-Encoding of its own, no inflating).
httplib::Client plain_client(const test::Server& server) {
  httplib::Client c = server.client();
  c.set_decompress(false);
  return c;
}

std::string raw_post(const std::string& path, const std::string& body) {
  return "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n" +
         "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

// A min-time search on a 1 ms scan with 1 000 plans allowed and an eta_motion limit (0.01 mm) no T
// meets: seconds to minutes of work however fast a plan is; only its budget or a stop ends it.
json endless_min_time(double time_limit_s) {
  json body = json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800},
    "motion_time_max_s": 5, "eta_rest_max_mm": 3, "eta_motion_max_mm": 0.01,
    "scan_step_s": 0.001, "max_plans": 1000, "strategies": ["time_domain"]})");
  body["options"] = {{"time_limit_s", time_limit_s}};
  return body;
}

// A server whose budget allows the endless search, with `config` members added.
class LongBudgetServer {
 public:
  LongBudgetServer(json config, const std::vector<std::string>& extra) {
    config["solve_budget_s"] = 600;
    test::write_file(dir_ / "slosh.json", config.dump());
    std::vector<std::string> args{"--config", (dir_ / "slosh.json").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    server_ = std::make_unique<test::Server>(args);
  }
  const test::Server& operator*() const { return *server_; }

 private:
  test::TempDir dir_;
  std::unique_ptr<test::Server> server_;
};

const std::string kBusy = "slosh_busy_workers";
const std::string kCancelledPlan = R"(slosh_solves_cancelled_total{kind="plan"})";
const std::string kCancelledMinTime = R"(slosh_solves_cancelled_total{kind="min_time"})";
const std::string kBackgroundQueue = "slosh_pool_background_queue_depth";

// The whole HTTP answer to `request` sent on its own connection (the request says
// Connection: close).
std::string round_trip(const test::Server& server, const std::string& request) {
  test::Raw raw(server.port());
  EXPECT_TRUE(raw.send(request));
  return raw.read_all();
}

// The value of header `name` in a raw answer's head; nullopt when absent.
std::optional<std::string> head_value(const std::string& answer, const std::string& name) {
  const std::string head = answer.substr(0, answer.find("\r\n\r\n"));
  const std::string line = "\r\n" + name + ": ";
  const auto at = head.find(line);
  if (at == std::string::npos) return std::nullopt;
  const auto from = at + line.size();
  return head.substr(from, head.find("\r\n", from) - from);
}

// A time_domain plan needs several milliseconds on any machine: within 1 ms it ends time_limit,
// with the uniform law. Its reply must not carry the tag of the complete plan the same recipe
// gets later (the key holds no time_limit_s), or a client revalidating the cut-short plan would be
// told 304 and keep it.
TEST(EtagHonesty, APlanCutShortByItsBudgetNeverRevalidatesAgainstTheCompletePlan) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client c = plain_client(server);
  json cut = thesis_plan("time_domain");
  cut["options"] = {{"time_limit_s", 0.001}};
  const auto first = c.Post("/v1/plans", cut.dump(), "application/json");
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 200) << first->body;
  const json short_plan = json::parse(first->body);
  ASSERT_EQ(short_plan.at("status"), "time_limit") << first->body.substr(0, 400);
  const std::string key = short_plan.at("key");
  const std::string kept_tag = first->get_header_value("ETag");
  // The complete plan of the same recipe, now cached.
  const auto full = c.Post("/v1/plans", thesis_plan("time_domain").dump(), "application/json");
  ASSERT_TRUE(full);
  ASSERT_EQ(full->status, 200) << full->body;
  const json complete = json::parse(full->body);
  ASSERT_EQ(complete.at("status"), "optimal");
  ASSERT_EQ(complete.at("key"), key);
  ASSERT_NE(complete.at("durations_s"), short_plan.at("durations_s"));
  // Whatever the cut-short reply carried (no tag at all is the service's choice), revalidating
  // with it answers the complete plan in full, in every view and coding, never 304.
  EXPECT_EQ(kept_tag, "") << "a cut-short plan carries no validator";
  if (!kept_tag.empty()) {
    const std::string& tag = kept_tag;
    for (const char* coding : {"identity", "gzip"}) {
      const httplib::Headers h{{"If-None-Match", tag}, {"Accept-Encoding", coding}};
      const auto post = c.Post("/v1/plans", h, cut.dump(), "application/json");
      ASSERT_TRUE(post);
      EXPECT_EQ(post->status, 200) << coding;
      for (const std::string& path : {"/v1/plans/" + key, "/v1/plans/" + key + "?view=compact"}) {
        const auto get = c.Get(path, h);
        ASSERT_TRUE(get);
        EXPECT_EQ(get->status, 200) << path << " " << coding;
      }
    }
  }
  // The complete plan's own tag still revalidates it.
  const std::string complete_tag = full->get_header_value("ETag");
  EXPECT_EQ(complete_tag, "\"" + key + "\"");
  const auto again =
      c.Post("/v1/plans", {{"If-None-Match", complete_tag}}, cut.dump(), "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
}

// The same for a min-time search cut short by its budget (not cached) against the complete search
// of the same key answered later.
TEST(EtagHonesty, AMinTimeAnswerCutShortByItsBudgetNeverRevalidatesAgainstTheCompleteOne) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client c = plain_client(server);
  // About 25 plans of a millisecond or more each: a 1 ms budget runs out.
  const auto first = c.Post("/v1/min-time", thesis_min_time(0.001).dump(), "application/json");
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 200) << first->body;
  const json cut = json::parse(first->body);
  ASSERT_EQ(cut.at("strategies").at(0).at("status"), "time_limit") << first->body.substr(0, 400);
  const std::string kept_tag = first->get_header_value("ETag");
  const auto full = c.Post("/v1/min-time", thesis_min_time(10).dump(), "application/json");
  ASSERT_TRUE(full);
  ASSERT_EQ(full->status, 200) << full->body;
  const json complete = json::parse(full->body);
  ASSERT_EQ(complete.at("strategies").at(0).at("status"), "optimal") << full->body.substr(0, 400);
  EXPECT_EQ(kept_tag, "") << "a cut-short min-time answer carries no validator";
  if (!kept_tag.empty()) {
    const auto again = c.Post("/v1/min-time", {{"If-None-Match", kept_tag}},
                              thesis_min_time(0.001).dump(), "application/json");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 200);
  }
  const std::string complete_tag = full->get_header_value("ETag");
  ASSERT_FALSE(complete_tag.empty());
  const auto again = c.Post("/v1/min-time", {{"If-None-Match", complete_tag}},
                            thesis_min_time(0.001).dump(), "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
}

// A 304 carries the Content-Length its 200 would have had, or none (RFC 9110 8.6): never the
// "0" of an empty body, which a cache merging the 304's headers into its stored 200 would take.
TEST(EtagHonesty, A304CarriesNoContentLengthButThe200s) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const auto made =
      server.client().Post("/v1/plans", thesis_plan("notch").dump(), "application/json");
  ASSERT_TRUE(made);
  ASSERT_EQ(made->status, 200);
  const std::string key = json::parse(made->body).at("key");
  const auto search =
      server.client().Post("/v1/min-time", thesis_min_time(10).dump(), "application/json");
  ASSERT_TRUE(search);
  ASSERT_EQ(search->status, 200);
  const std::string plan = thesis_plan("notch").dump();
  const std::string min_time = thesis_min_time(10).dump();
  const auto post = [](const std::string& path, const std::string& body, const std::string& h) {
    return "POST " + path + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n" + h +
           "Content-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
           "\r\n\r\n" + body;
  };
  const auto get = [](const std::string& path, const std::string& h) {
    return "GET " + path + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n" + h + "\r\n";
  };
  struct Case {
    std::string name;
    std::function<std::string(const std::string&)> request;  // of the extra header lines
  };
  const std::vector<Case> cases{
      {"POST /v1/plans", [&](const std::string& h) { return post("/v1/plans", plan, h); }},
      {"GET /v1/plans/{key}", [&](const std::string& h) { return get("/v1/plans/" + key, h); }},
      {"POST /v1/min-time",
       [&](const std::string& h) { return post("/v1/min-time", min_time, h); }},
      {"GET /", [&](const std::string& h) { return get("/", h); }}};
  for (const Case& c : cases) {
    for (const std::string coding : {"", "Accept-Encoding: gzip\r\n"}) {
      const std::string full = round_trip(server, c.request(coding));
      ASSERT_EQ(full.substr(0, 12), "HTTP/1.1 200") << c.name << full.substr(0, 300);
      const auto tag = head_value(full, "ETag");
      ASSERT_TRUE(tag) << c.name;
      const std::string body_length = std::to_string(full.size() - full.find("\r\n\r\n") - 4);
      const std::string answer =
          round_trip(server, c.request(coding + "If-None-Match: " + *tag + "\r\n"));
      ASSERT_EQ(answer.substr(0, 12), "HTTP/1.1 304") << c.name << answer.substr(0, 300);
      const auto length = head_value(answer, "Content-Length");
      if (length) {
        EXPECT_EQ(*length, body_length) << c.name << " " << coding;
      }
    }
  }
}

// A request never waits for a search with a larger budget than its own: it searches on its own
// and is answered within its budget, with its own budget in the message. Before, it joined the
// larger search and, queue_wait_s after its own budget, got a 504 (or, with a long queue_wait_s,
// the other search's answer naming the other client's budget).
TEST(FlightBudget, AMinTimeRequestWithASmallerBudgetNeverWaitsForALargerOnesSearch) {
  const LongBudgetServer holder(json{{"queue_wait_s", 0.5}}, {"--workers", "2"});
  const test::Server& server = *holder;
  ASSERT_GT(server.port(), 0) << server.log();
  test::Raw larger(server.port());
  ASSERT_TRUE(larger.send(raw_post("/v1/min-time", endless_min_time(500).dump())));
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBusy) == 1; }))
      << server.log();
  const auto r =
      server.client().Post("/v1/min-time", endless_min_time(1).dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json strategy = json::parse(r->body).at("strategies").at(0);
  EXPECT_EQ(strategy.at("status"), "time_limit");
  const std::string message = strategy.at("message");
  EXPECT_NE(message.find("(time_limit_s 1.000 s)"), std::string::npos) << message;
  EXPECT_EQ(message.find("time_limit_s 500"), std::string::npos) << message;
  EXPECT_EQ(test::metric_of(server, "slosh_min_time_joins_total"), 0);
  // The same budget still shares the running search.
  test::Raw same(server.port());
  ASSERT_TRUE(same.send(raw_post("/v1/min-time", endless_min_time(500).dump())));
  EXPECT_TRUE(
      test::wait_until([&] { return test::metric_of(server, "slosh_min_time_joins_total") == 1; }));
}

// The same for plans and robust plans: a request whose recipe is being solved with a larger
// budget queues a solve of its own (two solves queued) instead of joining; the same budget joins.
// The one worker is held by a search, so the solves stay queued and the counts are exact.
TEST(FlightBudget, APlanWithASmallerBudgetNeverJoinsALargerOnesSolve) {
  const LongBudgetServer holder(json{{"queue_wait_s", 0.3}}, {"--workers", "1"});
  const test::Server& server = *holder;
  ASSERT_GT(server.port(), 0) << server.log();
  test::Raw search(server.port());
  ASSERT_TRUE(search.send(raw_post("/v1/min-time", endless_min_time(500).dump())));
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBusy) == 1; }))
      << server.log();
  json robust = thesis_plan("auto");
  robust["options"]["uncertainty"] = {{"omega_error_pct", 5}};
  std::vector<std::unique_ptr<test::Raw>> waiting;
  double queued = 0;
  for (json larger : {thesis_plan("multi_notch"), robust}) {
    larger["options"]["time_limit_s"] = 60;
    waiting.push_back(std::make_unique<test::Raw>(server.port()));
    ASSERT_TRUE(waiting.back()->send(raw_post("/v1/plans", larger.dump())));
    ++queued;
    ASSERT_TRUE(
        test::wait_until([&] { return test::metric_of(server, "slosh_queue_depth") == queued; }));
    json smaller = larger;
    smaller["options"]["time_limit_s"] = 0.2;
    const auto r = server.client().Post("/v1/plans", smaller.dump(), "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 504) << r->body;  // its own solve queued behind the search
    EXPECT_EQ(json::parse(r->body)["error"]["message"],
              "the plan did not finish within its budget of 0.2 s plus 0.3 s of queueing");
    EXPECT_EQ(test::metric_of(server, "slosh_singleflight_joins_total"), 0) << larger.dump();
    ++queued;  // its stopped solve stays queued until the worker takes (and skips) it
    EXPECT_EQ(test::metric_of(server, "slosh_queue_depth"), queued);
  }
  // The same budget joins.
  json same = thesis_plan("multi_notch");
  same["options"]["time_limit_s"] = 60;
  test::Raw joiner(server.port());
  ASSERT_TRUE(joiner.send(raw_post("/v1/plans", same.dump())));
  EXPECT_TRUE(test::wait_until(
      [&] { return test::metric_of(server, "slosh_singleflight_joins_total") == 1; }));
}

// A batch whose client hung up stops its queued items (as a plan's does): none is solved after.
// The one worker is held by a search, so the items wait in the background queue.
TEST(BatchHangUp, TheQueuedItemsOfABatchWhoseClientHungUpAreNeverSolved) {
  const LongBudgetServer holder(json::object(), {"--workers", "1"});
  const test::Server& server = *holder;
  ASSERT_GT(server.port(), 0) << server.log();
  auto search = std::make_unique<test::Raw>(server.port());
  ASSERT_TRUE(search->send(raw_post("/v1/min-time", endless_min_time(500).dump())));
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBusy) == 1; }))
      << server.log();
  json batch{{"requests", json::array()}};
  for (int i = 0; i < 4; ++i) {
    json item = thesis_plan("notch");
    item["format"]["stroke_mm"] = 800 + i;
    batch["requests"].push_back(item);
  }
  {
    test::Raw client(server.port());
    ASSERT_TRUE(client.send(raw_post("/v1/plans/batch", batch.dump())));
    ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBackgroundQueue) == 4; }))
        << server.log();
  }  // the client hangs up
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kCancelledPlan) == 4; }))
      << server.log();
  search.reset();  // the worker is free: the queued items are taken and skipped
  ASSERT_TRUE(test::wait_until([&] {
    return test::metric_of(server, kCancelledMinTime) == 1 && test::metric_of(server, kBusy) == 0 &&
           test::metric_of(server, kBackgroundQueue) == 0;
  })) << server.log();
  EXPECT_EQ(test::metric_of(server, R"(slosh_solve_seconds_count{strategy="notch"})"), -1);
  // A new request for one of the recipes solves it afresh.
  const auto again =
      server.client().Post("/v1/plans", batch["requests"][0].dump(), "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200) << again->body;
  EXPECT_EQ(json::parse(again->body).at("status"), "optimal");
}

// RFC 9110 5.3: field lines of one header combine with commas, in order.
TEST(HttpFieldLines, AcceptEncodingOverTwoLinesIsOneList) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const auto made =
      server.client().Post("/v1/plans", thesis_plan("notch").dump(), "application/json");
  ASSERT_TRUE(made);
  const std::string key = json::parse(made->body).at("key");
  const auto coding = [&](const std::string& lines) {
    const std::string answer =
        round_trip(server, "GET /v1/plans/" + key +
                               " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n" + lines + "\r\n");
    EXPECT_EQ(answer.substr(0, 12), "HTTP/1.1 200") << answer.substr(0, 200);
    return head_value(answer, "Content-Encoding").value_or("identity");
  };
  EXPECT_EQ(coding("Accept-Encoding: identity\r\nAccept-Encoding: gzip\r\n"), "gzip");
  EXPECT_EQ(coding("Accept-Encoding: gzip\r\nAccept-Encoding: identity\r\n"), "gzip");
  EXPECT_EQ(coding("Accept-Encoding: gzip\r\nAccept-Encoding: gzip;q=0\r\n"),
            coding("Accept-Encoding: gzip, gzip;q=0\r\n"));
  EXPECT_EQ(coding("Accept-Encoding: gzip;q=0\r\nAccept-Encoding: gzip\r\n"),
            coding("Accept-Encoding: gzip;q=0, gzip\r\n"));
  // A list of tags over two If-None-Match lines revalidates as on one line.
  const std::string answer = round_trip(
      server, "GET /v1/plans/" + key +
                  " HTTP/1.1\r\nHost: x\r\nConnection: close\r\nIf-None-Match: \"other\"\r\n"
                  "If-None-Match: \"" +
                  key + "\"\r\n\r\n");
  EXPECT_EQ(answer.substr(0, 12), "HTTP/1.1 304") << answer.substr(0, 200);
}

// A search skipped while queued because its client left is counted as cancelled only: never as a
// search that ran, nor as a (sub-microsecond) search time.
TEST(MetricsCauses, ASkippedQueuedSearchIsNeitherCountedNorTimed) {
  const LongBudgetServer holder(json::object(), {"--workers", "1"});
  const test::Server& server = *holder;
  ASSERT_GT(server.port(), 0) << server.log();
  auto running = std::make_unique<test::Raw>(server.port());
  ASSERT_TRUE(running->send(raw_post("/v1/min-time", endless_min_time(500).dump())));
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBusy) == 1; }))
      << server.log();
  {
    test::Raw queued(server.port());
    ASSERT_TRUE(queued.send(raw_post("/v1/min-time", thesis_min_time(10).dump())));
    ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBackgroundQueue) == 1; }))
        << server.log();
  }  // its client hangs up while it is queued
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kCancelledMinTime) == 1; }));
  running.reset();
  ASSERT_TRUE(test::wait_until([&] {
    return test::metric_of(server, kCancelledMinTime) == 2 && test::metric_of(server, kBusy) == 0 &&
           test::metric_of(server, kBackgroundQueue) == 0;
  })) << server.log();
  EXPECT_EQ(test::metric_of(server, "slosh_min_time_searches_total"), 1);
  EXPECT_EQ(test::metric_of(server, R"(slosh_solve_seconds_count{strategy="min_time:notch"})"), -1);
  EXPECT_EQ(
      test::metric_of(server, R"(slosh_solve_seconds_count{strategy="min_time:time_domain"})"), 1);
}

// A client that half-closes right after its request (as `nc -N` does) is treated as gone: the HTTP
// library writes nothing to a socket whose peer has sent its FIN. What the service says about such
// a reply must be true: either the reply arrived in full, or the access log and the request
// counter say 499 (never 200 with the bytes of a body that was not sent).
TEST(HttpHalfClose, AReplyToAHalfClosedClientIsLoggedAsWhatWasSent) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  constexpr int kClients = 10;
  int answered = 0;
  for (int i = 0; i < kClients; ++i) {
    const std::string id = "half-close-" + std::to_string(i);
    test::Raw raw(server.port());
    ASSERT_TRUE(raw.send("GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\nX-Request-Id: " +
                         id + "\r\n\r\n"));
    raw.half_close();
    const std::string reply = raw.read_all();
    ASSERT_TRUE(
        test::wait_until([&] { return server.log().find("id=" + id + " ") != std::string::npos; }));
    const std::string log = server.log();
    const auto at = log.find("id=" + id + " ");
    const std::string line = log.substr(at, log.find('\n', at) - at);
    if (reply.substr(0, 12) == "HTTP/1.1 200") {
      ++answered;
      EXPECT_NE(line.find(" status=200 "), std::string::npos) << line;
    } else {
      EXPECT_EQ(reply, "");
      EXPECT_NE(line.find(" status=499 "), std::string::npos) << line;
      EXPECT_NE(line.find(" bytes=0 "), std::string::npos) << line;
    }
  }
  EXPECT_EQ(test::metric_of(server, R"(slosh_http_requests_total{route="/healthz",status="200"})"),
            answered == 0 ? -1 : answered);
  const double unwritten =
      test::metric_of(server, R"(slosh_http_requests_total{route="/healthz",status="499"})");
  EXPECT_EQ(unwritten == -1 ? 0 : unwritten, kClients - answered);
}

}  // namespace test_serve_honesty
}  // namespace slosh
