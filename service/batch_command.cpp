#include "batch_command.hpp"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include "cli_commands.hpp"
#include "http_client.hpp"
#include "io.hpp"
#include "plan_service.hpp"
#include "plan_table.hpp"
#include "recipe_table.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service {

namespace {

using nlohmann::json;

/// Timeout of one POST /v1/plans/batch chunk in server mode.
constexpr std::chrono::seconds kServerTimeout{600};
/// 503 answers retried per chunk before giving up.
constexpr int kServerRetries = 30;
/// How often the progress bar is refreshed while waiting for a solve.
constexpr std::chrono::milliseconds kPollInterval{100};

/// Stops the run (server unreachable, output not writable): exit kExitFailure.
struct BatchAbort : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Writes rows in input order and keeps the counts of the summary.
class RowSink {
 public:
  RowSink(PlanTableWriter& writer, bool full) : writer_(writer), full_(full) {}
  void write(const RecipeRow& recipe, const BatchResult& result) {
    const json row = plan_row(recipe, result, full_);
    const std::string status = row["status"].get<std::string>();
    ++statuses_[status];
    if (status == "error") failed_rows_.push_back(recipe.row);
    if (result.cached) ++cached_;
    ++written_;
    writer_.write(row);
  }
  [[nodiscard]] std::size_t written() const { return written_; }
  [[nodiscard]] std::size_t cached() const { return cached_; }
  [[nodiscard]] const std::vector<std::size_t>& failed_rows() const { return failed_rows_; }
  [[nodiscard]] const std::map<std::string, std::size_t>& statuses() const { return statuses_; }

 private:
  PlanTableWriter& writer_;
  bool full_;
  std::size_t written_{0};
  std::size_t cached_{0};
  std::vector<std::size_t> failed_rows_;
  std::map<std::string, std::size_t> statuses_;
};

BatchResult row_error_result(const RecipeRow& row) {
  BatchResult r;
  r.error = api::error_from_json(row.error);
  return r;
}

void run_local(const std::vector<RecipeRow>& rows, ServerConfig config, RowSink& sink,
               ProgressBar& bar) {
  std::vector<json> requests;
  std::vector<std::size_t> slot(rows.size(), static_cast<std::size_t>(-1));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].error.is_null()) continue;
    slot[i] = requests.size();
    requests.push_back(rows[i].request);
  }
  const std::size_t unreadable = rows.size() - requests.size();
  // Room for the whole table: submission never blocks, so rows are written as they finish.
  config.queue = std::max<std::size_t>(1, requests.size());
  PlanService service(config);
  if (const std::string e = service.cache().storage_error(); !e.empty()) {
    std::cerr << "slosh batch: warning: " << e << '\n';
  }
  const PendingBatch batch = service.start_batch(requests);
  // Counting finished solves polls every item: only when the bar is due for a redraw.
  auto refresh = [&] {
    if (bar.due()) bar.update(unreadable + batch.finished());
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (slot[i] == static_cast<std::size_t>(-1)) {
      sink.write(rows[i], row_error_result(rows[i]));
      continue;
    }
    while (!batch.wait_for(slot[i], kPollInterval)) refresh();
    sink.write(rows[i], batch.get(slot[i]));
    refresh();
  }
}

// POSTs one chunk, retrying 503 answers after their Retry-After.
std::vector<api::BatchItemReply> post_chunk(HttpClient& client,
                                            const std::vector<nlohmann::json>& requests) {
  const std::string body = api::batch_body_text(requests);
  for (int attempt = 0;; ++attempt) {
    HttpReply reply;
    try {
      reply = client.post_json("/v1/plans/batch", body);
    } catch (const HttpError& e) {
      throw BatchAbort(e.what());
    }
    if (reply.status == 503 && attempt < kServerRetries) {
      const int wait =
          reply.retry_after.empty() ? 1 : std::max(1, std::atoi(reply.retry_after.c_str()));
      std::this_thread::sleep_for(std::chrono::seconds(wait));
      continue;
    }
    auto results = reply.status == 200 ? api::parse_batch_reply(reply.body) : std::nullopt;
    if (!results) {
      std::string message = "HTTP " + std::to_string(reply.status);
      if (const std::string m = api::envelope_message(reply.body); !m.empty()) {
        message += ": " + m;
      }
      throw BatchAbort(client.base_url() + "/v1/plans/batch answered " + message);
    }
    return std::move(*results);
  }
}

