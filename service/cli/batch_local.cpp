#include "cli/batch_local.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <utility>

#include "slosh/api/service_bodies.hpp"

namespace slosh::service::batch_cli {

namespace {

/// How often the progress bar is refreshed while waiting for a solve.
constexpr std::chrono::milliseconds kPollInterval{100};

}  // namespace

void run_local(const std::vector<RecipeRow>& rows, ServerConfig config, RowSink& sink,
               ProgressBar& bar) {
  std::vector<std::size_t> slot(rows.size(), static_cast<std::size_t>(-1));
  std::size_t readable = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].error) slot[i] = readable++;
  }
  const std::size_t unreadable = rows.size() - readable;
  // Room for the whole table: submission never blocks, so rows are written as they finish.
  config.queue = std::max<std::size_t>(1, readable);
  PlanEngine engine(config);
  if (const std::string e = engine.cache().storage_error(); !e.empty()) {
    std::cerr << "slosh batch: warning: " << e << '\n';
  }
  std::vector<api::BatchItem> items;
  items.reserve(readable);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (slot[i] != static_cast<std::size_t>(-1)) {
      items.push_back(api::batch_item_of(rows[i].request, engine.config().solve_budget_s));
    }
  }
  const PendingBatch batch = engine.start_batch(std::move(items));
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

}  // namespace slosh::service::batch_cli
