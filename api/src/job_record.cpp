#include "slosh/api/job_record.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <utility>

#include "slosh/api/error.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;

constexpr std::array<JobState, 5> kStates{JobState::kQueued, JobState::kRunning, JobState::kDone,
                                          JobState::kCancelled, JobState::kFailed};

json optional_time(const std::optional<std::int64_t>& ms) {
  return ms ? json(iso_time(*ms)) : json(nullptr);
}

// Items solved: the stored rows and, while a helped job runs, the items its helpers solved ahead
// of them (each item once).
std::size_t solved_of(const JobStatus& s) {
  if (is_final(s.state)) return s.done;
  return std::min(s.total, s.done + s.solved_ahead);
}

// Items solved per second since the job started (to 0.1 item/s); 0 before it has.
double rate_per_s(const JobStatus& s, std::int64_t now_ms) {
  if (!s.started_ms) return 0.0;
  const std::int64_t end = s.finished_ms.value_or(now_ms);
  const double seconds = static_cast<double>(std::max<std::int64_t>(1, end - *s.started_ms)) / 1e3;
  return std::round(static_cast<double>(solved_of(s)) / seconds * 10.0) / 10.0;
}

// The member `name` of `object` as a whole count; nullopt when absent or not a number.
std::optional<std::size_t> count_member(const json& object, const char* name) {
  const auto it = object.find(name);
  if (it == object.end() || !it->is_number()) return std::nullopt;
  return it->get<std::size_t>();
}

}  // namespace

