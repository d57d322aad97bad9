// SPEC §7 "Hardening": what an attacker or an unlucky client did to `slosh serve`,
// each replayed against the real server on loopback. Every test here failed (hung, crashed or
// answered wrongly) before the fix it names.

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <future>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/simulate.hpp"
#include "support/process.hpp"
#include "support/raw_client.hpp"
#include "support/sanitizers.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_hardening {

using nlohmann::json;
using test::read_file;
using test::Server;
using test::TempDir;
using test::write_file;
using Clock = std::chrono::steady_clock;

json plan_body(const std::string& strategy, double stroke_mm = 800) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}})");
  body["strategy"] = strategy;
  body["format"]["stroke_mm"] = stroke_mm;
  return body;
}

json parse(const std::string& text) {
  try {
    return json::parse(text);
  } catch (const json::exception&) {
    ADD_FAILURE() << "not JSON: " << text.substr(0, 300);
  }
  return json::object();
}

using test::Raw;

long rss_kib(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

httplib::Result post(httplib::Client& c, const std::string& path, const json& body) {
  return c.Post(path.c_str(), body.dump(), "application/json");
}

// Item 1: a batch with more uncached items than workers + queue used to deadlock the service
// (the batch held the single-flight lock while waiting for queue room, which finishing tasks
// need), and every later solve and /healthz with it.
TEST(Hardening, BatchLargerThanTheQueueCompletesAndTheServiceStaysUp) {
  Server server({"--workers", "2", "--queue", "4"});
  httplib::Client c = server.client();
  c.set_read_timeout(120, 0);
  json batch{{"requests", json::array()}};
  for (int i = 0; i < 30; ++i) batch["requests"].push_back(plan_body("multi_notch", 300 + i));
  const auto r = post(c, "/v1/plans/batch", batch);
  ASSERT_TRUE(r) << httplib::to_string(r.error());
  ASSERT_EQ(r->status, 200) << r->body.substr(0, 300);
  const json out = parse(r->body);
  ASSERT_EQ(out["results"].size(), 30u);
  for (const json& item : out["results"]) EXPECT_TRUE(item.contains("plan")) << item.dump();
  // A new solve and the health check still answer.
  const auto single = post(c, "/v1/plans", plan_body("multi_notch", 999));
  ASSERT_TRUE(single);
  EXPECT_EQ(single->status, 200);
  const auto health = c.Get("/healthz");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
}

// Item 2: concurrent Ipopt solves corrupted MUMPS' global state and killed the process.
TEST(Hardening, ConcurrentIpoptPlansAndAnIpoptBatchDoNotCrash) {
  Server server({"--workers", "4"});
  std::vector<std::future<int>> plans;
  for (int i = 0; i < 4; ++i) {
    plans.push_back(std::async(std::launch::async, [&server, i] {
      httplib::Client c = server.client();
      json body = plan_body("multi_notch", 600 + i);
      body["options"] = {{"solver", "ipopt"}};
      const auto r = post(c, "/v1/plans", body);
      return r ? r->status : -1;
    }));
  }
  json batch{{"requests", json::array()}};
  for (int i = 0; i < 4; ++i) {
    json body = plan_body("min_jerk_band", 700 + i);
    body["options"] = {{"solver", "ipopt"}};
    batch["requests"].push_back(body);
  }
  httplib::Client c = server.client();
  const auto r = post(c, "/v1/plans/batch", batch);
  for (auto& p : plans) EXPECT_EQ(p.get(), 200);
  ASSERT_TRUE(r) << httplib::to_string(r.error());
  EXPECT_EQ(r->status, 200);
  const json results =
      parse(r->body)["results"];  // (a temporary's member would dangle in the loop)
  for (const json& item : results) {
    EXPECT_TRUE(item.contains("plan")) << item.dump().substr(0, 300);
  }
  EXPECT_FALSE(server.child().wait_for(std::chrono::milliseconds(0)).has_value())
      << "the server exited:\n"
      << server.log();
}

// Item 3: 70 000 nested arrays (131 kB) overflowed the stack of the service and of the CLI.
TEST(Hardening, DeepNestingIsA400NotACrash) {
  const std::string deep = std::string(70000, '[') + std::string(70000, ']');
  const std::string expected =
      R"({"error":{"code":"malformed_json","field":null,"message":"the body nests arrays and objects deeper than the limit of 64 levels"}})";
  Server server;
  httplib::Client c = server.client();
  for (const char* path : {"/v1/plans", "/v1/simulate", "/v1/plans/batch"}) {
    const auto r = c.Post(path, deep, "application/json");
    ASSERT_TRUE(r) << path << ": " << httplib::to_string(r.error());
    EXPECT_EQ(r->status, 400) << path;
    EXPECT_EQ(r->body, expected) << path;
  }
  // Inside a batch item and inside a field: the same limit on the whole body.
  const std::string in_batch = R"({"requests": [)" + deep + "]}";
  const auto b = c.Post("/v1/plans/batch", in_batch, "application/json");
  ASSERT_TRUE(b);
  EXPECT_EQ(b->status, 400);
  // 64 levels are fine (the parser and the message preview both handle them).
  json nested = json::array();
  for (int i = 0; i < 61; ++i) nested = json::array({nested});  // 2 + 62 levels
  json body = plan_body("baseline");
  body["format"]["fluid"] = nested;
  const auto ok = post(c, "/v1/plans", body);
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 422);
  EXPECT_EQ(parse(ok->body)["error"]["field"], "format.fluid");

  const test::RunResult cli = test::run_slosh({"plan", "--request", "-"}, deep);
  EXPECT_EQ(cli.exit_code, 2) << cli.err;
  EXPECT_EQ(parse(cli.err), parse(expected));
}

