#include "jobs/batch_jobs.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <optional>
#include <sstream>
#include <utility>

#include "http/query_params.hpp"
#include "jobs/batch_job_record.hpp"
#include "jobs/batch_job_state.hpp"
#include "jobs/job_messages.hpp"
#include "jobs/plan_table.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/job_record.hpp"
#include "slosh/api/job_request.hpp"
#include "slosh/api/plan_table_row.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::service {

namespace {

/// Rows read from the store at a time when a job's results are read (one HMGET of at most this
/// many fields on Redis: a 27 000-row job is not one command of 27 000 fields).
constexpr std::size_t kRowsPage = 500;

/// Another replica's record older than this [ms] (4 heartbeats) is behind: its owner is paused,
/// or the shared store refuses or fails its writes (its heartbeat then says it is alive).
constexpr std::int64_t kBehindMs = 2000;

/// The shortest time a replica sees another replica's record silent past batch_job_stale_s
/// before it reads the job as failed: the owner's Redis client retries a second after a failure
/// (RedisOptions::retry_interval), then writes at its next heartbeat (every 0.5 s).
constexpr std::chrono::milliseconds kSilenceConfirmFloor{2000};

[[noreturn]] void invalid(const std::string& field, const std::string& message) {
  throw api::ApiError(api::ErrorCode::kInvalidValue, field, message);
}

// The recipes of POST /v1/batches `text` and the outputs it asks for.
struct JobBody {
  std::vector<RecipeRow> rows;
  api::JobRequest outputs;
};

JobBody parse_job_body(const std::string& text, std::size_t max) {
  JobBody out;
  out.outputs = api::parse_job_request(
      text, max, [&](const std::string& table, const std::string& format, bool from_requests) {
        if (from_requests) {  // an array of 1 to max plan requests, read as a .json table
          out.rows = read_recipe_table(table, TableFormat::kJson);
          return;
        }
        try {
          out.rows = read_recipe_table(table, table_format(format, "-"));
        } catch (const TableError& e) {
          invalid("table", e.what());
        }
        if (out.rows.empty() || out.rows.size() > max) {
          invalid("table", "the table has " + std::to_string(out.rows.size()) +
                               " recipes: a job holds 1 to " + std::to_string(max) +
                               " (batch_job_max)");
        }
      });
  return out;
}

Reply record_reply(int status, const JobRecord& record) {
  Reply r;
  r.status = status;
  r.body = api::job_record_text(record);
  return r;
}

// The record of job `id`: 404 when no store knows it, 503 (unavailable) when the shared store
// cannot be asked (the job may run on another replica) or its stored text is damaged.
JobRecord load_record(JobStore& store, const std::string& id, const ServerConfig& config) {
  const JobStore::RecordLookup lookup = store.lookup_record(id);
  const auto& text = lookup.text;
  const std::string shown = id.substr(0, 64);
  if (lookup.damaged || !text) {
    refuse_missing_record(
        store, id, lookup,
        {config.batch_job_ttl_s, config.batch_jobs_kept, config.batch_jobs_bytes});
  }
  if (auto record = api::parse_job_record(*text)) return std::move(*record);
  throw api::ApiError(api::ErrorCode::kUnavailable, "id",
                      "the stored state of batch job '" + shown +
                          "' is damaged (not a job record): POST the job again");
}

// Rows [offset, offset + count) of job `id`, all of them, read in pages. Rows the shared store
// lost (e.g. while Redis was down or flushed) or holds damaged are a 503 (unavailable) naming
// them, never a short or blank-filled table answered as complete; a store that does not answer
// in time is a 503 naming it and its timeout (the rows are not lost).
std::vector<api::PlanTableRow> load_rows(JobStore& store, const std::string& id, std::size_t offset,
                                         std::size_t count) {
  std::vector<api::PlanTableRow> rows;
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
      if (auto row = api::parse_result_row(*(*slots)[i], number)) {
        ++readable;
        rows.push_back(std::move(*row));
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

// The rows of a shared job that stopped before all its rows were stored (cancelled): the
// replicas stored them in no particular order, so its rows have gaps. Rows [offset, offset +
// count) of those it holds, in table order; a 503 as load_rows() when fewer than its `done` are
// readable.
std::vector<api::PlanTableRow> load_present_rows(JobStore& store, const std::string& id,
                                                 const JobRecord& record, std::size_t offset,
                                                 std::size_t count) {
  std::vector<api::PlanTableRow> rows;
  std::vector<std::size_t> damaged;  // 1-based row numbers
  for (std::size_t page = 0; page < record.total; page += kRowsPage) {
    const std::size_t n = std::min(kRowsPage, record.total - page);
    const auto [slots, failure] = store.read_slots(id, page, n);
    if (!slots) {
      throw api::ApiError(api::ErrorCode::kUnavailable, "id",
                          rows_unread_text(id, page + 1, page + n, failure));
    }
    for (std::size_t i = 0; i < n && i < slots->size(); ++i) {
      if (!(*slots)[i]) continue;
      if (auto row = api::parse_result_row(*(*slots)[i], page + i + 1)) {
        rows.push_back(std::move(*row));
      } else {
        damaged.push_back(page + i + 1);
      }
    }
  }
  if (rows.size() < record.done || !damaged.empty()) {
    throw api::ApiError(api::ErrorCode::kUnavailable, "id",
                        rows_problem_text(id, rows.size(), 1, record.total, {}, damaged));
  }
  const std::size_t first = std::min(offset, rows.size());
  const std::size_t last = std::min(rows.size(), first + count);
  return {std::make_move_iterator(rows.begin() + static_cast<std::ptrdiff_t>(first)),
          std::make_move_iterator(rows.begin() + static_cast<std::ptrdiff_t>(last))};
}

// Rows [offset, offset + count) of the finished job of `record`, as load_rows() or, for a shared
// job with gaps, load_present_rows().
std::vector<api::PlanTableRow> finished_rows(JobStore& store, const std::string& id,
                                             const JobRecord& record, std::size_t offset,
                                             std::size_t count) {
  if (record.document.contains("shares") && record.done < record.total) {
    return load_present_rows(store, id, record, offset, count);
  }
  return load_rows(store, id, offset, count);
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
Reply table_reply(const std::string& id, TableFormat format,
                  const std::vector<api::PlanTableRow>& rows, JobState state, std::size_t total) {
  std::ostringstream out;
  PlanTableWriter writer(out, format);  // the `slosh batch` table writer
  for (const api::PlanTableRow& row : rows) writer.write(row);
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
  r.headers.emplace_back("X-Slosh-Job-State", std::string(api::to_string(state)));
  return r;
}

}  // namespace

BatchJobs::BatchJobs(PlanService& service, JobStore& store)
    : service_(service), store_(store), runner_([this] { run_jobs(); }) {
  const ServerConfig& config = service.config();
  if (!service.redis()) return;
  if (config.batch_job_spread == "helpers") {
    const auto ttl = std::chrono::milliseconds(std::llround(config.batch_job_ttl_s * 1e3));
    const auto stale = std::chrono::milliseconds(std::llround(config.batch_job_stale_s * 1e3));
    helped_ = std::make_unique<HelpedJobs>(service.redis(), replica_name(config), ttl);
    helper_ =
        std::make_unique<HelperWorker>(service, service.redis(), replica_name(config), ttl, stale,
                                       store, [this](const std::string& id) { return adopt(id); });
    return;
  }
  if (config.batch_job_spread != "replicas") return;
  SharedQueueOptions options;
  options.replica = replica_name(config);
  // A replica silent for batch_job_stale_s is stopped: its items are taken over after that long.
  options.claim_idle = std::chrono::milliseconds(std::llround(config.batch_job_stale_s * 1e3));
  options.alive = options.claim_idle;
  options.ttl = std::chrono::milliseconds(std::llround(config.batch_job_ttl_s * 1e3));
  options.max_bytes = config.batch_jobs_bytes;
  options.max_takes = config.batch_job_max_takes;
  shared_ = std::make_unique<SharedJobWorker>(
      service, service.redis(), std::move(options),
      [this](const std::string& id) { keep_finished_shared(id); });
}

BatchJobs::~BatchJobs() {
  shutdown();
  if (runner_.joinable()) runner_.join();
}

void BatchJobs::shutdown() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  if (shared_) shared_->stop();  // its items in flight are taken over by the other replicas
  if (helper_) helper_->stop();
  wake_.notify_all();
}

std::size_t BatchJobs::active() const {
  const std::lock_guard lock(mutex_);
  return active_.size() + (shared_ ? shared_->owned() : 0);
}

void BatchJobs::judge_liveness(JobRecord& record, const std::string& id) const {
  // A job this replica runs is alive whatever its record's age (the record may be old because
  // this process was paused, or the shared store missed writes): only another replica's job
  // whose owner stopped rewriting it is judged stale.
  {
    const std::lock_guard lock(mutex_);
    if (active_.count(id) != 0) return;
  }
  if (shared_ && shared_->owns(id)) return;  // its worker here beats it
  if (api::is_final(record.state)) {
    forget_silence(id);
    return;
  }
  const std::int64_t now = unix_ms_now();
  const std::int64_t age = now - record.updated_unix_ms;
  const double stale_s = service_.config().batch_job_stale_s;
  if (age > kBehindMs) {
    // The owner renews its heartbeat even while the store refuses its record (Redis full): a
    // heartbeat newer than the record is an owner alive whose progress the store lacks.
    const auto beat = store_.heartbeat_age_ms(id);
    if (beat && *beat + kBehindMs < age && static_cast<double>(*beat) <= stale_s * 1e3) {
      api::mark_unshared(record, std::nullopt,
                         shared_ ? shared_behind_text(age, *beat) : store_behind_text(age, *beat));
      return;
    }
  }
  if (static_cast<double>(age) <= stale_s * 1e3) {
    forget_silence(id);
    return;
  }
  // A stall of the shared store ages every record at once, and the live owner's next write comes
  // right after it: a record is only called failed once this replica has seen it silent for a
  // while longer, the owner's chance to write (and a helper's to take the job over) first.
  const auto seen_for = silence_seen_for(id, record.updated_unix_ms);
  const auto confirm = silence_confirmation(stale_s);
  if (seen_for >= confirm) {
    mark_if_stale(record, now, stale_s);
    return;
  }
  api::add_note(record, silent_owner_text(age, stale_s, confirm - seen_for, helped_ != nullptr));
}

std::chrono::milliseconds BatchJobs::silence_confirmation(double stale_s) {
  return std::max(kSilenceConfirmFloor, std::chrono::milliseconds(std::llround(stale_s * 1e3 / 2)));
}

std::chrono::milliseconds BatchJobs::silence_seen_for(const std::string& id,
                                                      std::int64_t updated_unix_ms) const {
  const auto now = std::chrono::steady_clock::now();
  const std::lock_guard lock(mutex_);
  // Jobs that were never read again are dropped once their records have expired.
  const auto keep = std::chrono::milliseconds(std::llround(
      (service_.config().batch_job_ttl_s + service_.config().batch_job_stale_s) * 1e3));
  std::erase_if(silences_, [&](const auto& entry) { return now - entry.second.first > keep; });
  auto [it, inserted] = silences_.try_emplace(id, Silence{updated_unix_ms, now});
  if (!inserted && it->second.updated_unix_ms != updated_unix_ms)
    it->second = {updated_unix_ms, now};
  return std::chrono::duration_cast<std::chrono::milliseconds>(now - it->second.first);
}

void BatchJobs::forget_silence(const std::string& id) const {
  const std::lock_guard lock(mutex_);
  silences_.erase(id);
}

JobRecord BatchJobs::load(const std::string& id) const {
  try {
    return load_record(store_, id, service_.config());
  } catch (const api::ApiError& e) {
    if (!shared_ || e.code() != api::ErrorCode::kUnavailable) throw;
    const auto own = shared_->owned_record(id);
    auto record = own ? api::parse_job_record(*own) : std::nullopt;
    if (!record) throw;
    api::mark_unshared(*record, std::nullopt, owner_view_text());
    return std::move(*record);
  }
}

std::string BatchJobs::record_text(Job& job) {
  JobStatus status = job.status;
  // A DELETE on this replica sets the job's flag from another thread: a queued job's record says
  // so at once, not only once the runner has taken the job.
  if (job.cancel) status.cancel_requested = true;
  return api::job_record_text(status, unix_ms_now());
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
      for (RecipeRow& row : body.rows)
        api::resolve_recipe_model(row.request, row.error, resolve_models_);
    }
    auto job = std::make_shared<Job>();
    job->status.id = new_job_id();
    job->status.format = body.outputs.format;
    job->status.view = body.outputs.view;
    job->status.total = body.rows.size();
    job->status.created_ms = unix_ms_now();
    job->rows = std::move(body.rows);
    if (body.outputs.view) job->view = api::parse_plan_view(*body.outputs.view);
    if (shared_) return post_shared(*job);
    Reply reply;
    {
      const std::lock_guard lock(mutex_);
      check_capacity_locked();  // again: other jobs may have been posted meanwhile
      // Rendered before the runner can see the job (it owns the status from then on).
      reply.status = 202;
      reply.body = api::job_record_text(job->status, unix_ms_now());
      reply.headers.emplace_back("Location", "/v1/batches/" + job->status.id);
      // Accepted only once every replica can find it: with a shared store down, another replica
      // would answer 404 for a job this one runs (until its next heartbeat published it).
      if (auto refused = store_.create(job->status.id, record_text(*job))) {
        throw api::ApiError(api::ErrorCode::kUnavailable, "",
                            *refused + "; the job was not started: POST it again later");
      }
      // Offered to the other replicas once accepted; without them (Redis refused the offer) it
      // runs here alone, as with "owner".
      if (helped_ && !helped_->publish(job->status, job->rows)) {
        spdlog::warn(
            "batch job {}: its items could not be offered to the other replicas; it runs here "
            "alone",
            job->status.id);
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
  const std::size_t active = active_.size() + (shared_ ? shared_->owned() : 0);
  if (active >= limit) {
    throw api::ApiError(api::ErrorCode::kOverloaded, "",
                        std::to_string(active) +
                            " batch jobs are queued or running here, the limit " +
                            "(batch_jobs_max); retry after one has finished");
  }
}

Reply BatchJobs::get(const std::string& id, const JobPageQuery& query) {
  return guarded_reply([&] {
    const ServerConfig& config = service_.config();
    std::size_t offset = 0;
    std::optional<api::ApiError> bad_offset;
    try {
      offset = query_count(query.offset, "offset", 0, 0, config.batch_job_max);
    } catch (const api::ApiError& e) {
      bad_offset = e;
    }
    const std::size_t limit = query_count(query.limit, "limit", kJobPageDefault, 1, kJobPageMax);
    JobRecord record = load(id);
    if (bad_offset) {
      // A job posted through a replica with a larger batch_job_max (settings changed one replica
      // at a time) is paged to its end through this one too.
      if (record.total <= config.batch_job_max) throw *bad_offset;
      offset = query_count(query.offset, "offset", 0, 0, record.total);
    }
    // A shared job's progress as of now, not of the last heartbeat, while some replica rewrites
    // its record (once none has for a while, the stored record is judged as it is).
    if (shared_ && !api::is_final(record.state) &&
        unix_ms_now() - record.updated_unix_ms <= kBehindMs) {
      if (auto live = shared_->live_record(id)) {
        if (auto now = api::parse_job_record(*live)) record = std::move(*now);
      }
    }
    // The latest view of a job posted here, answered while Redis cannot be asked.
    if (shared_ && !record.unshared) shared_->note_view(id, api::job_record_text(record));
    judge_liveness(record, id);
    if (const auto kept = store_.unshared(id)) {  // this replica runs it, the store is behind
      api::mark_unshared(record, kept->rows, kept->reason);
    }
    if ((!api::is_final(record.state) || record.state == JobState::kDone) &&
        !record.cancel_requested && store_.cancel_requested(id)) {
      // A DELETE through another replica is recorded in the shared store at once; the owner
      // rewrites the record when it next polls the flag (a queued job: when it starts). One it
      // accepted as the owner stored the last row finds the job done: it is kept, and said.
      api::mark_cancel_requested(record);
      if (record.state == JobState::kDone) {
        const auto note = record.document.find("note");
        api::add_note(record, late_cancel_note(note != record.document.end() && note->is_string()
                                                   ? note->get<std::string>()
                                                   : std::string()));
      }
    }
    if (api::is_final(record.state)) {
      const std::size_t stored = record.done;
      std::vector<api::PlanTableRow> rows;
      if (offset < stored) {
        rows = finished_rows(store_, id, record, offset, std::min(limit, stored - offset));
      }
      api::add_results(record, offset, limit, rows);
    }
    return record_reply(200, record);
  });
}

Reply BatchJobs::results(const std::string& id, TableFormat format,
                         const std::vector<std::string>& partial) {
  return guarded_reply([&] {
    const bool accept_partial = partial_of(partial);
    JobRecord record = load(id);
    judge_liveness(record, id);
    const JobState state = record.state;
    const std::size_t stored = record.done;
    const std::size_t total = record.total;
    const std::string path =
        "/v1/batches/" + id + (format == TableFormat::kCsv ? "/results.csv" : "/results.jsonl");
    if (!api::is_final(state) && record.unshared) {
      throw api::ApiError(api::ErrorCode::kUnavailable, "id",
                          results_behind_text(id, record.unshared_reason));
    }
    if (!api::is_final(state)) {
      return PlanService::error_reply(
          api::ErrorCode::kConflict,
          "batch job " + id + " is " + std::string(api::to_string(state)) + " (" +
              std::to_string(stored) + " of " + std::to_string(total) +
              " recipes done): its results are ready when it is done; poll GET /v1/batches/" + id,
          "id");
    }
    // A cancelled or failed job's table lacks rows: never answered as if it were the table.
    const bool complete = stored == total;
    if (!complete && !accept_partial) {
      return PlanService::error_reply(
          api::ErrorCode::kConflict,
          incomplete_results_text(id, std::string(api::to_string(state)), stored, total,
                                  record.message, path),
          "id");
    }
    return table_reply(id, format, finished_rows(store_, id, record, 0, stored), state, total);
  });
}

Reply BatchJobs::cancel(const std::string& id) {
  return guarded_reply([&] {
    JobRecord record = load(id);
    judge_liveness(record, id);
    if (api::is_final(record.state)) {
      store_.remove(id);
      api::mark_deleted(record);
      return record_reply(200, record);
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
    // A shared job posted here: its worker sets the flag once Redis answers.
    if (!recorded && !here && shared_) here = shared_->cancel_later(id);
    if (!recorded && !here) {
      // Another replica runs the job and only the shared store can tell it: a cancel that was
      // not recorded must not be answered as accepted.
      throw api::ApiError(api::ErrorCode::kUnavailable, "id",
                          "batch job '" + id.substr(0, 64) +
                              "' runs on another replica and its cancel could not be recorded in "
                              "the shared job store (Redis): DELETE it again later");
    }
    wake_.notify_all();
    api::mark_cancel_requested(record);
    if (!here &&
        !shared_) {  // when the owner will see it: it may be paused, or cut off from the store
      const std::int64_t age = unix_ms_now() - record.updated_unix_ms;
      const auto beat = age > kBehindMs ? store_.heartbeat_age_ms(id) : std::nullopt;
      api::add_cancel_note(
          record, remote_cancel_text(age, beat.value_or(-1), service_.config().batch_job_stale_s,
                                     helped_ != nullptr));
    }
    return record_reply(202, record);
  });
}

}  // namespace slosh::service
