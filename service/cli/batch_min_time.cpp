#include "cli/batch_min_time.hpp"

#include <iostream>
#include <optional>
#include <string>

#include "cli/batch_errors.hpp"
#include "cli/batch_retry.hpp"
#include "engine/plan_engine.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/recipe_row.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service::batch_cli {

namespace {

/// A min-time row on its way: its answer from the cache or a search, or the row's error.
struct MinTimeJob {
  std::optional<api::ApiError> error;
  PendingMinTime pending;
};

// Parses a row's min-time request and starts it on `engine`: from the plan store, joined to the
// search of an identical earlier row, or queued (waiting for queue room).
MinTimeJob start_min_time_row(const RecipeRow& row, double budget, PlanEngine& engine) {
  MinTimeJob job;
  if (row.error) {
    job.error = row.error;
    return job;
  }
  try {
    job.pending = engine.start_min_time(api::min_time_request_of(row.request, budget), true);
  } catch (const api::ApiError& e) {
    job.error = e;
  }
  return job;
}

// Writes the row of an answer (a stored or replied min-time response) or of its error; false for
// an error row.
bool write_min_time_row(const RecipeRow& recipe, const SolveOutcome& outcome,
                        MinTimeWriter& writer) {
  if (outcome.error) {
    writer.write(api::min_time_error_row(recipe.row, recipe.recipe_id, recipe.csv, *outcome.error));
    return false;
  }
  writer.write(api::min_time_answer_row(recipe.row, recipe.recipe_id, outcome.body));
  return true;
}

// POSTs one row's min-time request, retrying 503 answers after their Retry-After: the answer, or
// the error the service answered; BatchAbort when it answered no envelope.
SolveOutcome post_min_time_row(HttpClient& client, const std::string& body) {
  HttpReply reply = post_retrying_503(client, "/v1/min-time", body);
  if (reply.status == 200) return SolveOutcome{std::move(reply.body), std::nullopt};
  if (api::envelope_message(reply.body).empty()) {
    throw BatchAbort(client.base_url() + "/v1/min-time answered HTTP " +
                     std::to_string(reply.status));
  }
  return SolveOutcome{{}, api::error_from_text(reply.body)};
}

}  // namespace

MinTimeWriter::MinTimeWriter(std::ostream& out, TableFormat format) : out_(out), format_(format) {
  if (format_ == TableFormat::kCsv) {
    out_ << api::min_time_csv_header() << '\n';
  } else if (format_ == TableFormat::kJson) {
    out_ << '[';
  }
}

void MinTimeWriter::write(const api::MinTimeTableRow& row) {
  if (format_ == TableFormat::kCsv) {
    out_ << api::min_time_csv_line(row) << '\n';
  } else if (format_ == TableFormat::kJson) {
    out_ << (rows_ == 0 ? "\n" : ",\n") << api::min_time_json_text(row);
  } else {
    out_ << api::min_time_json_text(row) << '\n';
  }
  ++rows_;
  out_.flush();
}

void MinTimeWriter::finish() {
  if (format_ == TableFormat::kJson) out_ << (rows_ == 0 ? "]\n" : "\n]\n");
  out_.flush();
}

// Searches every row on a local PlanEngine (the cache file of `config`, `config.workers`, one
// task per row and strategy) and writes the rows in input order; the 1-based numbers of the rows
// in error.
std::vector<std::size_t> run_min_time_local(const std::vector<RecipeRow>& rows, ServerConfig config,
                                            MinTimeWriter& writer) {
  config.queue = 1024;
  PlanEngine engine(config);
  if (const std::string e = engine.min_time_cache().storage_error(); !e.empty()) {
    std::cerr << "slosh batch: warning: " << e << '\n';
  }
  std::vector<MinTimeJob> jobs;
  jobs.reserve(rows.size());
  for (const RecipeRow& row : rows) {
    jobs.push_back(start_min_time_row(row, config.solve_budget_s, engine));
  }
  std::vector<std::size_t> failed;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const MinTimeJob& job = jobs[i];
    const SolveOutcome outcome = job.error            ? SolveOutcome{{}, job.error}
                                 : job.pending.cached ? SolveOutcome{*job.pending.cached, {}}
                                                      : job.pending.search.get();
    if (!write_min_time_row(rows[i], outcome, writer)) failed.push_back(rows[i].row);
  }
  return failed;
}

// POSTs every readable row to the service's /v1/min-time, one after the other (each request's
// strategies run in parallel on the service's pool), and writes the rows as they return.
std::vector<std::size_t> run_min_time_remote(const std::vector<RecipeRow>& rows, HttpClient& client,
                                             MinTimeWriter& writer) {
  std::vector<std::size_t> failed;
  for (const RecipeRow& row : rows) {
    const SolveOutcome outcome =
        !row.error ? post_min_time_row(client, api::min_time_body_text(row.request))
                   : SolveOutcome{{}, row.error};
    try {
      if (!write_min_time_row(row, outcome, writer)) failed.push_back(row.row);
    } catch (const std::invalid_argument& e) {
      throw BatchAbort(client.base_url() + "/v1/min-time: " + e.what());
    }
  }
  return failed;
}

}  // namespace slosh::service::batch_cli