// Item 4: a chunked body was read whole whatever its size (878 MiB of RSS for a 32 MiB one).
TEST(Hardening, ChunkedBodiesHoldTheBodyLimit) {
  if (test::product_sanitized()) {
    // AddressSanitizer keeps freed blocks in a quarantine of up to 256 MiB, so every 64 KiB chunk
    // the server read and dropped would stay resident: a small quarantine keeps RSS the measure
    // of what the server holds.
    const char* asan = std::getenv("ASAN_OPTIONS");
    const std::string options = std::string(asan != nullptr ? asan : "") + ":quarantine_size_mb=4";
    ::setenv("ASAN_OPTIONS", options.c_str(), 1);
  }
  Server server({"--workers", "1"});
  const long before = rss_kib(server.child().pid());
  Raw raw(server.port());
  ASSERT_TRUE(raw.connected());
  raw.send(
      "POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
      "Transfer-Encoding: chunked\r\n\r\n");
  const std::string chunk = "10000\r\n" + std::string(0x10000, ' ') + "\r\n";
  std::size_t sent = 0;
  while (sent < (std::size_t{16} << 20) && raw.send(chunk)) sent += 0x10000;
  const std::string answer = raw.read_all();
  EXPECT_EQ(answer.rfind("HTTP/1.1 413", 0), 0u) << answer.substr(0, 200);
  EXPECT_NE(answer.find(R"("message":"the body is larger than the limit of 1048576 bytes )"
                        R"((max_body_bytes); a trajectory of more samples than a body holds )"
                        R"((about 30 000 t, x, y samples in 1 MiB) is simulated from a CSV file )"
                        R"(by slosh simulate --trajectory, up to 200000 samples")"),
            std::string::npos)
      << answer;
  const long after = rss_kib(server.child().pid());
  EXPECT_LT(after - before, 64 * 1024) << "RSS grew from " << before << " to " << after << " KiB";
}

// Item 4: a 9 000-byte JSON sent with curl's default form type got a 413 that blamed the 1 MiB
// limit (the HTTP library's own 8 KiB cap of form bodies).
TEST(Hardening, FormBodiesGetA415NamingJson) {
  Server server;
  httplib::Client c = server.client();
  json body = plan_body("baseline");
  body["padding"] = std::string(9000, 'x');
  const auto r = c.Post("/v1/plans", body.dump(), "application/x-www-form-urlencoded");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 415);
  EXPECT_EQ(parse(r->body)["error"]["message"],
            "the body is declared as 'application/x-www-form-urlencoded'; send the JSON request "
            "with Content-Type: application/json");
  // JSON with a charset, a +json type and no type at all are read.
  for (const char* type : {"application/json; charset=utf-8", "application/problem+json"}) {
    const auto ok = c.Post("/v1/plans", plan_body("baseline").dump(), type);
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok->status, 200) << type << ": " << ok->body.substr(0, 200);
  }
  Raw raw(server.port());
  const std::string untyped = plan_body("baseline").dump();
  raw.send("POST /v1/plans HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Length: " +
           std::to_string(untyped.size()) + "\r\n\r\n" + untyped);
  const std::string answer = raw.read_all();
  EXPECT_EQ(answer.rfind("HTTP/1.1 200", 0), 0u) << answer.substr(0, 300);
}

