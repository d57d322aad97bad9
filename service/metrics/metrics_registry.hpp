#pragma once
// The one writer of the Prometheus text exposition format (version 0.0.4) and the registry of
// everything GET /metrics reports: each part of the service (request counters, the engine's
// gauges, the batch jobs, the process) registers a collector that writes its families through
// MetricsText, and the registry runs them in registration order. No other code builds exposition
// text by hand.

#include <array>
#include <cstdint>
#include <functional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace slosh::service {

/// A label value with backslash, double quote and newline escaped (exposition format 0.0.4).
[[nodiscard]] std::string label_value(std::string_view value);

/// A histogram of `N` buckets with upper bounds kept by its owner (cumulative counts).
template <std::size_t N>
struct Histogram {
  std::array<std::uint64_t, N> buckets{};
  std::uint64_t count{};
  double sum{};

  /// Counts `value` in every bucket whose bound it does not exceed.
  void observe(const std::array<double, N>& bounds, double value) {
    for (std::size_t i = 0; i < N; ++i) {
      if (value <= bounds[i]) ++buckets[i];
    }
    ++count;
    sum += value;
  }
};

/// Exposition text under construction.
class MetricsText {
 public:
  /// The "# HELP" and "# TYPE" lines of a family (`type`: counter, gauge or histogram).
  void family(std::string_view name, std::string_view type, std::string_view help);
  /// "name{labels} value": `labels` already formatted (`a="x",b="y"`); empty = no braces.
  void sample(std::string_view name, std::string_view labels, std::uint64_t value);
  /// A real value in the stream's default notation (6 significant digits).
  void sample(std::string_view name, std::string_view labels, double value);
  /// A real value with every digit a double holds (%.17g): process figures such as start times.
  void exact_sample(std::string_view name, double value);
  /// The _bucket lines (one per bound, then +Inf), _sum and _count of `h` under `labels`.
  template <std::size_t N>
  void histogram(std::string_view name, std::string_view labels, const Histogram<N>& h,
                 const std::array<double, N>& bounds) {
    for (std::size_t i = 0; i < N; ++i) bucket(name, labels, bound_text(bounds[i]), h.buckets[i]);
    bucket(name, labels, "+Inf", h.count);
    sample(std::string(name) + "_sum", labels, h.sum);
    sample(std::string(name) + "_count", labels, h.count);
  }
  [[nodiscard]] std::string str() const { return out_.str(); }

 private:
  void bucket(std::string_view name, std::string_view labels, std::string_view le, std::uint64_t n);
  static std::string bound_text(double bound);
  std::ostringstream out_;
};

/// What GET /metrics reports, in the order the collectors were added.
class MetricsRegistry {
 public:
  using Collector = std::function<void(MetricsText&)>;
  /// Adds a collector; it runs on every render, so it must stay valid while the registry does.
  void add(Collector collector);
  /// The exposition text of every collector.
  [[nodiscard]] std::string render() const;

 private:
  std::vector<Collector> collectors_;
};

}  // namespace slosh::service
