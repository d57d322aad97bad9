#include "cli/batch_input.hpp"

#include <filesystem>
#include <iostream>
#include <utility>

#include "cli/batch_retry.hpp"
#include "cli/cli_commands.hpp"
#include "cli/io.hpp"
#include "slosh/api/error.hpp"

namespace slosh::service::batch_cli {

namespace {

// The view of the plan each JSON row carries: --view, or full with --full (both: the same view);
// nullopt for none. Throws TableError for an unknown view or two different ones.
std::optional<api::PlanView> row_plan_view(const BatchCommandOptions& options) {
  std::optional<api::PlanView> view;
  if (options.view) {
    try {
      view = api::parse_plan_view(*options.view);
    } catch (const api::ApiError& e) {
      throw TableError(std::string("--") + e.what());
    }
  }
  if (options.full && view && *view != api::PlanView::kFull) {
    throw TableError("--full adds the whole plan but --view " + *options.view +
                     " the compact one: give one of them");
  }
  return options.full ? std::optional(api::PlanView::kFull) : view;
}

// Throws TableError when writing the plan table would overwrite the recipe table: --out, or the
// "<out>.partial" file it is written to first, is the --in file (the same file after symbolic
// links and relative paths are resolved, or another hard link to it).
void check_out_is_not_in(const BatchCommandOptions& options) {
  if (options.in == "-" || options.out == "-") return;
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path in = fs::canonical(options.in, ec);
  if (ec) return;  // no such file: reading it fails with its own message
  if (fs::equivalent(options.out, in, ec) && !ec) {
    throw TableError("--out '" + options.out + "' is the --in file (" + in.string() +
                     "): the plan table would overwrite the recipe table; give --out another "
                     "path");
  }
  const std::string partial = options.out + ".partial";
  ec.clear();
  if (fs::equivalent(partial, in, ec) && !ec) {
    throw TableError("--out '" + options.out + "' is written first to '" + partial +
                     "', which is the --in file (" + in.string() +
                     "): the recipe table would be overwritten; give --out another path");
  }
}

}  // namespace

std::optional<int> read_batch_input(const BatchCommandOptions& options, BatchInput& in) {
  try {
    // Refused before anything is posted: a directory as --out would only fail once the job is
    // done, when the table is renamed into place.
    for (const auto& [flag, path] : {std::pair{"--in", &options.in}, {"--out", &options.out}}) {
      std::error_code ec;
      if (*path != "-" && std::filesystem::is_directory(*path, ec)) {
        throw TableError(std::string(flag) + " '" + *path +
                         "' is a directory: give the path of a table file" +
                         (std::string(flag) == "--in" ? "" : " to write") + " (or - for " +
                         (std::string(flag) == "--in" ? "stdin" : "stdout") + ")");
      }
    }
    check_out_is_not_in(options);
    in.in_format = table_format(options.in_format, options.in);
    in.out_format = table_format(options.out_format, options.out);
    try {
      in.text = read_request_text(options.in);
    } catch (const std::exception&) {
      throw TableError("cannot read the recipe table '" + options.in + "'");
    }
    in.rows = read_recipe_table(in.text, in.in_format);
    in.view = row_plan_view(options);
    if (in.view && in.out_format == TableFormat::kCsv) {
      throw TableError(
          std::string(options.full ? "--full adds the whole plan" : "--view adds the plan") +
          " to JSON rows: use a .json or .jsonl output");
    }
    if (!options.server.empty() && options.chunk == 0) {
      throw TableError("--chunk must be at least 1");
    }
    if (options.retries < 0 || options.retries > kMaxRetries) {
      throw TableError("--retries must be 0 to " + std::to_string(kMaxRetries) + " (got " +
                       std::to_string(options.retries) + ")");
    }
    if (options.give_up_after_s < kMinGiveUpAfterS || options.give_up_after_s > kMaxGiveUpAfterS) {
      throw TableError("--give-up-after must be " + std::to_string(kMinGiveUpAfterS) + " to " +
                       std::to_string(kMaxGiveUpAfterS) + " s (got " +
                       std::to_string(options.give_up_after_s) + ")");
    }
    if (!options.server.empty()) {
      in.client = std::make_unique<HttpClient>(options.server, kServerTimeout);  // checks the URL
      in.client->set_retries(options.retries);
    }
  } catch (const std::exception& e) {
    std::cerr << "slosh batch: " << e.what() << '\n';
    return kExitInvalidInput;
  }
  if (options.mode == "min_time" && in.view) {
    std::cerr << "slosh batch: " << (options.full ? "--full" : "--view")
              << " is for plan tables, not --mode min_time\n";
    return kExitInvalidInput;
  }
  return std::nullopt;
}

}  // namespace slosh::service::batch_cli
