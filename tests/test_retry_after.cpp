// Every 503 tells the client when to retry: the replies built from an error code (whatever
// endpoint builds them) and the calibration endpoint's refusal on a real server whose background
// queue is full.

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "http/plan_service.hpp"
#include "slosh/api/error.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_retry_after {

using nlohmann::json;

TEST(RetryAfter, EveryReplyOfA503CodeCarriesIt) {
  for (const api::ErrorCodeInfo& info : api::kErrorCodes) {
    const service::Reply built = service::PlanService::error_reply(info.code, "message");
    const service::Reply thrown = service::reply_of(api::ApiError(info.code, "", "message"));
    for (const service::Reply* reply : {&built, &thrown}) {
      EXPECT_EQ(reply->status, api::http_status(info.code));
      int retry_after = 0;
      for (const auto& [name, value] : reply->headers) {
        if (name == "Retry-After") {
          ++retry_after;
          EXPECT_EQ(value, "1") << info.name;
        }
      }
      EXPECT_EQ(retry_after, reply->status == 503 ? 1 : 0) << info.name;
    }
  }
}

// A calibration request on the thesis format: two samples of a measured move (enough to parse;
// the request is refused before it is fitted).
json calibration_body() {
  json t = json::array(), eta = json::array();
  for (int k = 0; k <= 50; ++k) {
    t.push_back(0.02 * k);
    eta.push_back(k < 40 ? 0.1 * k : 4.0 - 0.1 * (k - 40));
  }
  return {{"format", json::parse(R"({"container": {"radius_mm": 48.5, "height_mm": 150},
             "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 0.8})")},
          {"moves", json::array({{{"name", "move"},
                                  {"motion_time_s", 0.8},
                                  {"law", {{"type", "modified_trapezoid"}}},
                                  {"series", {{"t_s", t}, {"eta_mm", eta}}}}})}};
}

TEST(RetryAfter, TheCalibrationEndpointsOverloadedAnswerCarriesIt) {
  // One worker and room for one queued background task: a min-time search (hundreds of ms) holds
  // the worker, a first calibration takes the queue's room, and a second finds none.
  test::Server server({"--workers", "1", "--queue", "1"});
  const json search = json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800},
    "eta_rest_max_mm": 3, "strategies": ["time_domain"]})");
  const auto post = [&server](const std::string& path, const std::string& body) {
    auto client = server.client();
    return client.Post(path, body, "application/json");
  };
  auto client = server.client();
  const auto wait_for = [&client](const std::string& series) {
    for (const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
         std::chrono::steady_clock::now() < deadline;) {
      const auto metrics = client.Get("/metrics");
      if (metrics && test::metric(metrics->body, series) == 1) return true;
    }
    return false;
  };
  auto searching = std::async(std::launch::async, post, "/v1/min-time", search.dump());
  ASSERT_TRUE(wait_for("slosh_busy_workers")) << "the search never started";
  auto queued = std::async(std::launch::async, post, "/v1/calibrations", calibration_body().dump());
  ASSERT_TRUE(wait_for("slosh_pool_background_queue_depth")) << "the calibration never queued";
  const auto refused = post("/v1/calibrations", calibration_body().dump());
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 503) << refused->body;
  EXPECT_EQ(json::parse(refused->body).at("error").at("code"), "overloaded");
  EXPECT_EQ(refused->get_header_value("Retry-After"), "1");
  EXPECT_TRUE(searching.get());
  EXPECT_TRUE(queued.get());
}

}  // namespace test_retry_after
}  // namespace slosh
