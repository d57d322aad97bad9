// The typed seams between service and api: the one error table, stored plans and their replies,
// the batch response writer, and the route table the server registers.

#include <httplib.h>

#include <gtest/gtest.h>

#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/openapi.hpp"
#include "slosh/api/plan_reply.hpp"
#include "slosh/api/routes.hpp"
#include "slosh/api/service_bodies.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_service_types {

using nlohmann::json;

TEST(ErrorCodes, EveryCodeHasOneNameAndAnHttpErrorStatus) {
  std::set<std::string> names;
  for (const api::ErrorCodeInfo& row : api::kErrorCodes) {
    EXPECT_TRUE(names.insert(std::string(row.name)).second) << row.name;
    EXPECT_GE(row.status, 400) << row.name;
    EXPECT_LE(row.status, 599) << row.name;
    EXPECT_EQ(api::to_string(row.code), row.name);
    EXPECT_EQ(api::http_status(row.code), row.status);
  }
  EXPECT_EQ(api::error_code_of_status(400), api::ErrorCode::kBadRequest);
  EXPECT_EQ(api::error_code_of_status(431), api::ErrorCode::kHeadersTooLarge);
  EXPECT_EQ(api::error_code_of_status(418), api::ErrorCode::kBadRequest);
  EXPECT_EQ(api::error_code_of_status(502), api::ErrorCode::kInternal);
}

TEST(ErrorCodes, AnEnvelopeReadsBackAsTheSameError) {
  const api::ApiError e(api::ErrorCode::kOverloaded, "requests", "busy");
  const json envelope = json::parse(api::error_body(e));
  EXPECT_EQ(envelope, json::parse(R"({"error": {"code": "overloaded", "message": "busy",
                                                "field": "requests"}})"));
  const api::ApiError back = api::error_from_json(envelope["error"]);
  EXPECT_EQ(back.code(), e.code());
  EXPECT_EQ(back.field(), e.field());
  EXPECT_STREQ(back.what(), e.what());
  const api::ApiError unknown = api::error_from_json(json{{"code", "nonsense"}});
  EXPECT_EQ(unknown.code(), api::ErrorCode::kInternal);
  EXPECT_STREQ(unknown.what(), "an error without a message");
}

api::PlanRequest thesis_request() {
  return api::parse_plan_request(json::parse(R"({"format": {"container": {"radius_mm": 48.5},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "strategy": "notch"})"));
}

TEST(StoredPlan, TheReplyIsThePlanOfRunPlanWithTheCachedFlagOfTheReply) {
  const api::PlanRequest request = thesis_request();
  const api::StoredPlan stored = api::solve_for_storing(request);
  EXPECT_EQ(stored.status, SolveStatus::kOptimal);
  const json body = json::parse(stored.body);
  EXPECT_FALSE(body.contains("cached"));
  EXPECT_FALSE(body.contains("series"));
  json expected = api::run_plan(request);  // the independent path: plan + render in one go
  expected.erase("solver");                // solve_ms differs between two solves
  for (const bool cached : {false, true}) {
    json reply = json::parse(api::render_plan_reply(stored.body, cached));
    EXPECT_EQ(reply["cached"], cached);
    reply["cached"] = false;
    reply.erase("solver");
    EXPECT_EQ(reply, expected);
  }
}

TEST(StoredPlan, TheReplyWithAPeriodCarriesTheSeriesOfThatPeriod) {
  api::PlanRequest request = thesis_request();
  const api::StoredPlan stored = api::solve_for_storing(request);
  const json reply = json::parse(api::render_plan_reply(stored.body, true, &request, 0.01));
  EXPECT_EQ(reply["cached"], true);
  ASSERT_TRUE(reply.contains("series"));
  const json& t = reply["series"]["t_s"];
  ASSERT_GT(t.size(), 10u);
  EXPECT_NEAR(t[1].get<double>() - t[0].get<double>(), 0.01, 1e-12);
}

TEST(StoredPlan, OnlyAnswersThatDependOnTheRecipeAloneAreKept) {
  EXPECT_TRUE(api::is_cacheable(SolveStatus::kOptimal));
  EXPECT_TRUE(api::is_cacheable(SolveStatus::kAcceptable));
  EXPECT_TRUE(api::is_cacheable(SolveStatus::kInfeasible));
  EXPECT_FALSE(api::is_cacheable(SolveStatus::kTimeLimit));
  EXPECT_FALSE(api::is_cacheable(SolveStatus::kFailed));
}

TEST(BatchReplyWriter, ItemsInOrderErrorsWithTheirItemPathAndTheSizeLimit) {
  api::BatchReplyWriter writer(1 << 20);
  writer.add_plan(0, R"({"key":"a"})");
  writer.add_error(1, api::ApiError(api::ErrorCode::kInvalidValue, "format.stroke_mm", "bad"));
  writer.add_error(2, api::ApiError(api::ErrorCode::kCancelled, "", "gone"));
  EXPECT_EQ(json::parse(writer.finish()), json::parse(R"({"results": [
      {"index": 0, "plan": {"key": "a"}},
      {"index": 1, "error": {"code": "invalid_value", "message": "bad",
                             "field": "requests[1].format.stroke_mm"}},
      {"index": 2, "error": {"code": "cancelled", "message": "gone", "field": "requests[2]"}}]})"));
  api::BatchReplyWriter small(20);
  small.add_plan(0, "{}");
  try {
    small.add_plan(1, std::string(40, ' '));
    FAIL() << "a response over the limit was written";
  } catch (const api::ApiError& e) {
    EXPECT_EQ(e.field(), "requests");
    EXPECT_EQ(std::string(e.what()),
              "the plans of this batch exceed the response limit of 20 bytes at requests[1]; the "
              "plans are cached: send fewer requests per batch");
  }
}