// A client that trickles one header byte every second.
void trickle(int port, const std::atomic<bool>& stop) {
  Raw raw(port);
  const std::string line = "GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow: " + std::string(1000, 'a');
  for (char ch : line) {
    if (stop || !raw.send(std::string(1, ch))) return;
    for (int i = 0; i < 10 && !stop; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

// Item 5: 8 trickling or idle connections (= the 8 HTTP threads) made /healthz time out; 4
// trickling clients delayed SIGTERM beyond 40 s.
TEST(Hardening, SlowAndIdleClientsStarveNobodyAndShutdownIsBounded) {
  const TempDir dir;
  write_file(dir / "fast.json", R"({"request_timeout_s": 3, "keep_alive_timeout_s": 2})");
  Server server({"--config", (dir / "fast.json").string()});
  std::atomic<bool> stop{false};
  std::vector<std::thread> tricklers;
  for (int i = 0; i < 64; ++i) tricklers.emplace_back(trickle, server.port(), std::cref(stop));
  std::vector<std::unique_ptr<httplib::Client>> idle;
  for (int i = 0; i < 16; ++i) {
    idle.push_back(std::make_unique<httplib::Client>("127.0.0.1", server.port()));
    idle.back()->set_keep_alive(true);
    ASSERT_TRUE(idle.back()->Get("/healthz"));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  httplib::Client probe = server.client();
  probe.set_read_timeout(2, 0);
  for (int i = 0; i < 5; ++i) {
    const auto r = probe.Get("/healthz");
    ASSERT_TRUE(r) << "attempt " << i << ": " << httplib::to_string(r.error());
    EXPECT_EQ(r->status, 200);
  }
  // 32 concurrent clients on a cached plan are all served.
  ASSERT_TRUE(post(probe, "/v1/plans", plan_body("baseline")));
  std::vector<std::future<int>> clients;
  for (int i = 0; i < 32; ++i) {
    clients.push_back(std::async(std::launch::async, [&server] {
      httplib::Client c = server.client();
      c.set_read_timeout(2, 0);
      int ok = 0;
      for (int k = 0; k < 20; ++k) {
        const auto r = post(c, "/v1/plans", plan_body("baseline"));
        ok += r && r->status == 200 ? 1 : 0;
        if (!r || r->status != 200) {
          ADD_FAILURE() << "request " << k << ": "
                        << (r ? std::to_string(r->status) + " " + r->body.substr(0, 200)
                              : httplib::to_string(r.error()));
        }
      }
      return ok;
    }));
  }
  for (auto& f : clients) EXPECT_EQ(f.get(), 20) << server.log().substr(0, 3000);
  // The trickling connections are closed by the request timeout (2 s keep-alive + 3 s).
  std::this_thread::sleep_for(std::chrono::seconds(6));
  EXPECT_NE(server.log().find("no complete request within 5 s: connection closed"),
            std::string::npos)
      << server.log().substr(0, 2000);
  // SIGTERM with trickling clients connected: a bounded shutdown.
  std::atomic<bool> stop_late{false};
  std::vector<std::thread> late;
  for (int i = 0; i < 4; ++i) late.emplace_back(trickle, server.port(), std::cref(stop_late));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const auto t0 = Clock::now();
  const std::optional<int> code = server.stop();
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  stop = true;
  stop_late = true;
  for (auto& t : tricklers) t.join();
  for (auto& t : late) t.join();
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0);
  EXPECT_LT(seconds, 10.0);
}

// Item 6: a 232-byte request returned 15 MB of series and cached them in memory and SQLite.
TEST(Hardening, SeriesAreCappedAndNeverCached) {
  Server server;
  httplib::Client c = server.client();
  json body = plan_body("baseline");
  body["options"] = {{"rest_time_s", 30}};
  body["sample_period_s"] = 1e-4;
  const auto r = post(c, "/v1/plans", body);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 422);
  EXPECT_EQ(parse(r->body)["error"]["field"], "sample_period_s");
  // The largest series allowed is returned, and the cache holds the plan without it.
  body["options"]["rest_time_s"] = 3.9;  // 4.9 s at 0.1 ms: 49 001 samples
  const auto big = post(c, "/v1/plans", body);
  ASSERT_TRUE(big);
  ASSERT_EQ(big->status, 200);
  EXPECT_EQ(parse(big->body)["series"]["t_s"].size(), 49001u);
  const std::string key = parse(big->body)["key"];
  const auto cached = c.Get(("/v1/plans/" + key).c_str());
  ASSERT_TRUE(cached);
  EXPECT_FALSE(parse(cached->body).contains("series"));
  EXPECT_LT(cached->body.size(), big->body.size() / 20);
}

// Item 7: the same recipe with sample_period_s 0.05, none, 0.001 returned the first caller's 41
// samples each time, under one ETag.
TEST(Hardening, TheCachedAnswerIsWhatThisRequestAskedFor) {
  Server server;
  httplib::Client c = server.client();
  std::vector<std::string> etags;
  for (const json& period : {json(0.05), json(nullptr), json(0.001), json(0.05)}) {
    json body = plan_body("multi_notch");
    body["sample_period_s"] = period;
    const auto r = post(c, "/v1/plans", body);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200);
    const json plan = parse(r->body);
    if (period.is_null()) {
      EXPECT_FALSE(plan.contains("series"));
    } else {
      const double dt = period.get<double>();
      ASSERT_TRUE(plan.contains("series"));
      EXPECT_EQ(plan["series"]["t_s"].size(), static_cast<std::size_t>(2.0 / dt + 1.5));
      EXPECT_DOUBLE_EQ(plan["series"]["t_s"][1].get<double>(), dt);
    }
    etags.push_back(r->get_header_value("ETag"));
  }
  EXPECT_NE(etags[0], etags[1]);
  EXPECT_NE(etags[1], etags[2]);
  EXPECT_NE(etags[0], etags[2]);
  EXPECT_EQ(etags[0], etags[3]);
  // A conditional request with the ETag of another body is answered in full.
  httplib::Headers inm{{"If-None-Match", etags[1]}};
  json with_series = plan_body("multi_notch");
  with_series["sample_period_s"] = 0.05;
  const auto r = c.Post("/v1/plans", inm, with_series.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  httplib::Headers same{{"If-None-Match", etags[0]}};
  const auto not_modified = c.Post("/v1/plans", same, with_series.dump(), "application/json");
  ASSERT_TRUE(not_modified);
  EXPECT_EQ(not_modified->status, 304);
}

// Item 8 (the request side): in-range-looking input that gave a 500 or null numbers.
TEST(Hardening, DegenerateNumbersAreRejectedNamingTheField) {
  Server server;
  httplib::Client c = server.client();
  json stroke = plan_body("baseline");
  stroke["format"]["stroke_mm"] = 5e-324;
  const auto r = post(c, "/v1/plans", stroke);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 422);
  EXPECT_EQ(parse(r->body)["error"]["field"], "format.stroke_mm");
  json fill = plan_body("baseline");
  fill["format"]["fill_height_mm"] = 0.05;
  const auto f = post(c, "/v1/plans", fill);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->status, 422);
  EXPECT_EQ(parse(f->body)["error"]["field"], "format.fill_height_mm");
  // A harmonic of 1e-200 rad/s integrates to NaN: it passed the rest check and gave null series.
  json sim = json::parse(R"({"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82,
      "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "law": {"type": "piecewise", "pieces": [{"t_begin_s": 0, "t_end_s": 1, "a_poly": [0],
              "harmonic": {"cos": 0, "sin": 1, "omega_rad_s": 1e-200}}]},
      "sample_period_s": 0.01})");
  const auto s = post(c, "/v1/simulate", sim);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->status, 422);
  EXPECT_EQ(parse(s->body)["error"]["message"],
            "law.pieces[0].harmonic.omega_rad_s = 1e-200 is out of range: allowed 0 (no "
            "harmonic) or 0.001 to 1e+09 rad/s");
}

