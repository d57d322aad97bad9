#pragma once
// The recipe table of `slosh batch` and the options that shape its output, read and checked
// before anything is solved or posted.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/batch_command.hpp"
#include "cli/http_client.hpp"
#include "jobs/recipe_table.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::service::batch_cli {

// The recipe table and where its plans go; an exit code after a message when they are unusable.
struct BatchInput {
  std::string text;  // the table as read (sent to the service's batch jobs)
  TableFormat in_format{};
  std::vector<RecipeRow> rows;
  TableFormat out_format{};
  std::optional<api::PlanView> view;  // of the plan added to each JSON row (--full, --view)
  std::unique_ptr<HttpClient> client;
};

/// Reads the table and checks the options into `in`; an exit code (kExitInvalidInput) after a
/// message on stderr when they are unusable, nullopt when the run can go on.
std::optional<int> read_batch_input(const BatchCommandOptions& options, BatchInput& in);

}  // namespace slosh::service::batch_cli
