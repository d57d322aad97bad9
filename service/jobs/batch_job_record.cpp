#include "jobs/batch_job_record.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <ctime>

#include <algorithm>
#include <cstdio>

#include "slosh/api/fields.hpp"

namespace slosh::service {

using nlohmann::json;

std::int64_t unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string iso_time(std::int64_t unix_ms) {
  const std::time_t seconds = static_cast<std::time_t>(unix_ms / 1000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  std::array<char, 32> text{};
  const std::size_t n = std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%S", &utc);
  std::array<char, 8> millis{};
  std::snprintf(millis.data(), millis.size(), ".%03dZ", static_cast<int>(unix_ms % 1000));
  return std::string(text.data(), n) + millis.data();
}

namespace {

json optional_time(const std::optional<std::int64_t>& ms) {
  return ms ? json(iso_time(*ms)) : json(nullptr);
}

// Rows per second since the job started (to 0.1 row/s); 0 before it has.
double rate_per_s(const JobStatus& s, std::int64_t now_ms) {
  if (!s.started_ms) return 0.0;
  const std::int64_t end = s.finished_ms.value_or(now_ms);
  const double seconds = static_cast<double>(std::max<std::int64_t>(1, end - *s.started_ms)) / 1e3;
  return std::round(static_cast<double>(s.done) / seconds * 10.0) / 10.0;
}

}  // namespace

json job_record(const JobStatus& s, std::int64_t now_ms) {
  const double rate = rate_per_s(s, now_ms);
  json eta = nullptr;
  if (is_final_state(s.state)) {
    eta = 0;
  } else if (rate > 0.0) {
    eta = std::ceil(static_cast<double>(s.total - s.done) / rate);
  }
  const std::string base = "/v1/batches/" + s.id;
  return {{"id", s.id},
          {"state", s.state},
          {"format", s.format},
          {"view", s.view ? json(*s.view) : json(nullptr)},
          {"progress",
           {{"done", s.done},
            {"total", s.total},
            {"failed", s.failed},
            {"rate_per_s", rate},
            {"eta_s", eta}}},
          {"created_at", iso_time(s.created_ms)},
          {"started_at", optional_time(s.started_ms)},
          {"finished_at", optional_time(s.finished_ms)},
          {"updated_at", iso_time(now_ms)},
          {"updated_unix_ms", now_ms},
          {"message", s.message.empty() ? json(nullptr) : json(s.message)},
          {"note", s.note.empty() ? json(nullptr) : json(s.note)},
          {"cancel_requested", s.cancel_requested},
          {"results_csv", base + "/results.csv"},
          {"results_jsonl", base + "/results.jsonl"}};
}

bool is_final_state(const std::string& state) {
  return state == "done" || state == "cancelled" || state == "failed";
}

bool mark_if_stale(json& record, std::int64_t now_ms, double stale_s) {
  if (is_final_state(record.value("state", ""))) return false;
  const std::int64_t updated = record.value("updated_unix_ms", std::int64_t{0});
  const double silent_s = static_cast<double>(now_ms - updated) / 1e3;
  if (silent_s <= stale_s) return false;
  record["state"] = "failed";
  record["progress"]["rate_per_s"] = 0;
  record["progress"]["eta_s"] = 0;
  record["message"] = "the replica running it stopped: no update for " +
                      api::number_text(std::floor(silent_s)) +
                      " s (batch_job_stale_s = " + api::number_text(stale_s) +
                      " s); POST the job again (its plans are cached)";
  return true;
}

}  // namespace slosh::service
