#pragma once
// `slosh batch` solving a plan table here, on a PlanEngine of its own.

#include <vector>

#include "cli/batch_row_sink.hpp"
#include "cli/progress_bar.hpp"
#include "config/server_config.hpp"

namespace slosh::service::batch_cli {

/// Solves every readable row on a worker pool (`config.workers`, the plan cache of `config`) and
/// writes the rows to `sink` in input order as they finish, drawing the progress on `bar`.
void run_local(const std::vector<RecipeRow>& rows, ServerConfig config, RowSink& sink,
               ProgressBar& bar);

}  // namespace slosh::service::batch_cli
