#include "cli/batch_command.hpp"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "cli/batch_chunks.hpp"
#include "cli/batch_input.hpp"
#include "cli/batch_interrupt.hpp"
#include "cli/batch_job_remote.hpp"
#include "cli/batch_local.hpp"
#include "cli/batch_min_time.hpp"
#include "cli/batch_output.hpp"
#include "cli/batch_row_sink.hpp"
#include "cli/cli_commands.hpp"

namespace slosh::service {

namespace {

using namespace batch_cli;

std::string count(std::size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

std::string summary(const RowSink& sink, double seconds, const std::string& out) {
  std::string text = "slosh batch: " + count(sink.written(), "recipe") + ", " +
                     std::to_string(sink.written() - sink.failed_rows().size()) + " planned (" +
                     std::to_string(sink.cached()) + " from cache";
  for (const auto& [status, n] : sink.statuses()) text += ", " + std::to_string(n) + " " + status;
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

int run_min_time_mode(const BatchCommandOptions& options, BatchInput& in, BatchOutput& output) {
  std::vector<std::size_t> failed;
  try {
    MinTimeWriter writer(output.stream(), in.out_format);
    failed = in.client ? run_min_time_remote(in.rows, *in.client, writer)
                       : run_min_time_local(in.rows, options.config, writer);
    writer.finish();
  } catch (const std::exception& e) {
    std::cerr << "slosh batch: stopped: " << e.what() << '\n';
    return interrupt_requested() ? kExitInterrupted : kExitFailure;
  }
  if (!output.commit()) return kExitFailure;
  if (!failed.empty()) {
    std::cerr << "slosh batch: " << (failed.size() == 1 ? "row " : "rows ")
              << failed_rows_text(failed) << " could not be searched: see the message of the row\n";
    return kExitSomeRowsFailed;
  }
  return kExitOk;
}

int run_plan_mode(const BatchCommandOptions& options, BatchInput& in, BatchOutput& output,
                  std::chrono::steady_clock::time_point started) {
  PlanTableWriter writer(output.stream(), in.out_format);
  RowSink sink(writer, in.view);
  const bool draw = progress_enabled(options.progress);
  ProgressBar bar(std::cerr, in.rows.size(), draw);
  bar.update(0);
  try {
    if (options.server.empty()) {
      run_local(in.rows, options.config, sink, bar);
    } else if (!run_job_remote(in, options, *in.client, sink, bar)) {
      run_remote(in.rows, options, *in.client, sink, bar);
    }
    writer.finish();
  } catch (const std::exception& e) {
    bar.stop(sink.written());
    std::cerr << "slosh batch: stopped after " << sink.written() << " of " << in.rows.size()
              << " recipes: " << e.what() << '\n';
    if (!output.to_stdout()) {
      std::cerr << "slosh batch: the rows written so far are in " << output.partial();
      if (sink.written() == 0) {
        std::cerr << (in.out_format == TableFormat::kCsv ? " (none: it holds the header only)"
                                                         : " (none: it is empty)");
      }
      std::cerr << '\n';
    }
    return interrupt_requested() ? kExitInterrupted : kExitFailure;
  }
  bar.finish();
  if (!output.commit()) return kExitFailure;
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

}  // namespace

int run_batch_command(const BatchCommandOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  std::optional<InterruptFlag> interrupt;
  if (!options.server.empty()) interrupt.emplace();
  BatchInput in;
  if (auto exit_code = read_batch_input(options, in)) return *exit_code;
  // Before any plan is solved or posted: a table that cannot be written is not computed.
  BatchOutput output(options.out);
  if (!output.opened()) {
    std::cerr << "slosh batch: cannot write the output table '" << output.out() << "': creating '"
              << output.partial()
              << "' (where it is written before it is renamed) failed: " << output.open_error()
              << "; nothing was planned\n";
    return kExitFailure;
  }
  return options.mode == "min_time" ? run_min_time_mode(options, in, output)
                                    : run_plan_mode(options, in, output, started);
}

}  // namespace slosh::service