// Item 9: a second instance on a busy port started silently and took half of the connections.
TEST(Hardening, ASecondServerOnABusyPortFailsToStart) {
  Server first;
  const TempDir dir;
  write_file(dir / "stdin", "");
  test::Child second(
      test::spawn({"serve", "--host", "127.0.0.1", "--port", std::to_string(first.port()),
                   "--cache", (dir / "other.sqlite").string()},
                  dir / "stdin", dir / "stdout", dir / "stderr"));
  const std::optional<int> code = second.wait_for(std::chrono::seconds(10));
  ASSERT_TRUE(code.has_value()) << "the second server started on a busy port";
  EXPECT_EQ(*code, 1);
  const std::string log = read_file(dir / "stdout") + read_file(dir / "stderr");
  EXPECT_NE(log.find("cannot bind 127.0.0.1:" + std::to_string(first.port())), std::string::npos)
      << log;
}

// Item 10: framework answers in the envelope with their own codes; 405 with Allow; the caller's
// request id kept; X-Cache only where a cache was asked.
TEST(Hardening, FrameworkAnswersAreHonest) {
  Server server;
  httplib::Client c = server.client();
  const auto get_plans = c.Get("/v1/plans");
  ASSERT_TRUE(get_plans);
  EXPECT_EQ(get_plans->status, 405);
  EXPECT_EQ(get_plans->get_header_value("Allow"), "POST");
  EXPECT_EQ(parse(get_plans->body)["error"]["code"], "method_not_allowed");
  const auto post_health = c.Post("/healthz", "{}", "application/json");
  ASSERT_TRUE(post_health);
  EXPECT_EQ(post_health->status, 405);
  EXPECT_EQ(post_health->get_header_value("Allow"), "GET, HEAD");
  const auto missing = c.Get("/nowhere");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  EXPECT_EQ(parse(missing->body)["error"]["code"], "not_found");

  const auto long_uri = c.Get(("/" + std::string(9000, 'a')).c_str());
  ASSERT_TRUE(long_uri);
  EXPECT_EQ(long_uri->status, 414);
  EXPECT_EQ(parse(long_uri->body)["error"]["code"], "uri_too_long");

  Raw raw(server.port());
  raw.send("FOO /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  const std::string foo = raw.read_all();
  EXPECT_EQ(foo.rfind("HTTP/1.1 501", 0), 0u) << foo;
  EXPECT_NE(foo.find(R"("code":"not_implemented")"), std::string::npos) << foo;

  const auto bad_range = c.Get("/healthz", {{"Range", "bytes=zzz"}});
  ASSERT_TRUE(bad_range);
  EXPECT_EQ(bad_range->status, 416);
  EXPECT_EQ(parse(bad_range->body)["error"]["code"], "range_not_satisfiable");
  const auto range = c.Get("/healthz", {{"Range", "bytes=100000-"}});
  ASSERT_TRUE(range);
  EXPECT_EQ(range->status, 200);  // whole bodies only
  EXPECT_EQ(parse(range->body)["status"], "ok");

  const auto id = c.Get("/healthz", {{"X-Request-Id", "line-7/hmi-42"}});
  ASSERT_TRUE(id);
  EXPECT_EQ(id->get_header_value("X-Request-Id"), "line-7/hmi-42");
  const auto generated = c.Get("/healthz", {{"X-Request-Id", std::string(300, 'x')}});
  ASSERT_TRUE(generated);
  EXPECT_FALSE(generated->get_header_value("X-Request-Id").empty());
  EXPECT_NE(generated->get_header_value("X-Request-Id"), std::string(300, 'x'));

  for (const char* path : {"/healthz", "/metrics", "/readyz", "/v1/fluids"}) {
    const auto r = c.Get(path);
    ASSERT_TRUE(r);
    EXPECT_FALSE(r->has_header("X-Cache")) << path;
  }
}

// Item 10: cache misses counted 404s of GET /v1/plans/{key} and single-flight joiners.
TEST(Hardening, CacheMissesCountSolvesOnly) {
  Server server({"--workers", "2"});
  httplib::Client c = server.client();
  ASSERT_TRUE(c.Get("/v1/plans/0123456789abcdef0123456789abcdef"));
  std::vector<std::future<int>> same;
  for (int i = 0; i < 6; ++i) {
    same.push_back(std::async(std::launch::async, [&server] {
      httplib::Client k = server.client();
      const auto r = post(k, "/v1/plans", plan_body("time_domain", 777));
      return r ? r->status : -1;
    }));
  }
  for (auto& f : same) EXPECT_EQ(f.get(), 200);
  const auto metrics = c.Get("/metrics");
  ASSERT_TRUE(metrics);
  const std::string& text = metrics->body;
  auto value = [&text](const std::string& name) {
    const auto at = text.find("\n" + name + " ");
    return at == std::string::npos ? -1.0 : std::stod(text.substr(at + name.size() + 2));
  };
  EXPECT_EQ(value("slosh_cache_misses_total"), 1.0);
  EXPECT_EQ(
      value(R"(slosh_cache_hits_total{level="memory"})") + value("slosh_singleflight_joins_total"),
      5.0);
}

// Item 10: the start-up line reported "workers 0" (the setting) while /readyz said 2.
TEST(Hardening, TheLogNamesTheWorkersThatRun) {
  Server server;
  httplib::Client c = server.client();
  const auto ready = c.Get("/readyz");
  ASSERT_TRUE(ready);
  const int workers = parse(ready->body)["workers"];
  EXPECT_GE(workers, 1);
  EXPECT_NE(server.log().find("(workers " + std::to_string(workers) + ","), std::string::npos)
      << server.log();
}

// Item 10: a plan store that cannot be written is logged and said in /readyz ("degraded", still
// 200: the service answers correctly, from memory) and in a metric to alert on.
TEST(Hardening, AnUnwritableStoreIsLoggedAndSaidInReadyz) {
  const TempDir dir;
  write_file(dir / "plans.sqlite", std::string(4096, 'x'));  // the fixture's cache file
  Server server({}, &dir);
  httplib::Client c = server.client();
  const auto ready = c.Get("/readyz");
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->status, 200);
  const json body = parse(ready->body);
  EXPECT_EQ(body["status"], "degraded");
  const auto metrics = c.Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_NE(metrics->body.find("\nslosh_cache_store_ok 0\n"), std::string::npos);
  EXPECT_NE(body["reason"].get<std::string>().find("file is not a database"), std::string::npos);
  const auto plan = post(c, "/v1/plans", plan_body("baseline"));
  ASSERT_TRUE(plan);
  EXPECT_EQ(plan->status, 200);
  EXPECT_NE(server.log().find("file is not a database"), std::string::npos);
}

