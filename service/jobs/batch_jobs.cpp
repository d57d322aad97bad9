#include "jobs/batch_jobs.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <sstream>
#include <utility>

#include "http/query_params.hpp"
#include "jobs/batch_job_record.hpp"
#include "jobs/batch_job_state.hpp"
#include "jobs/job_messages.hpp"
#include "jobs/plan_table.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/service_bodies.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::service {

namespace {

using nlohmann::json;

/// Rows read from the store at a time when a job's results are read (one HMGET of at most this
/// many fields on Redis: a 27 000-row job is not one command of 27 000 fields).
constexpr std::size_t kRowsPage = 500;

/// Another replica's record older than this [ms] (4 heartbeats) is behind: its owner is paused,
/// or the shared store refuses or fails its writes (its heartbeat then says it is alive).
constexpr std::int64_t kBehindMs = 2000;

[[noreturn]] void invalid(const std::string& field, const std::string& message) {
  throw api::ApiError(api::ErrorCode::kInvalidValue, field, message);
}

// The body of POST /v1/batches.
struct JobBody {
  std::vector<RecipeRow> rows;
  std::string format{"csv"};
  std::optional<std::string> view;
};

std::vector<RecipeRow> table_rows(const json& body, std::size_t max) {
  const json& text = body["table"];
  if (!text.is_string())
    invalid("table", "table must be the text of a recipe table, got " + api::show(text));
  std::string format = "csv";
  if (const json* f = api::given_member(body, "table_format")) {
    format = f->is_string() ? f->get<std::string>() : api::show(*f);
    if (format != "csv" && format != "jsonl" && format != "json") {
      invalid("table_format", "table_format = " + api::show(*f) +
                                  " is not allowed: one of \"csv\", \"jsonl\", \"json\"");
    }
  }
  std::vector<RecipeRow> rows;
  try {
    rows = read_recipe_table(text.get<std::string>(), table_format(format, "-"));
  } catch (const TableError& e) {
    invalid("table", e.what());
  }
  if (rows.empty() || rows.size() > max) {
    invalid("table", "the table has " + std::to_string(rows.size()) +
                         " recipes: a job holds 1 to " + std::to_string(max) + " (batch_job_max)");
  }
  return rows;
}

std::vector<RecipeRow> request_rows(const json& requests, std::size_t max) {
  if (!requests.is_array() || requests.empty() || requests.size() > max) {
    invalid("requests", "requests must be an array of 1 to " + std::to_string(max) +
                            " plan requests (batch_job_max), got " +
                            (requests.is_array() ? std::to_string(requests.size()) + " requests"
                                                 : api::show(requests)));
  }
  // Read as `slosh batch` reads a .json table: each item a plan request, with an optional
  // "recipe_id" that the rows carry.
  return read_recipe_table(api::dump_json(requests), TableFormat::kJson);
}

JobBody parse_job_body(const std::string& text, std::size_t max) {
  const json body = api::parse_json_body(text);
  if (!body.is_object()) {
    invalid("",
            "the body must be an object {\"requests\": [plan requests]} or {\"table\": "
            "\"<recipe table>\", \"table_format\": \"csv\"}");
  }
  api::reject_unknown_fields(body, "", {"requests", "table", "table_format", "format", "view"});
  const bool has_requests = body.contains("requests");
  if (has_requests == body.contains("table")) {
    invalid(has_requests ? "table" : "requests",
            "give either requests (plan requests) or table (a recipe table's text), not " +
                std::string(has_requests ? "both" : "neither"));
  }
  if (has_requests && body.contains("table_format")) {
    invalid("table_format", "table_format goes with table, not with requests");
  }
  JobBody out;
  out.rows = has_requests ? request_rows(body["requests"], max) : table_rows(body, max);
  if (const json* f = api::given_member(body, "format")) {
    if (*f != "csv" && *f != "jsonl") {
      invalid("format", "format = " + api::show(*f) + " is not allowed: one of \"csv\", \"jsonl\"");
    }
    out.format = f->get<std::string>();
  }
  if (const json* v = api::given_member(body, "view")) {
    (void)api::batch_view({}, *v);  // 422 naming view unless "full" or "compact"
    out.view = v->get<std::string>();
  }
  return out;
}

Reply json_reply(int status, const json& body) {
  Reply r;
  r.status = status;
  r.body = api::dump_json(body);
  return r;
}

// The record of job `id`: 404 when no store knows it, 503 (unavailable) when the shared store
// cannot be asked (the job may run on another replica) or its stored text is damaged.
json load_record(JobStore& store, const std::string& id, const ServerConfig& config) {
  const JobStore::RecordLookup lookup = store.lookup_record(id);
  const auto& text = lookup.text;
  const std::string shown = id.substr(0, 64);
  if (lookup.damaged || !text) {
    refuse_missing_record(
        store, id, lookup,
        {config.batch_job_ttl_s, config.batch_jobs_kept, config.batch_jobs_bytes});
  }
  try {
    json record = json::parse(*text);
    (void)record.at("state").get<std::string>();
    (void)record.at("progress").at("done").get<std::size_t>();
    (void)record.at("progress").at("total").get<std::size_t>();
    return record;
  } catch (const json::exception&) {
    throw api::ApiError(api::ErrorCode::kUnavailable, "id",
                        "the stored state of batch job '" + shown +
                            "' is damaged (not a job record): POST the job again");
  }
}

// Whether `row` is a result row of the table's row `number` (1-based): an object naming its row
// and its status, as plan_row writes it. A row damaged in the shared store (e.g. "{}") is not.
bool is_result_row(const json& row, std::size_t number) {
  if (!row.is_object()) return false;
  const auto at = row.find("row");
  const auto status = row.find("status");
  return at != row.end() && at->is_number_unsigned() && at->get<std::size_t>() == number &&
         status != row.end() && status->is_string();
}

// Rows [offset, offset + count) of job `id`, all of them, read in pages. Rows the shared store
// lost (e.g. while Redis was down or flushed) or holds damaged are a 503 (unavailable) naming
// them, never a short or blank-filled table answered as complete; a store that does not answer
// in time is a 503 naming it and its timeout (the rows are not lost).
std::vector<json> load_rows(JobStore& store, const std::string& id, std::size_t offset,
                            std::size_t count) {
  std::vector<json> rows;
  rows.reserve(count);
  std::vector<std::size_t> damaged;  // 1-based row numbers
  std::vector<std::size_t> missing;  // 1-based row numbers
  std::size_t readable = 0;
  for (std::size_t page = offset; page < offset + count; page += kRowsPage) {
    const std::size_t n = std::min(kRowsPage, offset + count - page);
    const auto [slots, failure] = store.read_slots(id, page, n);
    if (!slots && !failure.empty()) {
      throw api::ApiError(api::ErrorCode::kUnavailable, "id",
                          rows_unread_text(id, page + 1, page + n, failure));
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t number = page + i + 1;
      if (!slots || i >= slots->size() || !(*slots)[i]) {
        missing.push_back(number);
        continue;
      }
      json row = json::parse(*(*slots)[i], nullptr, false);
      if (is_result_row(row, number)) {
        ++readable;
        rows.push_back(std::move(row));
      } else {
        damaged.push_back(number);
      }
    }
  }
  if (readable == count) return rows;
  throw api::ApiError(
      api::ErrorCode::kUnavailable, "id",
      rows_problem_text(id, readable, offset + 1, offset + count, missing, damaged));
}

// The value of ?partial= of a results download: "1" or "true" asks for the done rows of a job
// that did not finish them all; else 422 naming it.
bool partial_of(const std::vector<std::string>& values) {
  const std::string text = single_query_value(values, "partial").value_or("0");
  if (text == "1" || text == "true") return true;
  if (text == "0" || text == "false") return false;
  invalid("partial", "partial = " + (text.empty() ? "(empty)" : text.substr(0, 32)) +
                         " is not allowed: one of \"1\", \"true\", \"0\", \"false\"");
}

// A results download: the table as `slosh batch` writes it, with headers saying whether it holds
// every row of the job (X-Slosh-Partial), how many (X-Slosh-Rows of X-Slosh-Rows-Total) and the
// job's state (X-Slosh-Job-State).
Reply table_reply(const std::string& id, TableFormat format, const std::vector<json>& rows,
                  const std::string& state, std::size_t total) {
  std::ostringstream out;
  PlanTableWriter writer(out, format);  // the `slosh batch` table writer
  for (const json& row : rows) writer.write(row);
  writer.finish();
  Reply r;
  const bool csv = format == TableFormat::kCsv;
  r.content_type = csv ? "text/csv; charset=utf-8" : "application/x-ndjson";
  r.body = out.str();
  r.headers.emplace_back("Content-Disposition",
                         "attachment; filename=\"batch-" + id + (csv ? ".csv\"" : ".jsonl\""));
  r.headers.emplace_back("X-Slosh-Partial", rows.size() < total ? "true" : "false");
  r.headers.emplace_back("X-Slosh-Rows", std::to_string(rows.size()));
  r.headers.emplace_back("X-Slosh-Rows-Total", std::to_string(total));
  r.headers.emplace_back("X-Slosh-Job-State", state);
  return r;
}

}  // namespace