void run_remote(const std::vector<RecipeRow>& rows, const BatchCommandOptions& options,
                HttpClient& client, RowSink& sink, ProgressBar& bar) {
  for (std::size_t begin = 0; begin < rows.size(); begin += options.chunk) {
    const std::size_t end = std::min(rows.size(), begin + options.chunk);
    std::vector<nlohmann::json> requests;
    std::vector<std::size_t> sent;
    for (std::size_t i = begin; i < end; ++i) {
      if (rows[i].error.is_null()) {
        requests.push_back(rows[i].request);
        sent.push_back(i);
      }
    }
    const std::vector<api::BatchItemReply> results =
        requests.empty() ? std::vector<api::BatchItemReply>{} : post_chunk(client, requests);
    if (results.size() != sent.size()) {
      throw BatchAbort("the service answered " + std::to_string(results.size()) + " results for " +
                       std::to_string(sent.size()) + " requests");
    }
    std::size_t next = 0;
    for (std::size_t i = begin; i < end; ++i) {
      if (next < sent.size() && sent[next] == i) {
        const api::BatchItemReply& item = results[next++];
        BatchResult result;
        result.plan = item.plan;
        result.cached = item.cached;
        result.error = item.error;
        sink.write(rows[i], result);
      } else {
        sink.write(rows[i], row_error_result(rows[i]));
      }
    }
    bar.update(sink.written());
  }
}

std::string count(std::size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

std::string summary(const RowSink& sink, double seconds, const std::string& out) {
  std::string text = "slosh batch: " + count(sink.written(), "recipe") + ", " +
                     std::to_string(sink.written() - sink.failed_rows().size()) + " planned (" +
                     std::to_string(sink.cached()) + " from cache";
  for (const auto& [status, n] : sink.statuses()) {
    if (status != "error") text += ", " + std::to_string(n) + " " + status;
  }
  char timing[32];
  std::snprintf(timing, sizeof timing, ", %.1f s", seconds);
  text += "), " + count(sink.failed_rows().size(), "error") + timing;
  if (out != "-") text += " -> " + out;
  return text;
}

std::string failed_rows_text(const std::vector<std::size_t>& rows) {
  std::string text;
  for (std::size_t k = 0; k < rows.size() && k < 20; ++k) {
    text += (k == 0 ? "" : ", ") + std::to_string(rows[k]);
  }
  if (rows.size() > 20) text += ", ...";
  return text;
}

}  // namespace

int run_batch_command(const BatchCommandOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  std::vector<RecipeRow> rows;
  TableFormat out_format{};
  std::unique_ptr<HttpClient> client;
  try {
    const TableFormat in_format = table_format(options.in_format, options.in);
    out_format = table_format(options.out_format, options.out);
    std::string text;
    try {
      text = read_request_text(options.in);
    } catch (const std::exception&) {
      throw TableError("cannot read the recipe table '" + options.in + "'");
    }
    rows = read_recipe_table(text, in_format);
    if (options.full && out_format == TableFormat::kCsv) {
      throw TableError("--full adds the whole plan to JSON rows: use a .json or .jsonl output");
    }
    if (!options.server.empty() && options.chunk == 0) {
      throw TableError("--chunk must be at least 1");
    }
    if (!options.server.empty()) {
      client = std::make_unique<HttpClient>(options.server, kServerTimeout);  // checks the URL
    }
  } catch (const std::exception& e) {
    std::cerr << "slosh batch: " << e.what() << '\n';
    return kExitInvalidInput;
  }

  const bool to_stdout = options.out == "-";
  const std::string partial = options.out + ".partial";
  std::ofstream file;
  if (!to_stdout) {
    file.open(partial, std::ios::binary | std::ios::trunc);
    if (!file) {
      std::cerr << "slosh batch: cannot write '" << partial << "'\n";
      return kExitFailure;
    }
  }
  std::ostream& out = to_stdout ? std::cout : file;
  PlanTableWriter writer(out, out_format);
  RowSink sink(writer, options.full);
  const bool draw = progress_enabled(options.progress);
  ProgressBar bar(std::cerr, rows.size(), draw);
  bar.update(0);
  try {
    if (options.server.empty()) {
      run_local(rows, options.config, sink, bar);
    } else {
      run_remote(rows, options, *client, sink, bar);
    }
    writer.finish();
  } catch (const std::exception& e) {
    bar.finish();
    std::cerr << "slosh batch: stopped after " << sink.written() << " of " << rows.size()
              << " recipes: " << e.what() << '\n';
    if (!to_stdout) std::cerr << "slosh batch: the rows written so far are in " << partial << '\n';
    return kExitFailure;
  }
  bar.finish();
  if (!to_stdout) {
    file.close();
    if (!file || std::rename(partial.c_str(), options.out.c_str()) != 0) {
      std::cerr << "slosh batch: cannot write '" << options.out << "' (the table is in " << partial
                << ")\n";
      return kExitFailure;
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (draw || !sink.failed_rows().empty()) std::cerr << summary(sink, seconds, options.out) << '\n';
  if (!sink.failed_rows().empty()) {
    std::cerr << "slosh batch: " << (sink.failed_rows().size() == 1 ? "row " : "rows ")
              << failed_rows_text(sink.failed_rows())
              << " could not be planned: see the message of the row\n";
    return kExitSomeRowsFailed;
  }
  return kExitOk;
}

}  // namespace slosh::service
