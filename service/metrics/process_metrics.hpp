#pragma once
// The standard process_* metrics of Prometheus client libraries, read from /proc (Linux).

#include <optional>
#include <string>

#include "metrics/metrics_registry.hpp"

namespace slosh::service {

/// What /proc says about this process; a member is nullopt when it could not be read.
struct ProcessStats {
  std::optional<double> cpu_seconds;         ///< user + system CPU time [s]
  std::optional<double> resident_bytes;      ///< resident set size [bytes]
  std::optional<double> virtual_bytes;       ///< virtual memory size [bytes]
  std::optional<double> open_fds;            ///< open file descriptors
  std::optional<double> max_fds;             ///< the soft RLIMIT_NOFILE
  std::optional<double> start_time_seconds;  ///< start time since the Unix epoch [s]
};

/// Reads /proc/self/stat, /proc/stat (boot time), /proc/self/fd and the NOFILE limit.
[[nodiscard]] ProcessStats read_process_stats();

/// Writes `stats` to `out` (HELP, TYPE and one sample per known member): the same families as
/// process_metrics_text.
void collect_process_metrics(MetricsText& out, const ProcessStats& stats);

/// The exposition text of `stats` (HELP, TYPE and one sample per known member):
/// process_cpu_seconds_total, process_resident_memory_bytes, process_virtual_memory_bytes,
/// process_open_fds, process_max_fds, process_start_time_seconds.
[[nodiscard]] std::string process_metrics_text(const ProcessStats& stats);
/// The same of this process now.
[[nodiscard]] std::string process_metrics_text();

}  // namespace slosh::service