BatchJobs::BatchJobs(PlanService& service, JobStore& store)
    : service_(service), store_(store), runner_([this] { run_jobs(); }) {}

BatchJobs::~BatchJobs() {
  shutdown();
  if (runner_.joinable()) runner_.join();
}

void BatchJobs::shutdown() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
}

std::size_t BatchJobs::active() const {
  const std::lock_guard lock(mutex_);
  return active_.size();
}

void BatchJobs::judge_liveness(nlohmann::json& record, const std::string& id) const {
  // A job this replica runs is alive whatever its record's age (the record may be old because
  // this process was paused, or the shared store missed writes): only another replica's job
  // whose owner stopped rewriting it is judged stale.
  {
    const std::lock_guard lock(mutex_);
    if (active_.count(id) != 0) return;
  }
  if (is_final_state(record["state"].get<std::string>())) return;
  const std::int64_t now = unix_ms_now();
  const std::int64_t age = now - record.value("updated_unix_ms", std::int64_t{0});
  const double stale_s = service_.config().batch_job_stale_s;
  if (age > kBehindMs) {
    // The owner renews its heartbeat even while the store refuses its record (Redis full): a
    // heartbeat newer than the record is an owner alive whose progress the store lacks.
    const auto beat = store_.heartbeat_age_ms(id);
    if (beat && *beat + kBehindMs < age && static_cast<double>(*beat) <= stale_s * 1e3) {
      record["unshared"] = {{"rows", nullptr}, {"reason", store_behind_text(age, *beat)}};
      return;
    }
  }
  mark_if_stale(record, now, stale_s);
}

