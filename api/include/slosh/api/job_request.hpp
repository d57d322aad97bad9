#pragma once
// The body of POST /v1/batches (SPEC §13), read for the job manager: the recipe table it carries
// (a table's text, or plan requests as a JSON array), the download format and the plan view.
//
// {"requests": [plan requests, each with an optional "recipe_id"]} or {"table": "<recipe table
// text>", "table_format": "csv"|"jsonl"|"json" (default "csv")}, with optional "format":
// "csv"|"jsonl" (default "csv") and "view": "full"|"compact".

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/recipe_row.hpp"

namespace slosh::api {

/// A job's outputs as asked.
struct JobRequest {
  std::string format{"csv"};        ///< of the results download: "csv" or "jsonl"
  std::optional<std::string> view;  ///< "full" or "compact"; nullopt: the figures only
};

/// Reads the recipes of a job body: `table` is the recipe table's text, `table_format` its
/// format ("csv", "jsonl", "json"); `from_requests` when it is the body's plan requests (then a
/// JSON array of 1 to `max` items, already checked). The reader throws ApiError for a table it
/// refuses.
using JobTableReader = std::function<void(const std::string& table, const std::string& table_format,
                                          bool from_requests)>;

/// Parses the body `text` of a job of at most `max` recipes, handing its table to `read_table`
/// before the outputs are checked. Throws ApiError (invalid_value) naming the field: not an
/// object, an unknown member, both or neither of requests and table, table_format with
/// requests, requests not an array of 1 to `max`, table not text, a table_format, format or
/// view not allowed.
[[nodiscard]] JobRequest parse_job_request(const std::string& text, std::size_t max,
                                           const JobTableReader& read_table);

/// A recipe's plan request with the stored calibration put in when its options.model names one:
/// `resolve` maps the request's text to the text with the model put in and throws ApiError for a
/// bad or unknown name; then `request` is null and `error` that error. A request without a named
/// model is left as it is.
void resolve_recipe_model(RecipeRequest& request, std::optional<ApiError>& error,
                          const std::function<std::string(const std::string&)>& resolve);

}  // namespace slosh::api