// Found by the fuzzer: a NUL in an unknown key cut the message short (what() is a C string).
TEST(Hardening, ANulInAKeyIsQuotedNotTruncating) {
  try {
    (void)api::parse_simulate_request(api::parse_json_body(R"({"\u0000":1})"));
    ADD_FAILURE() << "accepted";
  } catch (const api::ApiError& e) {
    EXPECT_EQ(std::string(e.what()),
              "\\u0000 is not a known field; allowed here: format, law, rest_time_s, "
              "sample_period_s, options");
    EXPECT_EQ(e.field(), std::string(1, '\0'));
  }
}

// Found by the fuzzer: breakpoints 5e-324 s apart made the slope infinite and the law NaN.
TEST(Hardening, BreakpointsAtLeastOneNanosecondApart) {
  const json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1},
      "law": {"type": "piecewise_linear", "breakpoints_s": [0, 5e-324, 1e-323, 1],
              "acceleration_m_s2": [0, 1, 0, 0]}})");
  try {
    (void)api::parse_simulate_request(body);
    ADD_FAILURE() << "accepted";
  } catch (const api::ApiError& e) {
    EXPECT_EQ(e.field(), "law.breakpoints_s[1]");
    EXPECT_EQ(std::string(e.what()).rfind("law.breakpoints_s[1] = 4.940656458e-324 is out of "
                                          "range: allowed 1e-09 to ",
                                          0),
              0u)
        << e.what();
  }
}