std::string BatchJobs::record_text(Job& job) {
  json record = job_record(job.status, unix_ms_now());
  // A DELETE on this replica sets the job's flag from another thread: a queued job's record says
  // so at once, not only once the runner has taken the job.
  if (job.cancel) record["cancel_requested"] = true;
  return api::dump_json(record);
}

bool BatchJobs::write_record(Job& job) {
  return store_.put_record(job.status.id, record_text(job));
}

Reply BatchJobs::post(const std::string& text) {
  return guarded_reply([&] {
    const ServerConfig& config = service_.config();
    JobBody body = parse_job_body(text, config.batch_job_max);
    // The cheap refusal first: resolving the recipes' stored models reads the calibrations.
    check_capacity();
    if (resolve_models_) {
      for (RecipeRow& row : body.rows) {
        const json* options =
            row.request.is_object() ? api::given_member(row.request, "options") : nullptr;
        const json* model = options != nullptr && options->is_object()
                                ? api::given_member(*options, "model")
                                : nullptr;
        if (model == nullptr || !model->is_string()) continue;
        try {
          row.request = json::parse(resolve_models_(api::dump_json(row.request)));
        } catch (const api::ApiError& e) {  // this recipe's row answers the error
          row.error = api::error_envelope(e)["error"];
          row.request = nullptr;
        }
      }
    }
    auto job = std::make_shared<Job>();
    job->status.id = new_job_id();
    job->status.format = body.format;
    job->status.view = body.view;
    job->status.total = body.rows.size();
    job->status.created_ms = unix_ms_now();
    job->rows = std::move(body.rows);
    if (body.view) job->view = api::parse_plan_view(*body.view);
    Reply reply;
    {
      const std::lock_guard lock(mutex_);
      check_capacity_locked();  // again: other jobs may have been posted meanwhile
      // Rendered before the runner can see the job (it owns the status from then on).
      reply = json_reply(202, job_record(job->status, unix_ms_now()));
      reply.headers.emplace_back("Location", "/v1/batches/" + job->status.id);
      // Accepted only once every replica can find it: with a shared store down, another replica
      // would answer 404 for a job this one runs (until its next heartbeat published it).
      if (auto refused = store_.create(job->status.id, record_text(*job))) {
        throw api::ApiError(api::ErrorCode::kUnavailable, "",
                            *refused + "; the job was not started: POST it again later");
      }
      active_[job->status.id] = job;
      queue_.push_back(job);
    }
    wake_.notify_all();
    return reply;
  });
}

void BatchJobs::check_capacity() const {
  const std::lock_guard lock(mutex_);
  check_capacity_locked();
}

void BatchJobs::check_capacity_locked() const {
  if (stopping_ || !service_.accepting()) {
    throw api::ApiError(api::ErrorCode::kOverloaded, "", "the service is shutting down");
  }
  const std::size_t limit = service_.config().batch_jobs_max;
  if (active_.size() >= limit) {
    throw api::ApiError(api::ErrorCode::kOverloaded, "",
                        std::to_string(active_.size()) +
                            " batch jobs are queued or running here, the limit " +
                            "(batch_jobs_max); retry after one has finished");
  }
}

