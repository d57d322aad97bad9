#include "metrics/metrics.hpp"

#include "config/version.hpp"

namespace slosh::service {

void Metrics::count_request(const std::string& route, int status) {
  std::lock_guard lock(mutex_);
  ++requests_[{route, status}];
}

void Metrics::observe_solve(const std::string& strategy, double seconds) {
  std::lock_guard lock(mutex_);
  solves_[strategy].observe(kSolveBuckets, seconds);
}

void Metrics::count_singleflight_join() {
  std::lock_guard lock(mutex_);
  ++singleflight_joins_;
}

void Metrics::count_min_time_search() {
  std::lock_guard lock(mutex_);
  ++min_time_searches_;
}

void Metrics::count_min_time_join() {
  std::lock_guard lock(mutex_);
  ++min_time_joins_;
}

void Metrics::count_export_refusal() {
  std::lock_guard lock(mutex_);
  ++export_refusals_;
}

void Metrics::observe_http(const std::string& route, const std::string& method, double seconds) {
  std::lock_guard lock(mutex_);
  http_[{route, method}].observe(kHttpBuckets, seconds);
}

void Metrics::count_plan(const std::string& strategy, const std::string& status) {
  std::lock_guard lock(mutex_);
  ++plans_[{strategy, status}];
}

void Metrics::count_cache_hit(CacheLevel level) {
  std::lock_guard lock(mutex_);
  ++cache_hits_.at(static_cast<std::size_t>(level));
}

void Metrics::count_cache_miss() {
  std::lock_guard lock(mutex_);
  ++cache_misses_;
}

void Metrics::collect_counters(MetricsText& out) const {
  out.family("slosh_http_requests_total", "counter", "HTTP requests by route and status.");
  for (const auto& [key, n] : requests_) {
    out.sample("slosh_http_requests_total",
               "route=\"" + key.first + "\",status=\"" + std::to_string(key.second) + "\"", n);
  }
  out.family("slosh_solve_seconds", "histogram", "Wall-clock time of plan solves by strategy.");
  for (const auto& [strategy, h] : solves_) {
    out.histogram("slosh_solve_seconds", "strategy=\"" + strategy + "\"", h, kSolveBuckets);
  }
  out.family("slosh_cache_hits_total", "counter",
             "Plan and min-time requests answered from the cache, by level: memory (this "
             "replica's LRU), sqlite (its local file), redis (the shared level).");
  for (const CacheLevel level : {CacheLevel::kMemory, CacheLevel::kLocal, CacheLevel::kShared}) {
    out.sample("slosh_cache_hits_total", "level=\"" + std::string(level_name(level)) + "\"",
               cache_hits_.at(static_cast<std::size_t>(level)));
  }
  const auto counter = [&out](const char* name, const char* help, std::uint64_t n) {
    out.family(name, "counter", help);
    out.sample(name, "", n);
  };
  counter("slosh_cache_misses_total", "Plan requests that needed a solve.", cache_misses_);
  counter("slosh_singleflight_joins_total",
          "Plan requests that waited for the running solve of the same recipe.",
          singleflight_joins_);
  counter("slosh_min_time_searches_total",
          "Min-time searches that ran (one pool task per strategy); one skipped while queued "
          "because its clients left is counted in slosh_solves_cancelled_total only.",
          min_time_searches_);
  counter("slosh_min_time_joins_total",
          "Min-time requests that waited for the running search of the same request.",
          min_time_joins_);
  counter("slosh_cam_export_refusals_total",
          "Cam exports refused (503) because the exports in flight left too little of "
          "cam_export_bytes.",
          export_refusals_);
}

void Metrics::collect_http(MetricsText& out) const {
  out.family("slosh_http_request_duration_seconds", "histogram",
             "Time from routing a request to its response written, by route and method.");
  for (const auto& [key, h] : http_) {
    out.histogram(
        "slosh_http_request_duration_seconds",
        "route=\"" + label_value(key.first) + "\",method=\"" + label_value(key.second) + "\"", h,
        kHttpBuckets);
  }
  out.family("slosh_plans_total", "counter",
             "Plans served (solved for the request or from the cache) by strategy and plan "
             "status.");
  for (const auto& [key, n] : plans_) {
    out.sample(
        "slosh_plans_total",
        "strategy=\"" + label_value(key.first) + "\",status=\"" + label_value(key.second) + "\"",
        n);
  }
  out.family("slosh_build_info", "gauge", "The running slosh version (always 1).");
  out.sample("slosh_build_info", "version=\"" + label_value(kVersion) + "\"", std::uint64_t{1});
}

void Metrics::collect(MetricsText& out, std::size_t queue_depth, std::size_t busy_workers,
                      std::size_t workers) const {
  std::lock_guard lock(mutex_);
  collect_counters(out);
  const auto gauge = [&out](const char* name, const char* help, std::uint64_t n) {
    out.family(name, "gauge", help);
    out.sample(name, "", n);
  };
  gauge("slosh_queue_depth", "Solves waiting for a worker.", queue_depth);
  gauge("slosh_busy_workers", "Workers running a solve.", busy_workers);
  gauge("slosh_workers", "Size of the worker pool.", workers);
  collect_http(out);
}

}  // namespace slosh::service