// An item's message names the request paths inside the batch as its field does, each of them
// (a refusal may name two members), and only whole paths; the CLI reads back the row's own.
TEST(BatchReplyWriter, MessagesNameThePathsInsideTheBatchAndReadBackAsTheRowsOwn) {
  const std::string both =
      "format.container.radius_mm and format.container.length_mm are both given: a container is "
      "a cylinder (radius_mm) or rectangular (format.container.shape = \"rectangular\" with "
      "length_mm, width_mm and orientation_deg), not both";
  api::BatchReplyWriter writer(1 << 20);
  writer.add_error(
      3, api::ApiError(api::ErrorCode::kInvalidValue, "format.container.length_mm", both));
  writer.add_error(4, api::ApiError(api::ErrorCode::kInvalidValue, "strategy",
                                    "strategy = \"fast\" is not allowed: the plan's options. "
                                    "Its format.x stays"));
  const std::string text = writer.finish();
  const json out = json::parse(text);
  EXPECT_EQ(out["results"][0]["error"]["message"],
            "requests[3].format.container.radius_mm and requests[3].format.container.length_mm "
            "are both given: a container is a cylinder (radius_mm) or rectangular "
            "(requests[3].format.container.shape = \"rectangular\" with length_mm, width_mm and "
            "orientation_deg), not both");
  EXPECT_EQ(out["results"][1]["error"]["message"],
            "requests[4].strategy = \"fast\" is not allowed: the plan's options. Its "
            "requests[4].format.x stays");
  const auto items = api::parse_batch_reply(text);
  ASSERT_TRUE(items);
  ASSERT_EQ(items->size(), 2u);
  ASSERT_TRUE((*items)[0].error);
  EXPECT_EQ((*items)[0].error->field(), "format.container.length_mm");
  EXPECT_EQ(std::string((*items)[0].error->what()), both);
  EXPECT_EQ((*items)[1].error->field(), "strategy");
}

// A value the message echoes stays as it was sent, even when it reads like a path: only the
// message's own words are read inside the batch, and only those are read back.
TEST(BatchReplyWriter, ValuesTheMessageEchoesStayAsSent) {
  const std::string fluid =
      "format.fluid = \"requests[0].format.stroke_mm \\\"options.x\\\"\" is not in the "
      "catalogue; see format.fluid";
  api::BatchReplyWriter writer(1 << 20);
  writer.add_error(0, api::ApiError(api::ErrorCode::kInvalidValue, "format.fluid", fluid));
  const std::string text = writer.finish();
  EXPECT_EQ(json::parse(text)["results"][0]["error"]["message"],
            "requests[0].format.fluid = \"requests[0].format.stroke_mm \\\"options.x\\\"\" is "
            "not in the catalogue; see requests[0].format.fluid");
  const auto items = api::parse_batch_reply(text);
  ASSERT_TRUE(items);
  ASSERT_TRUE((*items)[0].error);
  EXPECT_EQ(std::string((*items)[0].error->what()), fluid);
}

TEST(Routes, TheServerAnswersEveryRouteAndTheDocumentListsEachOnce) {
  const json doc = api::openapi_document("test");
  std::size_t operations = 0;
  for (const auto& [path, methods] : doc["paths"].items()) operations += methods.size();
  EXPECT_EQ(operations, api::routes().size());
  test::Server server({"--workers", "1"});
  httplib::Client client = server.client();
  for (const api::Route& route : api::routes()) {
    std::string path(route.path);
    if (const auto at = path.find("{key}"); at != std::string::npos) {
      path.replace(at, 5, "0123456789abcdef");
    }
    if (const auto at = path.find("{name}"); at != std::string::npos) path.replace(at, 6, "app.js");
    std::string method(route.method);
    for (char& c : method) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    EXPECT_TRUE(doc["paths"].contains(std::string(route.path)) &&
                doc["paths"][std::string(route.path)].contains(method))
        << route.method << " " << route.path;
    if (const auto at = path.find("{id}"); at != std::string::npos) path.replace(at, 4, "0123");
    const auto res = route.method == "GET"      ? client.Get(path)
                     : route.method == "DELETE" ? client.Delete(path)
                                                : client.Post(path, "{}", "application/json");
    ASSERT_TRUE(res) << route.path;
    // Routed: the handler answered (a 404 only as "no plan with key" or "no batch job", never
    // "no endpoint").
    EXPECT_EQ(res->body.find("no endpoint"), std::string::npos) << route.path << ": " << res->body;
    EXPECT_NE(res->status, 405) << route.path;
  }
}

}  // namespace test_service_types
}  // namespace slosh