// Regression: a POST without Content-Length held a thread for the read timeout (the library
// read "until close") before a 400.
TEST(Hardening, APostWithoutALengthHasAnEmptyBody) {
  Server server;
  Raw raw(server.port());
  const auto t0 = Clock::now();
  raw.send(
      "POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
      "Connection: close\r\n\r\n");
  const std::string answer = raw.read_all();
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 2.0);
  EXPECT_EQ(answer.rfind("HTTP/1.1 400", 0), 0u) << answer;
  EXPECT_NE(answer.find(R"("code":"malformed_json")"), std::string::npos) << answer;
}

// Regression: multipart bodies gave 500 bad_function_call (uncounted in the metrics);
// "Expect: 100-continue" with an oversized length got "100 Continue".
TEST(Hardening, MultipartAndOversizedExpectationsAreRefusedUpFront) {
  Server server;
  httplib::Client c = server.client();
  const httplib::MultipartFormDataItems items{{"x", plan_body("baseline").dump(), "x.json", ""}};
  const auto r = c.Post("/v1/plans", items);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 415);
  EXPECT_EQ(parse(r->body)["error"]["code"], "unsupported_media_type");
  Raw raw(server.port());
  raw.send(
      "POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
      "Content-Length: 5000000\r\nExpect: 100-continue\r\n\r\n");
  const std::string answer = raw.read_all();
  EXPECT_EQ(answer.rfind("HTTP/1.1 413", 0), 0u) << answer.substr(0, 200);
  EXPECT_NE(answer.find("the body is larger than the limit of 1048576 bytes"), std::string::npos);
  const auto metrics = c.Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_NE(metrics->body.find(R"(slosh_http_requests_total{route="/v1/plans",status="415"} 1)"),
            std::string::npos)
      << metrics->body;
}

