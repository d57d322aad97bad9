#include "metrics.hpp"

#include <sstream>

#include "process_metrics.hpp"
#include "version.hpp"

namespace slosh::service {

void Metrics::count_request(const std::string& route, int status) {
  std::lock_guard lock(mutex_);
  ++requests_[{route, status}];
}

void Metrics::observe_solve(const std::string& strategy, double seconds) {
  std::lock_guard lock(mutex_);
  Histogram& h = solves_[strategy];
  for (std::size_t i = 0; i < kSolveBuckets.size(); ++i) {
    if (seconds <= kSolveBuckets[i]) ++h.buckets[i];
  }
  ++h.count;
  h.sum += seconds;
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
  HttpHistogram& h = http_[{route, method}];
  for (std::size_t i = 0; i < kHttpBuckets.size(); ++i) {
    if (seconds <= kHttpBuckets[i]) ++h.buckets[i];
  }
  ++h.count;
  h.sum += seconds;
}

void Metrics::count_plan(const std::string& strategy, const std::string& status) {
  std::lock_guard lock(mutex_);
  ++plans_[{strategy, status}];
}

namespace {

// A label value with backslash, double quote and newline escaped (exposition format 0.0.4).
std::string label(const std::string& value) {
  std::string out;
  for (const char c : value) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

// The HTTP latency histogram, the plans served, the build info and the process metrics.
void Metrics::render_http_and_process(std::ostringstream& out) const {
  out << "# HELP slosh_http_request_duration_seconds Time from routing a request to its response "
         "written, by route and method.\n"
      << "# TYPE slosh_http_request_duration_seconds histogram\n";
  for (const auto& [key, h] : http_) {
    const std::string labels =
        "route=\"" + label(key.first) + "\",method=\"" + label(key.second) + "\"";
    for (std::size_t i = 0; i < kHttpBuckets.size(); ++i) {
      out << "slosh_http_request_duration_seconds_bucket{" << labels << ",le=\"" << kHttpBuckets[i]
          << "\"} " << h.buckets[i] << '\n';
    }
    out << "slosh_http_request_duration_seconds_bucket{" << labels << ",le=\"+Inf\"} " << h.count
        << '\n'
        << "slosh_http_request_duration_seconds_sum{" << labels << "} " << h.sum << '\n'
        << "slosh_http_request_duration_seconds_count{" << labels << "} " << h.count << '\n';
  }
  out << "# HELP slosh_plans_total Plans served (solved for the request or from the cache) by "
         "strategy and plan status.\n"
      << "# TYPE slosh_plans_total counter\n";
  for (const auto& [key, n] : plans_) {
    out << "slosh_plans_total{strategy=\"" << label(key.first) << "\",status=\""
        << label(key.second) << "\"} " << n << '\n';
  }
  out << "# HELP slosh_build_info The running slosh version (always 1).\n"
      << "# TYPE slosh_build_info gauge\n"
      << "slosh_build_info{version=\"" << label(kVersion) << "\"} 1\n"
      << process_metrics_text();
}

void Metrics::count_cache_hit(CacheLevel level) {
  std::lock_guard lock(mutex_);
  ++cache_hits_.at(static_cast<std::size_t>(level));
}

void Metrics::count_cache_miss() {
  std::lock_guard lock(mutex_);
  ++cache_misses_;
}

std::string Metrics::render(std::size_t queue_depth, std::size_t busy_workers,
                            std::size_t workers) const {
  std::lock_guard lock(mutex_);
  std::ostringstream out;
  out << "# HELP slosh_http_requests_total HTTP requests by route and status.\n"
      << "# TYPE slosh_http_requests_total counter\n";
  for (const auto& [key, n] : requests_) {
    out << "slosh_http_requests_total{route=\"" << key.first << "\",status=\"" << key.second
        << "\"} " << n << '\n';
  }
  out << "# HELP slosh_solve_seconds Wall-clock time of plan solves by strategy.\n"
      << "# TYPE slosh_solve_seconds histogram\n";
  for (const auto& [strategy, h] : solves_) {
    for (std::size_t i = 0; i < kSolveBuckets.size(); ++i) {
      out << "slosh_solve_seconds_bucket{strategy=\"" << strategy << "\",le=\"" << kSolveBuckets[i]
          << "\"} " << h.buckets[i] << '\n';
    }
    out << "slosh_solve_seconds_bucket{strategy=\"" << strategy << "\",le=\"+Inf\"} " << h.count
        << '\n'
        << "slosh_solve_seconds_sum{strategy=\"" << strategy << "\"} " << h.sum << '\n'
        << "slosh_solve_seconds_count{strategy=\"" << strategy << "\"} " << h.count << '\n';
  }
  out << "# HELP slosh_cache_hits_total Plan and min-time requests answered from the cache, by "
         "level: memory (this replica's LRU), sqlite (its local file), redis (the shared level).\n"
      << "# TYPE slosh_cache_hits_total counter\n";
  for (const CacheLevel level : {CacheLevel::kMemory, CacheLevel::kLocal, CacheLevel::kShared}) {
    out << "slosh_cache_hits_total{level=\"" << level_name(level) << "\"} "
        << cache_hits_.at(static_cast<std::size_t>(level)) << '\n';
  }
  out << "# HELP slosh_cache_misses_total Plan requests that needed a solve.\n"
      << "# TYPE slosh_cache_misses_total counter\n"
      << "slosh_cache_misses_total " << cache_misses_ << '\n'
      << "# HELP slosh_singleflight_joins_total Plan requests that waited for the running solve "
         "of the same recipe.\n"
      << "# TYPE slosh_singleflight_joins_total counter\n"
      << "slosh_singleflight_joins_total " << singleflight_joins_ << '\n'
      << "# HELP slosh_min_time_searches_total Min-time requests that started a search (one pool "
         "task per strategy).\n"
      << "# TYPE slosh_min_time_searches_total counter\n"
      << "slosh_min_time_searches_total " << min_time_searches_ << '\n'
      << "# HELP slosh_min_time_joins_total Min-time requests that waited for the running search "
         "of the same request.\n"
      << "# TYPE slosh_min_time_joins_total counter\n"
      << "slosh_min_time_joins_total " << min_time_joins_ << '\n'
      << "# HELP slosh_cam_export_refusals_total Cam exports refused (503) because the exports "
         "in flight left too little of cam_export_bytes.\n"
      << "# TYPE slosh_cam_export_refusals_total counter\n"
      << "slosh_cam_export_refusals_total " << export_refusals_ << '\n'
      << "# HELP slosh_queue_depth Solves waiting for a worker.\n"
      << "# TYPE slosh_queue_depth gauge\n"
      << "slosh_queue_depth " << queue_depth << '\n'
      << "# HELP slosh_busy_workers Workers running a solve.\n"
      << "# TYPE slosh_busy_workers gauge\n"
      << "slosh_busy_workers " << busy_workers << '\n'
      << "# HELP slosh_workers Size of the worker pool.\n"
      << "# TYPE slosh_workers gauge\n"
      << "slosh_workers " << workers << '\n';
  render_http_and_process(out);
  return out.str();
}

}  // namespace slosh::service
