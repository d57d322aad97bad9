// GET /metrics of the real `slosh serve`: the exposition text parsed strictly (support/prom_text),
// counters that change exactly as requests are made (HTTP latency by route and method, plans by
// strategy and status, build info), the process_* metrics against /proc read by the test itself,
// and `promtool check metrics` (Debian prometheus) when it is installed.

#include <sys/resource.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "metrics/process_metrics.hpp"
#include "slosh/version.hpp"
#include "support/process.hpp"
#include "support/prom_text.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_metrics {

using nlohmann::json;
using test::PromText;
using test::Server;

json baseline_plan() {
  return json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "strategy": "baseline"})");
}

// Infeasible: a small shallow container moved far and fast with tight eta limits.
json infeasible_plan() {
  return json::parse(R"({"format": {"container": {"radius_mm": 10, "height_mm": 12},
      "fill_height_mm": 2.5, "fluid": "water", "stroke_mm": 900, "motion_time_s": 0.3},
      "options": {"eta_rest_max_mm": 0.001, "eta_motion_max_mm": 0.01, "limits": {"a_max": 30}},
      "strategy": "notch"})");
}

PromText scrape(httplib::Client& client) {
  const auto r = client.Get("/metrics");
  if (!r || r->status != 200) throw std::runtime_error("GET /metrics failed");
  return test::parse_prom_text(r->body);
}

// Observations of the latency histogram of `route` and `method` (0 when none yet).
double http_count(const PromText& m, const std::string& route, const std::string& method) {
  const double n =
      m.value("slosh_http_request_duration_seconds_count", {{"route", route}, {"method", method}});
  return std::isnan(n) ? 0.0 : n;
}

double plans(const PromText& m, const std::string& strategy, const std::string& status) {
  const double n = m.value("slosh_plans_total", {{"strategy", strategy}, {"status", status}});
  return std::isnan(n) ? 0.0 : n;
}

std::size_t fd_entries(const std::string& dir) {
  std::size_t n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    (void)entry;
    ++n;
  }
  return n;
}

TEST(PromText, RefusesMalformedExpositions) {
  EXPECT_NO_THROW(test::parse_prom_text("# HELP a_total A.\n# TYPE a_total counter\na_total 3\n"));
  EXPECT_ANY_THROW(test::parse_prom_text("a_total 3\n"));  // no TYPE
  EXPECT_ANY_THROW(test::parse_prom_text("# HELP a A.\n# TYPE a gauge\na 1\na 2\n"));
  EXPECT_ANY_THROW(test::parse_prom_text("# HELP a A.\n# TYPE a gauge\na{x=\"1} 1\n"));
  const std::string h = "# HELP h H.\n# TYPE h histogram\n";
  EXPECT_NO_THROW(test::parse_prom_text(
      h + "h_bucket{le=\"1\"} 1\nh_bucket{le=\"+Inf\"} 2\nh_sum 3\nh_count 2\n"));
  EXPECT_ANY_THROW(test::parse_prom_text(  // not cumulative
      h + "h_bucket{le=\"1\"} 3\nh_bucket{le=\"+Inf\"} 2\nh_sum 3\nh_count 2\n"));
  EXPECT_ANY_THROW(test::parse_prom_text(  // +Inf differs from the count
      h + "h_bucket{le=\"1\"} 1\nh_bucket{le=\"+Inf\"} 2\nh_sum 3\nh_count 3\n"));
  EXPECT_ANY_THROW(test::parse_prom_text(h + "h_bucket{le=\"1\"} 1\nh_sum 3\nh_count 1\n"));
}

TEST(Metrics, CountsChangeExactlyAsRequestsAreMade) {
  Server server({"--workers", "1"});
  auto client = server.client();
  // One keep-alive connection: each request is logged and observed before the next is read.
  client.set_keep_alive(true);
  const PromText before = scrape(client);
  EXPECT_EQ(before.types.at("slosh_http_request_duration_seconds"), "histogram");
  EXPECT_EQ(before.types.at("slosh_plans_total"), "counter");
  EXPECT_EQ(before.value("slosh_build_info", {{"version", kVersion}}), 1.0);

  const auto miss = client.Post("/v1/plans", baseline_plan().dump(), "application/json");
  ASSERT_TRUE(miss && miss->status == 200);
  const json plan = json::parse(miss->body);
  const auto hit = client.Post("/v1/plans", baseline_plan().dump(), "application/json");
  ASSERT_TRUE(hit && hit->status == 200);
  const auto by_key = client.Get("/v1/plans/" + plan.at("key").get<std::string>());
  ASSERT_TRUE(by_key && by_key->status == 200);
  const auto infeasible = client.Post("/v1/plans", infeasible_plan().dump(), "application/json");
  ASSERT_TRUE(infeasible && infeasible->status == 200);
  const std::string infeasible_status = json::parse(infeasible->body).at("status");
  ASSERT_EQ(infeasible_status, "infeasible");
  const auto invalid = client.Post("/v1/plans", "{}", "application/json");
  ASSERT_TRUE(invalid && invalid->status == 422);
  ASSERT_TRUE(client.Get("/nowhere"));
  ASSERT_TRUE(client.Get("/healthz"));

  const PromText after = scrape(client);
  EXPECT_EQ(
      plans(after, "baseline", plan.at("status")) - plans(before, "baseline", plan.at("status")),
      3.0);
  EXPECT_EQ(plans(after, "notch", "infeasible") - plans(before, "notch", "infeasible"), 1.0);
  EXPECT_EQ(http_count(after, "/v1/plans", "POST") - http_count(before, "/v1/plans", "POST"), 4.0);
  EXPECT_EQ(http_count(after, "/v1/plans/{key}", "GET"), 1.0);
  EXPECT_EQ(http_count(after, "other", "GET"), 1.0);
  EXPECT_EQ(http_count(after, "/healthz", "GET"), 1.0);
  // The scrape before is observed once its response has been written.
  EXPECT_EQ(http_count(after, "/metrics", "GET") - http_count(before, "/metrics", "GET"), 1.0);
  // The two solved POSTs lasted at least their solves: the latency sum bounds the solve sum.
  const double post_sum = after.value("slosh_http_request_duration_seconds_sum",
                                      {{"route", "/v1/plans"}, {"method", "POST"}});
  const double solve_sum = after.value("slosh_solve_seconds_sum", {{"strategy", "baseline"}}) +
                           after.value("slosh_solve_seconds_sum", {{"strategy", "notch"}});
  EXPECT_GE(post_sum, solve_sum);
}