Reply BatchJobs::get(const std::string& id, const JobPageQuery& query) {
  return guarded_reply([&] {
    const ServerConfig& config = service_.config();
    const std::size_t offset = query_count(query.offset, "offset", 0, 0, config.batch_job_max);
    const std::size_t limit = query_count(query.limit, "limit", kJobPageDefault, 1, kJobPageMax);
    json record = load_record(store_, id, config);
    judge_liveness(record, id);
    if (const auto kept = store_.unshared(id)) {  // this replica runs it, the store is behind
      record["unshared"] = {{"rows", kept->rows}, {"reason", kept->reason}};
    }
    if (!is_final_state(record["state"].get<std::string>()) &&
        record.value("cancel_requested", false) == false && store_.cancel_requested(id)) {
      // A DELETE through another replica is recorded in the shared store at once; the owner
      // rewrites the record when it next polls the flag (a queued job: when it starts).
      record["cancel_requested"] = true;
    }
    if (is_final_state(record["state"].get<std::string>())) {
      const std::size_t stored = record["progress"]["done"].get<std::size_t>();
      json rows = json::array();
      if (offset < stored) {
        for (json& row : load_rows(store_, id, offset, std::min(limit, stored - offset))) {
          rows.push_back(std::move(row));
        }
      }
      const std::size_t next = offset + rows.size();
      record["results"] = {{"offset", offset},
                           {"limit", limit},
                           {"rows", rows},
                           {"next_offset", next < stored ? json(next) : json(nullptr)},
                           {"partial", stored < record["progress"]["total"].get<std::size_t>()}};
    }
    return json_reply(200, record);
  });
}

Reply BatchJobs::results(const std::string& id, TableFormat format,
                         const std::vector<std::string>& partial) {
  return guarded_reply([&] {
    const ServerConfig& config = service_.config();
    const bool accept_partial = partial_of(partial);
    json record = load_record(store_, id, config);
    judge_liveness(record, id);
    const std::string state = record["state"].get<std::string>();
    const std::size_t stored = record["progress"]["done"].get<std::size_t>();
    const std::size_t total = record["progress"]["total"].get<std::size_t>();
    const std::string path =
        "/v1/batches/" + id + (format == TableFormat::kCsv ? "/results.csv" : "/results.jsonl");
    if (!is_final_state(state) && record.contains("unshared")) {
      throw api::ApiError(api::ErrorCode::kUnavailable, "id",
                          results_behind_text(id, record["unshared"]["reason"]));
    }
    if (!is_final_state(state)) {
      return PlanService::error_reply(
          api::ErrorCode::kConflict,
          "batch job " + id + " is " + state + " (" + std::to_string(stored) + " of " +
              std::to_string(total) +
              " recipes done): its results are ready when it is done; poll GET /v1/batches/" + id,
          "id");
    }
    // A cancelled or failed job's table lacks rows: never answered as if it were the table.
    const bool complete = stored == total;
    if (!complete && !accept_partial) {
      return PlanService::error_reply(
          api::ErrorCode::kConflict,
          incomplete_results_text(id, state, stored, total, record.value("message", ""), path),
          "id");
    }
    return table_reply(id, format, load_rows(store_, id, 0, stored), state, total);
  });
}

Reply BatchJobs::cancel(const std::string& id) {
  return guarded_reply([&] {
    const ServerConfig& config = service_.config();
    json record = load_record(store_, id, config);
    judge_liveness(record, id);
    if (is_final_state(record["state"].get<std::string>())) {
      store_.remove(id);
      record["deleted"] = true;
      return json_reply(200, record);
    }
    const bool recorded = store_.request_cancel(id);
    bool here = false;
    {
      const std::lock_guard lock(mutex_);
      if (auto it = active_.find(id); it != active_.end()) {
        it->second->cancel = true;
        here = true;
      }
    }
    if (!recorded && !here) {
      // Another replica runs the job and only the shared store can tell it: a cancel that was
      // not recorded must not be answered as accepted.
      throw api::ApiError(api::ErrorCode::kUnavailable, "id",
                          "batch job '" + id.substr(0, 64) +
                              "' runs on another replica and its cancel could not be recorded in "
                              "the shared job store (Redis): DELETE it again later");
    }
    wake_.notify_all();
    record["cancel_requested"] = true;
    if (!here) {  // when the owner will see it: it may be paused, or cut off from the store
      const std::int64_t age = unix_ms_now() - record.value("updated_unix_ms", std::int64_t{0});
      const auto beat = age > kBehindMs ? store_.heartbeat_age_ms(id) : std::nullopt;
      record["cancel_note"] =
          remote_cancel_text(age, beat.value_or(-1), service_.config().batch_job_stale_s);
    }
    return json_reply(202, record);
  });
}

}  // namespace slosh::service
