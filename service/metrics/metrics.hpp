#pragma once
// The service's request, cache and solve counters (GET /metrics, written through
// metrics_registry.hpp).

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <utility>

#include "cache/cache_level.hpp"
#include "metrics/metrics_registry.hpp"

namespace slosh::service {

class Metrics {
 public:
  /// Upper bounds of the solve-time histogram buckets [s].
  static constexpr std::array<double, 10> kSolveBuckets{0.001, 0.002, 0.005, 0.01, 0.02,
                                                        0.05,  0.1,   0.2,   0.5,  1.0};

  void count_request(const std::string& route, int status);
  void observe_solve(const std::string& strategy, double seconds);
  /// A plan (or min-time) request answered from the cache level `level`.
  void count_cache_hit(CacheLevel level);
  /// A plan (or min-time) request that needed a new solve (or search).
  void count_cache_miss();
  /// A plan request that waited for the running solve of the same recipe (single flight).
  void count_singleflight_join();
  /// A min-time request that started a search (its strategies queued on the pool).
  void count_min_time_search();
  /// A min-time request that waited for the running search of the same key (single flight).
  void count_min_time_join();
  /// A cam export refused because the export budget had no room for it (503).
  void count_export_refusal();

  /// Upper bounds of the HTTP latency histogram buckets [s]: 1 ms to 60 s (a cached plan answers
  /// in well under a millisecond, a solve takes up to its budget plus queueing).
  static constexpr std::array<double, 15> kHttpBuckets{
      0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 30.0, 60.0};
  /// One answered HTTP request: `route` is the routes-table path (or "other"), `method` a known
  /// HTTP method (or "other"); `seconds` from the start of routing to the response written.
  void observe_http(const std::string& route, const std::string& method, double seconds);
  /// A plan served to a client (solved for it or from the cache): its strategy and status.
  void count_plan(const std::string& strategy, const std::string& status);

  /// Writes the counters and histograms, the pool's gauges (`queue_depth`, `busy_workers`,
  /// `workers`, sampled by the caller) and slosh_build_info.
  void collect(MetricsText& out, std::size_t queue_depth, std::size_t busy_workers,
               std::size_t workers) const;

 private:
  // Requests, solve times and the cache counters, under the lock.
  void collect_counters(MetricsText& out) const;
  // HTTP latency, plans served and the build info, under the lock.
  void collect_http(MetricsText& out) const;
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, int>, std::uint64_t> requests_;
  std::map<std::string, Histogram<kSolveBuckets.size()>> solves_;
  std::map<std::pair<std::string, std::string>, Histogram<kHttpBuckets.size()>> http_;
  std::map<std::pair<std::string, std::string>, std::uint64_t> plans_;
  std::array<std::uint64_t, 3> cache_hits_{};  // by CacheLevel
  std::uint64_t cache_misses_{};
  std::uint64_t singleflight_joins_{};
  std::uint64_t min_time_searches_{};
  std::uint64_t min_time_joins_{};
  std::uint64_t export_refusals_{};
};

}  // namespace slosh::service