std::optional<JobState> job_state_named(std::string_view name) {
  // The names are to_string's (one table).
  for (const JobState state : kStates) {
    if (to_string(state) == name) return state;
  }
  return std::nullopt;
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

std::string job_record_text(const JobStatus& s, std::int64_t now_ms) {
  const double rate = rate_per_s(s, now_ms);
  json eta = nullptr;
  if (is_final(s.state)) {
    eta = 0;
  } else if (rate > 0.0) {
    eta = std::ceil(static_cast<double>(s.total - solved_of(s)) / rate);
  }
  const std::string base = "/v1/batches/" + s.id;
  json record{{"id", s.id},
              {"state", to_string(s.state)},
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
  if (!s.shares.empty()) {
    json shares = json::object();
    for (const auto& [replica, rows] : s.shares) shares[replica] = rows;
    record["shares"] = std::move(shares);
    // A job several replicas work on: its items solved on any of them, each once.
    record["progress"]["solved"] = solved_of(s);
  }
  return dump_json(record);
}

std::optional<JobRecord> parse_job_record(std::string_view text) {
  json document = json::parse(text, nullptr, false);
  if (document.is_discarded() || !document.is_object()) return std::nullopt;
  const auto state = document.find("state");
  const auto progress = document.find("progress");
  if (state == document.end() || !state->is_string() || progress == document.end() ||
      !progress->is_object()) {
    return std::nullopt;
  }
  const auto named = job_state_named(state->get_ref<const std::string&>());
  const auto done = count_member(*progress, "done");
  const auto total = count_member(*progress, "total");
  if (!named || !done || !total) return std::nullopt;
  JobRecord record;
  record.state = *named;
  record.done = *done;
  record.total = *total;
  if (const auto updated = document.find("updated_unix_ms");
      updated != document.end() && updated->is_number()) {
    record.updated_unix_ms = updated->get<std::int64_t>();
  }
  if (const auto cancel = document.find("cancel_requested");
      cancel != document.end() && cancel->is_boolean()) {
    record.cancel_requested = cancel->get<bool>();
  }
  if (const auto message = document.find("message");
      message != document.end() && message->is_string()) {
    record.message = message->get<std::string>();
  }
  record.document = std::move(document);
  return record;
}

void mark_failed(JobRecord& record, const std::string& message) {
  record.state = JobState::kFailed;
  record.message = message;
  record.document["state"] = to_string(JobState::kFailed);
  record.document["progress"]["rate_per_s"] = 0;
  record.document["progress"]["eta_s"] = 0;
  record.document["message"] = message;
}

void mark_unshared(JobRecord& record, std::optional<std::size_t> rows, const std::string& reason) {
  record.unshared = true;
  record.unshared_reason = reason;
  record.document["unshared"] = {{"rows", rows ? json(*rows) : json(nullptr)}, {"reason", reason}};
}

void mark_cancel_requested(JobRecord& record) {
  record.cancel_requested = true;
  record.document["cancel_requested"] = true;
}

void add_note(JobRecord& record, const std::string& note) {
  record.document["note"] = note;
}

void add_cancel_note(JobRecord& record, const std::string& note) {
  record.document["cancel_note"] = note;
}

void mark_deleted(JobRecord& record) {
  record.document["deleted"] = true;
}

void add_results(JobRecord& record, std::size_t offset, std::size_t limit,
                 const std::vector<PlanTableRow>& rows) {
  json page = json::array();
  for (const PlanTableRow& row : rows) page.push_back(row.document);
  const std::size_t next = offset + rows.size();
  record.document["results"] = {{"offset", offset},
                                {"limit", limit},
                                {"rows", std::move(page)},
                                {"next_offset", next < record.done ? json(next) : json(nullptr)},
                                {"partial", record.done < record.total}};
}

std::string job_record_text(const JobRecord& record) {
  return dump_json(record.document);
}

std::optional<PlanTableRow> parse_result_row(std::string_view text, std::size_t number) {
  json row = json::parse(text, nullptr, false);
  if (!row.is_object()) return std::nullopt;
  const auto at = row.find("row");
  const auto status = row.find("status");
  if (at == row.end() || !at->is_number_unsigned() || at->get<std::size_t>() != number ||
      status == row.end() || !status->is_string()) {
    return std::nullopt;
  }
  return table_row_of(std::move(row));
}

namespace {

// The milliseconds of an iso_time() text; nullopt for anything else.
std::optional<std::int64_t> unix_ms_of(const json& text) {
  if (!text.is_string()) return std::nullopt;
  std::tm utc{};
  int millis = 0;
  const std::string& s = text.get_ref<const std::string&>();
  if (std::sscanf(s.c_str(), "%d-%d-%dT%d:%d:%d.%dZ", &utc.tm_year, &utc.tm_mon, &utc.tm_mday,
                  &utc.tm_hour, &utc.tm_min, &utc.tm_sec, &millis) != 7) {
    return std::nullopt;
  }
  utc.tm_year -= 1900;
  utc.tm_mon -= 1;
  return static_cast<std::int64_t>(timegm(&utc)) * 1000 + millis;
}

}  // namespace

JobStatus job_status_of(const JobRecord& record) {
  const json& d = record.document;
  JobStatus s;
  s.id = d.value("id", "");
  s.state = record.state;
  s.format = d.value("format", "csv");
  if (const auto view = d.find("view"); view != d.end() && view->is_string()) {
    s.view = view->get<std::string>();
  }
  s.total = record.total;
  s.done = record.done;
  if (const auto progress = d.find("progress"); progress != d.end()) {
    s.failed = count_member(*progress, "failed").value_or(0);
  }
  s.created_ms = unix_ms_of(d.value("created_at", json())).value_or(0);
  s.started_ms = unix_ms_of(d.value("started_at", json()));
  s.message = record.message;
  if (const auto note = d.find("note"); note != d.end() && note->is_string()) {
    s.note = note->get<std::string>();
  }
  s.cancel_requested = record.cancel_requested;
  if (const auto shares = d.find("shares"); shares != d.end() && shares->is_object()) {
    for (const auto& [replica, rows] : shares->items()) {
      if (rows.is_number_unsigned()) s.shares.emplace_back(replica, rows.get<std::size_t>());
    }
  }
  return s;
}

}  // namespace slosh::api
