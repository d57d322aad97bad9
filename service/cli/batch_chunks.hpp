#pragma once
// `slosh batch --server` through POST /v1/plans/batch in chunks: the way for a service without
// batch jobs, or for a table over its body limit.

#include <vector>

#include "cli/batch_command.hpp"
#include "cli/batch_row_sink.hpp"
#include "cli/http_client.hpp"
#include "cli/progress_bar.hpp"

namespace slosh::service::batch_cli {

/// POSTs the readable rows in chunks of `options.chunk` (503 answers retried) and writes every
/// row to `sink` in input order; BatchAbort when the service answers anything but the results.
void run_remote(const std::vector<RecipeRow>& rows, const BatchCommandOptions& options,
                HttpClient& client, RowSink& sink, ProgressBar& bar);

}  // namespace slosh::service::batch_cli
