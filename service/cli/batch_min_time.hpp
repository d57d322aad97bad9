#pragma once
// `slosh batch --mode min_time`: each strategy's minimum motion time per recipe, searched here on
// a PlanEngine or by a running service's POST /v1/min-time, written as a table.

#include <cstddef>
#include <ostream>
#include <vector>

#include "cli/http_client.hpp"
#include "config/server_config.hpp"
#include "jobs/recipe_table.hpp"
#include "slosh/api/min_time_table.hpp"

namespace slosh::service::batch_cli {

/// Writes the min_time rows in the table format (the CSV header, or the JSON array's brackets).
class MinTimeWriter {
 public:
  MinTimeWriter(std::ostream& out, TableFormat format);
  void write(const api::MinTimeTableRow& row);
  void finish();

 private:
  std::ostream& out_;
  TableFormat format_;
  std::size_t rows_{0};
};

/// Searches every row on a local PlanEngine (the cache file of `config`, `config.workers`, one
/// task per row and strategy) and writes the rows in input order; the 1-based numbers of the rows
/// in error.
std::vector<std::size_t> run_min_time_local(const std::vector<RecipeRow>& rows, ServerConfig config,
                                            MinTimeWriter& writer);

/// POSTs every readable row to the service's /v1/min-time, one after the other (each request's
/// strategies run in parallel on the service's pool), and writes the rows as they return; the
/// 1-based numbers of the rows in error. BatchAbort when the service answers no envelope.
std::vector<std::size_t> run_min_time_remote(const std::vector<RecipeRow>& rows, HttpClient& client,
                                             MinTimeWriter& writer);

}  // namespace slosh::service::batch_cli