TEST(Metrics, ProcessMetricsMatchProc) {
  Server server;
  auto client = server.client();
  // One keep-alive connection: each request is logged and observed before the next is read.
  client.set_keep_alive(true);
  const std::string fd_dir = "/proc/" + std::to_string(server.child().pid()) + "/fd";
  // The server's descriptors as the test lists them; a scrape between two equal listings must
  // report the same number (the test's one keep-alive connection is open throughout).
  bool matched = false;
  for (int attempt = 0; attempt < 5 && !matched; ++attempt) {
    const std::size_t listed = fd_entries(fd_dir);
    const PromText m = scrape(client);
    matched =
        listed == fd_entries(fd_dir) && m.value("process_open_fds") == static_cast<double>(listed);
    if (attempt == 4) {
      EXPECT_EQ(m.value("process_open_fds"), static_cast<double>(listed));
    }
  }
  EXPECT_TRUE(matched);
  // statm (size and resident, in pages) read before and after the scrape: the server's threads
  // may map memory meanwhile (a new malloc arena reserves 64 MiB of address space), so the
  // scraped values lie between the two readings, not at either.
  const std::string statm = "/proc/" + std::to_string(server.child().pid()) + "/statm";
  const auto read_statm = [&statm] {
    std::ifstream in(statm);
    std::array<double, 2> pages{};
    in >> pages[0] >> pages[1];
    return pages;
  };
  const std::array<double, 2> before = read_statm();
  const PromText m = scrape(client);
  const std::array<double, 2> after = read_statm();
  std::ifstream limits("/proc/" + std::to_string(server.child().pid()) + "/limits");
  std::string line;
  double soft = -1;
  while (std::getline(limits, line)) {
    if (line.starts_with("Max open files")) soft = std::stod(line.substr(26));
  }
  EXPECT_EQ(m.value("process_max_fds"), soft);
  const double page = static_cast<double>(::sysconf(_SC_PAGESIZE));
  const auto within = [&](double value, std::size_t k, double slack) {
    const double lo = std::min(before[k], after[k]) * page,
                 hi = std::max(before[k], after[k]) * page;
    EXPECT_GE(value, (1.0 - slack) * lo)
        << k << ": " << before[k] << " and " << after[k] << " pages";
    EXPECT_LE(value, (1.0 + slack) * hi)
        << k << ": " << before[k] << " and " << after[k] << " pages";
  };
  within(m.value("process_virtual_memory_bytes"), 0, 0.05);
  within(m.value("process_resident_memory_bytes"), 1, 0.2);
  const double now = static_cast<double>(std::time(nullptr));
  const double start = m.value("process_start_time_seconds");
  EXPECT_LE(start, now + 1);
  EXPECT_GE(start, now - 60);  // started by this test
  EXPECT_GE(m.value("process_cpu_seconds_total"), 0.0);
}

TEST(Metrics, ProcessStatsOfThisProcess) {
  const double before = service::read_process_stats().open_fds.value();
  int pipes[2][2];
  ASSERT_EQ(::pipe(pipes[0]), 0);
  ASSERT_EQ(::pipe(pipes[1]), 0);
  EXPECT_EQ(service::read_process_stats().open_fds.value(), before + 4);
  for (auto& p : pipes) {
    ::close(p[0]);
    ::close(p[1]);
  }
  // CPU time against getrusage, after burning some.
  volatile double x = 0;
  for (int i = 0; i < 20000000; ++i) x = x + std::sqrt(static_cast<double>(i));
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  const double rusage_s =
      static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
      static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
  EXPECT_NEAR(service::read_process_stats().cpu_seconds.value(), rusage_s, 0.05);
  rlimit limit{};
  ::getrlimit(RLIMIT_NOFILE, &limit);
  EXPECT_EQ(service::read_process_stats().max_fds.value(), static_cast<double>(limit.rlim_cur));
  EXPECT_NO_THROW(test::parse_prom_text(service::process_metrics_text()));
}

TEST(Metrics, PromtoolAcceptsTheExposition) {
  if (!std::filesystem::exists("/usr/bin/promtool")) {
    GTEST_SKIP() << "promtool not installed (Debian prometheus)";
  }
  Server server;
  auto client = server.client();
  // One keep-alive connection: each request is logged and observed before the next is read.
  client.set_keep_alive(true);
  ASSERT_TRUE(client.Post("/v1/plans", baseline_plan().dump(), "application/json"));
  const auto r = client.Get("/metrics");
  ASSERT_TRUE(r && r->status == 200);
  test::TempDir dir;
  test::write_file(dir / "metrics.txt", r->body);
  const std::string command = "/usr/bin/promtool check metrics < " +
                              (dir / "metrics.txt").string() + " > " + (dir / "out.txt").string() +
                              " 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << test::read_file(dir / "out.txt");
}

}  // namespace test_metrics
}  // namespace slosh