// Regression: GET /v1/plans/batch looked up a plan "batch"; TRACE got a 400; a weak or "*"
// If-None-Match was not honoured.
TEST(Hardening, MoreHonestFrameworkAnswers) {
  Server server;
  httplib::Client c = server.client();
  const auto batch = c.Get("/v1/plans/batch");
  ASSERT_TRUE(batch);
  EXPECT_EQ(batch->status, 405);
  EXPECT_EQ(batch->get_header_value("Allow"), "POST");
  Raw raw(server.port());
  raw.send("TRACE /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  const std::string trace = raw.read_all();
  EXPECT_EQ(trace.rfind("HTTP/1.1 501", 0), 0u) << trace;
  const auto first = post(c, "/v1/plans", plan_body("baseline"));
  ASSERT_TRUE(first);
  const std::string tag = first->get_header_value("ETag");
  for (const std::string& inm : {"W/" + tag, std::string("*"), "\"other\", " + tag}) {
    const auto r = c.Post("/v1/plans", {{"If-None-Match", inm}}, plan_body("baseline").dump(),
                          "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 304) << inm;
  }
}

// Regression: a cached plan echoed the first client's fluid name to the next one.
TEST(Hardening, ACachedPlanEchoesThisRequestsFluidName) {
  Server server;
  httplib::Client c = server.client();
  json secret = plan_body("baseline");
  secret["format"]["fluid"] = {
      {"density_kg_m3", 1000}, {"viscosity_pa_s", 0.001}, {"name", "Customer X syrup"}};
  json plain = plan_body("baseline");
  plain["format"]["fluid"] = {{"density_kg_m3", 1000}, {"viscosity_pa_s", 0.001}};
  const auto a = post(c, "/v1/plans", secret);
  const auto b = post(c, "/v1/plans", plain);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(parse(a->body)["format"]["fluid"]["name"], "Customer X syrup");
  EXPECT_EQ(parse(b->body)["format"]["fluid"]["name"], "custom");
  EXPECT_NE(parse(a->body)["key"], parse(b->body)["key"]);
}

// Regression: a request with a larger budget joined a running solve of the same recipe with
// a smaller one and got its time_limit answer.
TEST(Hardening, ALargerBudgetDoesNotJoinASmallerOne) {
  // The patient plan must finish within its budget: 20 times longer under the sanitizers, and the
  // server's own budget raised to allow it.
  const double patient_s = test::solve_budget(10);
  ::setenv("SLOSH_SOLVE_BUDGET_S", std::to_string(patient_s).c_str(), 1);
  Server server({"--workers", "2"});
  ::unsetenv("SLOSH_SOLVE_BUDGET_S");
  json hurried = plan_body("multi_notch", 613);
  hurried["options"] = {{"solver", "ipopt"}, {"time_limit_s", 0.3}};
  json patient = hurried;
  patient["options"]["time_limit_s"] = patient_s;
  auto first = std::async(std::launch::async, [&] {
    httplib::Client c = server.client();
    return post(c, "/v1/plans", hurried);
  });
  // The hurried plan must be solving before the patient one is sent: a slower build (the
  // sanitizers) may take longer than any fixed pause to start it, and a hurried plan arriving
  // second joins the patient flight, as a smaller budget may.
  ASSERT_TRUE(test::wait_until(
      [&] {
        return first.wait_for(std::chrono::seconds(0)) == std::future_status::ready ||
               test::metric_of(server, "slosh_busy_workers") >= 1;
      },
      std::chrono::seconds(30)));
  httplib::Client c = server.client();
  const auto second = post(c, "/v1/plans", patient);
  ASSERT_TRUE(second);
  EXPECT_NE(parse(second->body)["status"], "time_limit") << second->body.substr(0, 300);
  ASSERT_TRUE(first.get());
  const auto metrics = c.Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_NE(metrics->body.find("\nslosh_singleflight_joins_total 0\n"), std::string::npos);
}

// Regression: a batch whose client hung up went on queueing all its solves, and every other
// client got 503 meanwhile.
TEST(Hardening, AnAbandonedBatchStopsQueueing) {
  Server server({"--workers", "1", "--queue", "2"});
  json batch{{"requests", json::array()}};
  for (int i = 0; i < 200; ++i) batch["requests"].push_back(plan_body("time_domain", 300 + i));
  const std::string text = batch.dump();
  {
    Raw raw(server.port());
    raw.send(
        "POST /v1/plans/batch HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
        "Content-Length: " +
        std::to_string(text.size()) + "\r\n\r\n" + text);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }  // the client hangs up
  httplib::Client c = server.client();
  int status = 0;
  for (int attempt = 0; attempt < 40 && status != 200; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    const auto r = post(c, "/v1/plans", plan_body("baseline", 999));
    status = r ? r->status : -1;
  }
  EXPECT_EQ(status, 200) << "still refused 10 s after the batch's client left";
  const auto metrics = c.Get("/metrics");
  ASSERT_TRUE(metrics);
  const std::string& m = metrics->body;
  const std::string line = "slosh_solve_seconds_count{strategy=\"time_domain\"} ";
  const auto at = m.find(line);
  ASSERT_NE(at, std::string::npos);
  EXPECT_LT(std::stoi(m.substr(at + line.size())), 100);
}

// Regression: 1 000 copies of a large cached plan in a 189 kB batch made a 657 MB response.
TEST(Hardening, BatchResponsesAreBounded) {
  const TempDir dir;
  write_file(dir / "small.json", R"({"max_response_bytes": 1048576})");
  Server server({"--config", (dir / "small.json").string()});
  httplib::Client c = server.client();
  json batch{{"requests", json::array()}};
  for (int i = 0; i < 200; ++i) batch["requests"].push_back(plan_body("baseline"));
  const auto r = post(c, "/v1/plans/batch", batch);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 422);
  const json e = parse(r->body)["error"];
  EXPECT_EQ(e["field"], "requests");
  EXPECT_NE(e["message"].get<std::string>().find(
                "exceed the response limit of 1048576 bytes at requests["),
            std::string::npos)
      << e;
  batch["requests"] = json::array({plan_body("baseline"), plan_body("baseline")});
  const auto small = post(c, "/v1/plans/batch", batch);
  ASSERT_TRUE(small);
  EXPECT_EQ(small->status, 200);
}

// Regression: at SIGTERM every queued solve still ran (28 s with 6 Ipopt plans queued).
// The shutdown may wait for the solve already running, never for the queued ones: it has to end
// soon after the last plan that was answered 200, however slow one solve is (AddressSanitizer).
TEST(Hardening, ShutdownAnswersQueuedSolvesInsteadOfRunningThem) {
  Server server({"--workers", "1", "--queue", "8"});
  struct Answer {
    int status;
    Clock::time_point at;
  };
  std::vector<std::future<Answer>> plans;
  for (int i = 0; i < 6; ++i) {
    plans.push_back(std::async(std::launch::async, [&server, i] {
      httplib::Client c = server.client();
      c.set_read_timeout(300, 0);
      json body = plan_body("multi_notch", 640 + i);
      body["options"] = {{"solver", "ipopt"}};
      const auto r = post(c, "/v1/plans", body);
      return Answer{r ? r->status : -1, Clock::now()};
    }));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const auto t0 = Clock::now();
  const std::optional<int> code = server.stop();
  const auto stopped = Clock::now();
  int refused = 0;
  auto last_solved = t0;
  for (auto& p : plans) {
    const Answer a = p.get();
    refused += a.status == 503 ? 1 : 0;
    if (a.status == 200) last_solved = std::max(last_solved, a.at);
  }
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0);
  EXPECT_GE(refused, 3);
  EXPECT_LT(std::chrono::duration<double>(stopped - last_solved).count(), 3.0)
      << "the shutdown kept running after the last solve it answered";
}

// Found by the fuzzer: 100 m in 50 ms on a 1 mm container makes the nonlinear model diverge;
// the NaN became a 500 (the finite guard) instead of an answer the caller can act on.
TEST(Hardening, ADivergingModelIsA422NamingTheLaw) {
  const json body = json::parse(R"({"format": {"container": {"radius_mm": 1},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 100000, "motion_time_s": 0.05},
      "law": {"type": "seven_segment_uniform"}, "options": {"alpha": 2}})");
  try {
    (void)api::run_simulate(api::parse_simulate_request(body));
    ADD_FAILURE() << "answered";
  } catch (const api::ApiError& e) {
    EXPECT_EQ(e.status(), 422);
    EXPECT_EQ(e.field(), "law");
    EXPECT_EQ(std::string(e.what()),
              "the nonlinear sloshing model diverges for this law on this format (peak |a| = "
              "245000 m/s^2): the motion is outside what the model describes");
  }
}

