#include "slosh/api/batch_job_reply.hpp"

#include <array>
#include <utility>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"

namespace slosh::api {

namespace {

constexpr std::array<std::pair<JobState, std::string_view>, 5> kStateNames{{
    {JobState::kQueued, "queued"},
    {JobState::kRunning, "running"},
    {JobState::kDone, "done"},
    {JobState::kCancelled, "cancelled"},
    {JobState::kFailed, "failed"},
}};

std::optional<JobState> state_named(std::string_view name) {
  for (const auto& [state, text] : kStateNames) {
    if (text == name) return state;
  }
  return std::nullopt;
}

// The string member `name` of `object`; empty when it is absent, null or not a string.
std::string text_member(const nlohmann::json& object, const char* name) {
  const auto it = object.find(name);
  return it != object.end() && it->is_string() ? it->get<std::string>() : std::string();
}

}  // namespace

std::string_view to_string(JobState state) {
  for (const auto& [s, text] : kStateNames) {
    if (s == state) return text;
  }
  return "unknown";
}

bool is_final(JobState state) {
  return state == JobState::kDone || state == JobState::kCancelled || state == JobState::kFailed;
}

std::optional<JobProgress> parse_job_progress(std::string_view text) {
  const nlohmann::json record = nlohmann::json::parse(text, nullptr, false);
  if (record.is_discarded() || !record.is_object()) return std::nullopt;
  const auto state = state_named(text_member(record, "state"));
  const auto progress = record.find("progress");
  if (!state || progress == record.end() || !progress->is_object()) return std::nullopt;
  const auto done = progress->find("done");
  if (done == progress->end() || !done->is_number_unsigned()) return std::nullopt;
  JobProgress p;
  p.state = *state;
  p.done = done->get<std::size_t>();
  if (const auto total = progress->find("total");
      total != progress->end() && total->is_number_unsigned()) {
    p.total = total->get<std::size_t>();
  }
  p.message = text_member(record, "message");
  const auto cancel = record.find("cancel_requested");
  p.cancel_requested = cancel != record.end() && cancel->is_boolean() && cancel->get<bool>();
  return p;
}

std::optional<std::string> parse_job_id(std::string_view text) {
  const nlohmann::json record = nlohmann::json::parse(text, nullptr, false);
  if (record.is_discarded() || !record.is_object()) return std::nullopt;
  std::string id = text_member(record, "id");
  return id.empty() ? std::nullopt : std::optional(std::move(id));
}

std::string job_body_text(std::string_view table, std::string_view table_format,
                          const std::optional<std::string>& view) {
  nlohmann::json body{{"table", table}, {"table_format", table_format}, {"format", "jsonl"}};
  if (view) body["view"] = *view;
  return dump_json(body);
}

}  // namespace slosh::api
