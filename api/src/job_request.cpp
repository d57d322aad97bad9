#include "slosh/api/job_request.hpp"

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/service_bodies.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;

void read_table_member(const json& body, const JobTableReader& read_table) {
  const json& text = body["table"];
  if (!text.is_string())
    invalid("table", "table must be the text of a recipe table, got " + show(text));
  std::string format = "csv";
  if (const json* f = given_member(body, "table_format")) {
    format = f->is_string() ? f->get<std::string>() : show(*f);
    if (format != "csv" && format != "jsonl" && format != "json") {
      invalid("table_format", "table_format = " + show(*f) +
                                  " is not allowed: one of \"csv\", \"jsonl\", \"json\"");
    }
  }
  read_table(text.get<std::string>(), format, false);
}

void read_requests_member(const json& requests, std::size_t max, const JobTableReader& read_table) {
  if (!requests.is_array() || requests.empty() || requests.size() > max) {
    invalid("requests", "requests must be an array of 1 to " + std::to_string(max) +
                            " plan requests (batch_job_max), got " +
                            (requests.is_array() ? std::to_string(requests.size()) + " requests"
                                                 : show(requests)));
  }
  // Read as `slosh batch` reads a .json table: each item a plan request, with an optional
  // "recipe_id" that the rows carry.
  read_table(dump_json(requests), "json", true);
}

}  // namespace

JobRequest parse_job_request(const std::string& text, std::size_t max,
                             const JobTableReader& read_table) {
  const json body = parse_json_body(text);
  if (!body.is_object()) {
    invalid("",
            "the body must be an object {\"requests\": [plan requests]} or {\"table\": "
            "\"<recipe table>\", \"table_format\": \"csv\"}");
  }
  reject_unknown_fields(body, "", {"requests", "table", "table_format", "format", "view"});
  // A member given null is absent, as every optional member is.
  const bool has_requests = given_member(body, "requests") != nullptr;
  if (has_requests == (given_member(body, "table") != nullptr)) {
    invalid(has_requests ? "table" : "requests",
            "give either requests (plan requests) or table (a recipe table's text), not " +
                std::string(has_requests ? "both" : "neither"));
  }
  if (has_requests && given_member(body, "table_format") != nullptr) {
    invalid("table_format", "table_format goes with table, not with requests");
  }
  if (has_requests) {
    read_requests_member(body["requests"], max, read_table);
  } else {
    read_table_member(body, read_table);
  }
  JobRequest out;
  if (const json* f = given_member(body, "format")) {
    if (*f != "csv" && *f != "jsonl") {
      invalid("format", "format = " + show(*f) + " is not allowed: one of \"csv\", \"jsonl\"");
    }
    out.format = f->get<std::string>();
  }
  if (const json* v = given_member(body, "view")) {
    (void)batch_view({}, *v);  // 422 naming view unless "full" or "compact"
    out.view = v->get<std::string>();
  }
  return out;
}

void resolve_recipe_model(RecipeRequest& request, std::optional<ApiError>& error,
                          const std::function<std::string(const std::string&)>& resolve) {
  const json& body = request.body();
  const json* options = body.is_object() ? given_member(body, "options") : nullptr;
  const json* model =
      options != nullptr && options->is_object() ? given_member(*options, "model") : nullptr;
  if (model == nullptr || !model->is_string()) return;
  try {
    request = RecipeRequest(json::parse(resolve(dump_json(body))));
  } catch (const ApiError& e) {  // this recipe's row answers the error
    error = e;
    request = RecipeRequest();
  }
}

}  // namespace slosh::api