// A plan the planner refuses as input (here: the uniform law already drives the nonlinear model
// out of its range) is a 422 naming the format, not a 200 "failed" with zero predictions.
TEST(Hardening, APlanOfAnInvalidFormatIsA422) {
  Server server;
  httplib::Client c = server.client();
  const json body = json::parse(R"({"format": {"container": {"radius_mm": 1},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 100000, "motion_time_s": 0.05},
      "strategy": "baseline", "options": {"alpha": 2, "min_ramp_s": 0.005}})");
  const auto r = post(c, "/v1/plans", body);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 422);
  const json e = parse(r->body)["error"];
  EXPECT_EQ(e["field"], "format");
  EXPECT_EQ(e["message"],
            "invalid input: the uniform law's predicted sloshing is not finite for this format; "
            "nothing was planned");
}

long vm_size_kib(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmSize:", 0) == 0) return std::stol(line.substr(7));
  }
  return -1;
}

// Regression: under `ulimit -v` the connection pool's std::thread threw std::system_error
// out of the HTTP library's accept loop and std::terminate aborted the server. Here the running
// server's address space is limited (prlimit, as `ulimit -v` would) to what it maps plus 4 MiB,
// less than a thread's stack: each connection is answered 503 with Retry-After by the pool's
// refusing thread, and once threads can be started again the server answers as before.
TEST(Hardening, AConnectionThatGetsNoThreadIsAnswered503AndTheServerLivesOn) {
  // AddressSanitizer's allocator aborts the process when the address space runs out (instead of
  // the std::bad_alloc / std::system_error the server handles): the limit would test the sanitizer.
  SLOSH_SKIP_WHEN_SANITIZED(
      "an address-space limit under AddressSanitizer aborts in its allocator");
  Server server({"--workers", "1"});
  ASSERT_GT(server.port(), 0) << server.log();
  const pid_t pid = server.child().pid();
  rlimit stack{};
  ASSERT_EQ(::prlimit(pid, RLIMIT_STACK, nullptr, &stack), 0);
  constexpr rlim_t kHeadroom = rlim_t{4} << 20;
  if (stack.rlim_cur != RLIM_INFINITY && stack.rlim_cur <= kHeadroom) {
    GTEST_SKIP() << "thread stacks of " << stack.rlim_cur << " bytes fit in the headroom";
  }
  rlimit before{};
  ASSERT_EQ(::prlimit(pid, RLIMIT_AS, nullptr, &before), 0);
  const long vm = vm_size_kib(pid);
  ASSERT_GT(vm, 0);
  const rlimit tight{static_cast<rlim_t>(vm) * 1024 + kHeadroom, before.rlim_max};
  ASSERT_EQ(::prlimit(pid, RLIMIT_AS, &tight, nullptr), 0);
  for (int i = 0; i < 3; ++i) {
    httplib::Client c = server.client();
    const auto r = c.Get("/healthz");
    ASSERT_TRUE(r) << httplib::to_string(r.error()) << "\n" << server.log();
    EXPECT_EQ(r->status, 503);
    EXPECT_EQ(r->get_header_value("Retry-After"), "1");
    EXPECT_EQ(r->get_header_value("Connection"), "close");
    EXPECT_EQ(parse(r->body),
              json::parse(R"({"error": {"code": "overloaded", "field": null, "message":
                "the service cannot start a thread for this connection (the system refused one): retry later"}})"));
  }
  ASSERT_EQ(::prlimit(pid, RLIMIT_AS, &before, nullptr), 0);
  httplib::Client c = server.client();
  const auto health = c.Get("/healthz");
  ASSERT_TRUE(health) << server.log();
  EXPECT_EQ(health->status, 200);
  const auto metrics = c.Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_EQ(
      test::metric(metrics->body, "slosh_http_requests_total{route=\"other\",status=\"503\"}"),
      3.0);
  EXPECT_NE(server.log().find("cannot start a connection thread (0 running)"), std::string::npos)
      << server.log();
  EXPECT_EQ(server.stop(), 0) << server.log();
}

}  // namespace test_hardening
}  // namespace slosh
