#include "metrics/process_metrics.hpp"

#include <dirent.h>
#include <sys/resource.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <vector>

namespace slosh::service {

namespace {

// The fields of /proc/self/stat after the command name (which may hold spaces and parentheses):
// field 3 (state) is element 0.
std::vector<std::string> stat_fields() {
  std::ifstream in("/proc/self/stat");
  std::string line;
  std::getline(in, line);
  const std::size_t close = line.rfind(')');
  std::vector<std::string> fields;
  if (close == std::string::npos) return fields;
  std::istringstream rest(line.substr(close + 1));
  for (std::string f; rest >> f;) fields.push_back(f);
  return fields;
}

std::optional<double> boot_time_seconds() {
  std::ifstream in("/proc/stat");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("btime ", 0) == 0) return std::stod(line.substr(6));
  }
  return std::nullopt;
}

// Entries of /proc/self/fd other than . and .. and the directory's own descriptor.
std::optional<double> open_fds() {
  DIR* dir = ::opendir("/proc/self/fd");
  if (dir == nullptr) return std::nullopt;
  const std::string own = std::to_string(::dirfd(dir));
  double n = 0;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (name != "." && name != ".." && name != own) ++n;
  }
  ::closedir(dir);
  return n;
}

void sample(MetricsText& out, const char* name, const char* type, const char* help,
            const std::optional<double>& value) {
  if (!value) return;
  out.family(name, type, help);
  out.exact_sample(name, *value);
}

}  // namespace

ProcessStats read_process_stats() {
  ProcessStats s;
  const double ticks = static_cast<double>(::sysconf(_SC_CLK_TCK));
  const double page = static_cast<double>(::sysconf(_SC_PAGESIZE));
  // man 5 proc: utime (14), stime (15), starttime (22), vsize (23), rss (24); element = field - 3.
  const std::vector<std::string> f = stat_fields();
  if (f.size() > 21 && ticks > 0) {
    s.cpu_seconds = (std::stod(f[11]) + std::stod(f[12])) / ticks;
    s.virtual_bytes = std::stod(f[20]);
    s.resident_bytes = std::stod(f[21]) * page;
    if (const auto boot = boot_time_seconds())
      s.start_time_seconds = *boot + std::stod(f[19]) / ticks;
  }
  s.open_fds = open_fds();
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) == 0) s.max_fds = static_cast<double>(limit.rlim_cur);
  return s;
}

void collect_process_metrics(MetricsText& out, const ProcessStats& s) {
  sample(out, "process_cpu_seconds_total", "counter",
         "Total user and system CPU time spent in seconds.", s.cpu_seconds);
  sample(out, "process_resident_memory_bytes", "gauge", "Resident memory size in bytes.",
         s.resident_bytes);
  sample(out, "process_virtual_memory_bytes", "gauge", "Virtual memory size in bytes.",
         s.virtual_bytes);
  sample(out, "process_open_fds", "gauge", "Number of open file descriptors.", s.open_fds);
  sample(out, "process_max_fds", "gauge", "Maximum number of open file descriptors.", s.max_fds);
  sample(out, "process_start_time_seconds", "gauge",
         "Start time of the process since unix epoch in seconds.", s.start_time_seconds);
}

std::string process_metrics_text(const ProcessStats& s) {
  MetricsText out;
  collect_process_metrics(out, s);
  return out.str();
}

std::string process_metrics_text() {
  return process_metrics_text(read_process_stats());
}

}  // namespace slosh::service
