// Two real `slosh serve` replicas behind the real nginx (Debian nginx-light) on loopback, with the
// deployed config (deploy/nginx.conf, rewritten by support/proxy.hpp): requests through the proxy
// reach both replicas (X-Slosh-Replica and each replica's own /metrics), the probes answer
// through it, request ids pass both ways, a large download arrives whole, and killing one replica
// leaves the proxy answering from the other until it is back.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <string>

#include "support/prom_text.hpp"
#include "support/proxy.hpp"
#include "support/replicas.hpp"

namespace slosh {
namespace test_replicas {

using nlohmann::json;

std::string plan_text() {
  return json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "strategy": "baseline"})")
      .dump();
}

bool have_nginx() {
  return std::filesystem::exists(test::kNginx);
}

// GET /healthz observations of a replica, from its own /metrics, once they reach `expected`
// (a request is observed after its response is written, so nginx may have the answer first);
// the last value read after 5 s otherwise.
double healthz_seen(test::Replica& replica, double expected) {
  auto c = replica.client();
  double n = -1;
  for (int i = 0; i < 250 && n != expected; ++i) {
    if (i > 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto r = c.Get("/metrics");
    if (!r) continue;
    n = test::parse_prom_text(r->body).value("slosh_http_request_duration_seconds_count",
                                             {{"route", "/healthz"}, {"method", "GET"}});
    if (std::isnan(n)) n = 0.0;
  }
  return n;
}

TEST(Deploy, NginxConfigPassesNginxT) {
  if (!have_nginx()) {
    GTEST_SKIP() << "nginx not installed (Debian nginx-light)";
  }
  const test::TempDir dir;
  const std::string config = test::nginx_test_config(test::deployed_nginx_config(), {18081, 18082},
                                                     18080, (dir / "").string());
  EXPECT_NE(config.find("server 127.0.0.1:18081 max_fails=1 fail_timeout=5s;"), std::string::npos);
  EXPECT_EQ(config.find("slosh-1:8080"), std::string::npos);
  EXPECT_NE(config.find("listen 127.0.0.1:18080;"), std::string::npos);
  const test::RunResult t = test::nginx_check(config, dir);
  EXPECT_EQ(t.exit_code, 0) << t.out << config;
  const test::RunResult broken = test::nginx_check(config + "\nnot_a_directive;\n", dir);
  EXPECT_NE(broken.exit_code, 0);
}

TEST(Replicas, ProxyReachesBothAndAnswersWhenOneIsKilled) {
  if (!have_nginx()) {
    GTEST_SKIP() << "nginx not installed (Debian nginx-light)";
  }
  test::ReplicaSet replicas(2, {"--workers", "1"}, "line");
  test::NginxProxy proxy(replicas.ports());
  auto client = proxy.client();

  // Round robin over keep-alive connections: both replicas answer, each counts its own.
  std::map<std::string, int> answered;
  for (int i = 0; i < 20; ++i) {
    const auto r = client.Get("/healthz");
    ASSERT_TRUE(r && r->status == 200) << proxy.log();
    ++answered[r->get_header_value("X-Slosh-Replica")];
  }
  EXPECT_EQ(answered.size(), 2u);
  EXPECT_GT(answered["line-1"], 0);
  EXPECT_GT(answered["line-2"], 0);
  EXPECT_EQ(healthz_seen(replicas[0], answered["line-1"]), answered["line-1"]);
  EXPECT_EQ(healthz_seen(replicas[1], answered["line-2"]), answered["line-2"]);

  const auto ready = client.Get("/readyz");
  ASSERT_TRUE(ready && ready->status == 200);
  EXPECT_EQ(json::parse(ready->body).at("status"), "ready");

  // The client's request id reaches the replica (which echoes it); without one, nginx's.
  const auto traced = client.Get("/healthz", {{"X-Request-Id", "trace-42"}});
  EXPECT_EQ(traced->get_header_value("X-Request-Id"), "trace-42");
  const auto untraced = client.Get("/healthz");
  EXPECT_TRUE(
      std::regex_match(untraced->get_header_value("X-Request-Id"), std::regex("[0-9a-f]{32}")));

  // A plan on both replicas, then its cam table (about 1 MB at 0.1 ms) through the proxy: whole
  // and identical to the replica's own answer.
  std::string key;
  for (std::size_t i = 0; i < 2; ++i) {
    auto direct = replicas[i].client();
    const auto r = direct.Post("/v1/plans", plan_text(), "application/json");
    ASSERT_TRUE(r && r->status == 200);
    key = json::parse(r->body).at("key");
  }
  auto direct = replicas[0].client();
  const auto expected = direct.Get("/v1/plans/" + key + "/cam.csv?period_ms=0.1");
  ASSERT_TRUE(expected && expected->status == 200);
  ASSERT_GT(expected->body.size(), 100000u);
  for (int i = 0; i < 2; ++i) {
    const auto table = client.Get("/v1/plans/" + key + "/cam.csv?period_ms=0.1");
    ASSERT_TRUE(table && table->status == 200);
    EXPECT_EQ(table->body, expected->body);
  }

  // One replica crashes: every request (GET and the POST of a plan) is answered by the other.
  ASSERT_EQ(replicas[0].kill(SIGKILL), 128 + SIGKILL);
  for (int i = 0; i < 10; ++i) {
    const auto health = client.Get("/healthz");
    ASSERT_TRUE(health && health->status == 200) << proxy.log();
    EXPECT_EQ(health->get_header_value("X-Slosh-Replica"), "line-2");
    const auto plan = client.Post("/v1/plans", plan_text(), "application/json");
    ASSERT_TRUE(plan && plan->status == 200) << proxy.log();
    EXPECT_EQ(plan->get_header_value("X-Slosh-Replica"), "line-2");
    EXPECT_EQ(json::parse(plan->body).at("key"), key);
  }
  const auto still_ready = client.Get("/readyz");
  ASSERT_TRUE(still_ready && still_ready->status == 200);

  // Back on its port: nginx returns to it once its fail_timeout (5 s) has passed.
  replicas[0].start();
  std::set<std::string> seen;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (seen.size() < 2 && std::chrono::steady_clock::now() < deadline) {
    const auto r = client.Get("/healthz");
    ASSERT_TRUE(r && r->status == 200);
    seen.insert(r->get_header_value("X-Slosh-Replica"));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(seen, (std::set<std::string>{"line-1", "line-2"}));
}

}  // namespace test_replicas
}  // namespace slosh
