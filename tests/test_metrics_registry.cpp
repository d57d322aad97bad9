// The one writer of the exposition text (MetricsText, MetricsRegistry) against texts written out
// by hand here, and the /metrics of a real `slosh serve`: every family written once, its HELP and
// TYPE before its samples, in the registry's order (request counters, process, store gauges,
// batch jobs, cancellations).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "metrics/metrics_registry.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_metrics_registry {

TEST(MetricsRegistry, AHistogramIsWrittenWithCumulativeBucketsSumAndCount) {
  const std::array<double, 3> bounds{0.001, 0.0025, 1.0};
  service::Histogram<3> h;
  const std::vector<double> values{0.0005, 0.001, 0.002, 0.5, 7.0};
  for (const double v : values) h.observe(bounds, v);
  service::MetricsText out;
  out.family("x_seconds", "histogram", "Some time.");
  out.histogram("x_seconds", "route=\"/a\"", h, bounds);
  // Cumulative counts by hand: <= 0.001: 0.0005, 0.001; <= 0.0025: + 0.002; <= 1: + 0.5.
  EXPECT_EQ(out.str(),
            "# HELP x_seconds Some time.\n"
            "# TYPE x_seconds histogram\n"
            "x_seconds_bucket{route=\"/a\",le=\"0.001\"} 2\n"
            "x_seconds_bucket{route=\"/a\",le=\"0.0025\"} 3\n"
            "x_seconds_bucket{route=\"/a\",le=\"1\"} 4\n"
            "x_seconds_bucket{route=\"/a\",le=\"+Inf\"} 5\n"
            "x_seconds_sum{route=\"/a\"} 7.5035\n"
            "x_seconds_count{route=\"/a\"} 5\n");
}

TEST(MetricsRegistry, SamplesAndLabelValuesAreWrittenAsTheFormatSays) {
  EXPECT_EQ(service::label_value("a\\b\"c\nd"), "a\\\\b\\\"c\\nd");
  service::MetricsText out;
  out.sample("n_total", "", std::uint64_t{18446744073709551615ULL});
  out.sample("g", "k=\"v\"", 0.125);
  out.exact_sample("t_seconds", 1764217057.123456789);
  EXPECT_EQ(out.str(),
            "n_total 18446744073709551615\n"
            "g{k=\"v\"} 0.125\n"
            "t_seconds 1764217057.1234567\n");
}

TEST(MetricsRegistry, CollectorsRunInTheOrderTheyWereAdded) {
  service::MetricsRegistry registry;
  int runs = 0;
  registry.add([&](service::MetricsText& out) {
    ++runs;
    out.sample("first", "", std::uint64_t{1});
  });
  registry.add([&](service::MetricsText& out) {
    ++runs;
    out.sample("second", "", std::uint64_t{2});
  });
  EXPECT_EQ(registry.render(), "first 1\nsecond 2\n");
  EXPECT_EQ(registry.render(), "first 1\nsecond 2\n");
  EXPECT_EQ(runs, 4);
}

// The family a sample line belongs to: its name without the histogram suffixes.
std::string family_of(const std::string& name, const std::map<std::string, std::string>& types) {
  for (const char* suffix : {"_bucket", "_sum", "_count"}) {
    const std::string s(suffix);
    if (name.size() > s.size() && name.ends_with(s)) {
      const std::string base = name.substr(0, name.size() - s.size());
      if (types.contains(base) && types.at(base) == "histogram") return base;
    }
  }
  return name;
}

TEST(MetricsRegistry, TheServersMetricsHaveEachFamilyOnceInTheRegistrysOrder) {
  test::Server server;
  auto client = server.client();
  ASSERT_TRUE(client.Get("/healthz"));
  const auto r = client.Get("/metrics");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  std::istringstream in(r->body);
  std::map<std::string, std::string> types;
  std::vector<std::string> order;  // families in the order their HELP lines come
  std::string current;
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with("# HELP ")) {
      current = line.substr(7, line.find(' ', 7) - 7);
      EXPECT_FALSE(types.contains(current)) << current << " is written twice";
      order.push_back(current);
      continue;
    }
    if (line.starts_with("# TYPE ")) {
      std::istringstream words(line.substr(7));
      std::string name, type;
      words >> name >> type;
      EXPECT_EQ(name, current) << "TYPE right after its HELP";
      types[name] = type;
      continue;
    }
    const std::string name = line.substr(0, line.find_first_of("{ "));
    EXPECT_EQ(family_of(name, types), current) << line;
  }
  const auto at = [&](const std::string& family) {
    return std::find(order.begin(), order.end(), family) - order.begin();
  };
  const std::vector<std::string> expected{"slosh_http_requests_total",
                                          "slosh_workers",
                                          "slosh_build_info",
                                          "process_cpu_seconds_total",
                                          "slosh_cache_store_ok",
                                          "slosh_cam_export_budget_bytes",
                                          "slosh_batch_jobs_active",
                                          "slosh_solves_cancelled_total",
                                          "slosh_solves_timed_out_total"};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_LT(at(expected[i]), static_cast<long>(order.size())) << expected[i] << " is missing";
    if (i > 0) {
      EXPECT_LT(at(expected[i - 1]), at(expected[i])) << expected[i];
    }
  }
  EXPECT_EQ(order.back(), "slosh_solves_timed_out_total");
}

}  // namespace test_metrics_registry
}  // namespace slosh
