#pragma once
// `slosh batch --server` as a batch job of the service (POST /v1/batches): posted once, its
// progress polled, its rows downloaded; cancelled on Ctrl-C or a failure, with the rows it
// finished saved.

#include "cli/batch_command.hpp"
#include "cli/batch_input.hpp"
#include "cli/batch_row_sink.hpp"
#include "cli/http_client.hpp"
#include "cli/progress_bar.hpp"

namespace slosh::service::batch_cli {

/// Runs the table as a batch job of the service: POSTs the table's text, polls the progress,
/// downloads the rows (JSON lines) and writes them to `sink` in the output format. False when the
/// service has no batch jobs (404, 405) or the table is larger than its body limit (413): the
/// caller falls back to POST /v1/plans/batch in chunks. BatchAbort (BatchInterrupted on Ctrl-C)
/// when the run stops.
bool run_job_remote(const BatchInput& in, const BatchCommandOptions& options, HttpClient& client,
                    RowSink& sink, ProgressBar& bar);

}  // namespace slosh::service::batch_cli
