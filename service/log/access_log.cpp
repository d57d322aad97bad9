#include "log/access_log.hpp"

#include <spdlog/formatter.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <ctime>
#include <memory>

#include "log/batched_log.hpp"
#include "slosh/api/log_json.hpp"

namespace slosh::service {

namespace {

std::atomic<bool> json_logs{false};

// Marks a message whose payload is the members of a JSON object (`{"a":1,...}`) to be merged into
// the log line; no other message starts with it (ASCII record separator).
constexpr char kFieldsMarker = '\x1e';

// "2026-11-24T23:55:01.123Z"
std::string utc_time(spdlog::log_clock::time_point when) {
  const auto since_epoch = when.time_since_epoch();
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(since_epoch);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch - seconds);
  const std::time_t t = seconds.count();
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char text[40];
  const std::size_t n = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
  return std::string(text, n) + fmt::format(".{:03d}Z", ms.count());
}

// One JSON object per message: time, level, then msg, or the marked message's own members.
class JsonFormatter final : public spdlog::formatter {
 public:
  void format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& dest) override {
    const std::string_view payload(msg.payload.data(), msg.payload.size());
    const spdlog::string_view_t level = spdlog::level::to_string_view(msg.level);
    std::string line = "{\"time\":\"" + utc_time(msg.time) + "\",\"level\":" +
                       api::json_quoted(std::string_view(level.data(), level.size())) + ",";
    if (!payload.empty() && payload.front() == kFieldsMarker) {
      line.append(payload.substr(2));  // the members after the marker and the object's '{'
    } else {
      line += "\"msg\":" + api::json_quoted(payload) + "}";
    }
    line += '\n';
    dest.append(line.data(), line.data() + line.size());
  }
  [[nodiscard]] std::unique_ptr<spdlog::formatter> clone() const override {
    return std::make_unique<JsonFormatter>();
  }
};

// `text` with every byte that could end or fake a text log line, or that a terminal would
// interpret, written as \xNN: control bytes (CR, LF, NUL, ESC, ...), space, DEL, bytes of
// non-ASCII characters, and the backslash itself (so an escape in the log is never ambiguous).
std::string escaped(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte <= 0x20 || byte >= 0x7f || c == '\\') {
      out += fmt::format("\\x{:02x}", byte);
    } else {
      out += c;
    }
  }
  return out;
}

void add_plan_text(std::string& line, const PlanFacts& plan) {
  line += " plan=" + plan.key + " strategy=" + plan.strategy + " plan_status=" + plan.status;
}

std::string json_fields(const AccessLogEntry& e) {
  api::LoggedRequest r{e.request_id, e.method, e.route, e.path,      e.status,
                       e.ms,         e.bytes,  e.cache, std::nullopt};
  if (e.plan)
    r.plan = api::LoggedPlan{e.plan->key, e.plan->strategy, e.plan->status, e.plan->cached};
  return api::request_log_object(r);
}

}  // namespace

void use_log_format(const std::string& format) {
  json_logs = format == "json";
  if (json_logs) {
    spdlog::set_formatter(std::make_unique<JsonFormatter>());
  } else {
    spdlog::set_pattern("%+");
  }
}

void log_access(const AccessLogEntry& e) {
  const BatchedSink::Batchable batchable;  // one line per request: it may wait for its batch
  if (json_logs) {
    spdlog::info("{}{}", kFieldsMarker, json_fields(e));
    return;
  }
  std::string line = fmt::format(
      "request id={} method={} path={} status={} cache={} ms={} bytes={} route={}", e.request_id,
      escaped(e.method), escaped(e.path), e.status, e.cache.empty() ? "-" : e.cache,
      e.ms ? fmt::format("{:.3f}", *e.ms) : "-", e.bytes, e.route);
  if (e.plan) add_plan_text(line, *e.plan);
  spdlog::info("{}", line);
}

}  // namespace slosh::service
