#pragma once
// The body of the two recipe-table fuzz targets (fuzz_recipe_csv.cpp, fuzz_recipe_jsonl.cpp):
// what `slosh batch` does with a table short of solving. The table is read
// (service::read_recipe_table), every readable row goes through PlanService::start_batch (its
// validation, budget and recipe key; the service is shut down, so a valid row is refused instead
// of being solved), and every row is rendered as a plan-table row in CSV, JSON lines and JSON.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "http/plan_service.hpp"
#include "jobs/plan_table.hpp"
#include "jobs/recipe_table.hpp"

namespace slosh::fuzz {

inline service::PlanService& shut_down_service() {
  static const std::unique_ptr<service::PlanService> instance = [] {
    service::ServerConfig config;
    config.workers = 1;
    config.queue = 1;
    config.cache_path.clear();  // memory only: nothing written to disk
    auto s = std::make_unique<service::PlanService>(config);
    s->begin_shutdown();
    return s;
  }();
  return *instance;
}

inline void run_recipe_table(const std::uint8_t* data, std::size_t size,
                             service::TableFormat format) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<service::RecipeRow> rows;
  try {
    rows = service::read_recipe_table(text, format);
  } catch (const service::TableError& e) {
    require(std::string(e.what()).rfind("recipe table: ", 0) == 0,
            "a table error names the recipe table");
    return;  // nothing is planned (exit 2)
  }
  // As batch_command.cpp's run_local: readable rows are planned, the others keep their error.
  std::vector<api::BatchItem> items;
  std::vector<std::size_t> slot(rows.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    require(rows[i].row == i + 1, "rows are numbered in input order");
    if (rows[i].error) continue;
    slot[i] = items.size();
    items.push_back(
        api::batch_item_of(rows[i].request, shut_down_service().engine().config().solve_budget_s));
  }
  service::PlanService& service = shut_down_service();
  const service::PendingBatch batch = service.start_batch(std::move(items));
  std::ostringstream csv, jsonl, json;
  service::PlanTableWriter csv_writer(csv, service::TableFormat::kCsv);
  service::PlanTableWriter jsonl_writer(jsonl, service::TableFormat::kJsonLines);
  service::PlanTableWriter json_writer(json, service::TableFormat::kJson);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    service::BatchResult result;
    if (slot[i] == rows.size()) {
      result.error = rows[i].error;
    } else {
      require(batch.wait_for(slot[i], std::chrono::milliseconds(0)), "nothing was queued");
      result = batch.get(slot[i]);
    }
    require(!result.ok(), "a shut-down service plans nothing");
    const std::string code = api::to_string(result.error->code());
    require(code == "invalid_value" || code == "malformed_json" || code == "overloaded",
            "a recipe fails as invalid_value or malformed_json (or is refused), never internal");
    const api::PlanTableRow row = service::plan_row(rows[i], result, std::nullopt);
    require(row.failed && row.document["message"].is_string(), "an error row has a message");
    csv_writer.write(row);
    jsonl_writer.write(row);
    json_writer.write(row);
  }
  json_writer.finish();
  require(!nlohmann::json::parse(json.str(), nullptr, false).is_discarded(),
          "the JSON plan table is valid JSON");
}

}  // namespace slosh::fuzz
