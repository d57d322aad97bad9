// The client side of the batch jobs API in api/ (what `slosh batch --server` reads and sends):
// job records read into typed values, refusals of what is not a record, the rows of a results
// download, and the body that starts a job, checked against texts written out here.

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "slosh/api/batch_job_reply.hpp"
#include "slosh/api/min_time_table.hpp"
#include "slosh/api/plan_table_row.hpp"

namespace slosh {
namespace test_batch_client_json {

TEST(BatchClientJson, AJobRecordIsReadIntoItsTypedFields) {
  const auto p = api::parse_job_progress(
      R"({"id":"ab","state":"cancelled","progress":{"done":7,"total":12,"rate_per_s":3.5},)"
      R"("message":"cancelled by DELETE","cancel_requested":true,"results":{"rows":[]}})");
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->state, api::JobState::kCancelled);
  EXPECT_EQ(p->done, 7u);
  EXPECT_EQ(p->total, 12u);
  EXPECT_EQ(p->message, "cancelled by DELETE");
  EXPECT_TRUE(p->cancel_requested);
  EXPECT_TRUE(api::is_final(p->state));
  // A null message (a running job) reads empty; the states name themselves.
  const auto running =
      api::parse_job_progress(R"({"state":"running","progress":{"done":0},"message":null})");
  ASSERT_TRUE(running.has_value());
  EXPECT_EQ(running->message, "");
  EXPECT_FALSE(running->cancel_requested);
  EXPECT_FALSE(api::is_final(running->state));
  for (const char* name : {"queued", "running", "done", "cancelled", "failed"}) {
    const auto r = api::parse_job_progress(std::string(R"({"state":")") + name +
                                           R"(","progress":{"done":1}})");
    ASSERT_TRUE(r.has_value()) << name;
    EXPECT_EQ(api::to_string(r->state), name);
  }
}

TEST(BatchClientJson, WhatIsNotAJobRecordIsRefused) {
  for (const char* text :
       {"", "not json", "[]", R"({"state":"done"})", R"({"state":"paused","progress":{"done":1}})",
        R"({"state":"done","progress":{"done":-1}})", R"({"state":"done","progress":{"done":1.5}})",
        R"({"state":7,"progress":{"done":1}})", R"({"progress":{"done":1}})"}) {
    EXPECT_FALSE(api::parse_job_progress(text).has_value()) << text;
  }
  EXPECT_EQ(api::parse_job_id(R"({"id":"0123","state":"queued"})"), "0123");
  EXPECT_FALSE(api::parse_job_id(R"({"state":"queued"})").has_value());
  EXPECT_FALSE(api::parse_job_id(R"({"id":12})").has_value());
}

TEST(BatchClientJson, TheJobBodyIsTheTableAsReadWithItsFormatAndView) {
  EXPECT_EQ(api::job_body_text("recipe_id\n\"a\"\n", "csv", std::nullopt),
            R"({"format":"jsonl","table":"recipe_id\n\"a\"\n","table_format":"csv"})");
  EXPECT_EQ(api::job_body_text("[]", "json", std::string("compact")),
            R"({"format":"jsonl","table":"[]","table_format":"json","view":"compact"})");
}

TEST(BatchClientJson, ResultRowsAreReadWithTheirCountsAndABadLineIsNamed) {
  const auto rows = api::parse_table_rows(
      R"({"row":1,"recipe_id":"a","status":"optimal","cached":true})"
      "\n\n"
      R"({"row":2,"recipe_id":"b","status":"error","error":{"code":"invalid_value"}})"
      "\n");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].number, 1u);
  EXPECT_EQ(rows[0].status, "optimal");
  EXPECT_TRUE(rows[0].cached);
  EXPECT_FALSE(rows[0].failed);
  EXPECT_EQ(rows[1].number, 2u);
  EXPECT_TRUE(rows[1].failed);
  EXPECT_FALSE(rows[1].cached);
  EXPECT_EQ(rows[1].document.at("error").at("code"), "invalid_value");
  const auto unnumbered = api::parse_table_rows(R"({"status":"optimal"})");
  ASSERT_EQ(unnumbered.size(), 1u);
  EXPECT_EQ(unnumbered[0].number, 0u);
  EXPECT_EQ(unnumbered[0].number_text, "null");
  try {
    (void)api::parse_table_rows(R"({"row":1,"status":"optimal"})"
                                "\n{\"row\":2}\n");
    ADD_FAILURE() << "a row without a status was read";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "line 2 of the results is not a plan-table row");
  }
}

// An error row of a CSV table names the column (motion_time_s for the search's upper end), and a
// cell with a comma or a quote is quoted as RFC 4180 says.
TEST(BatchClientJson, MinTimeErrorRowsNameTheColumnAndQuoteTheirCells) {
  const api::ApiError e(api::ErrorCode::kInvalidValue, "motion_time_max_s",
                        "motion_time_max_s = -1 is out of range, \"allowed\" 0.05 to 60 s");
  const auto row = api::min_time_error_row(3, "r,3", true, e);
  const std::string line = api::min_time_csv_line(row);
  EXPECT_EQ(line.rfind("3,\"r,3\",error,", 0), 0u) << line;
  EXPECT_NE(line.find(",\"motion_time_s = -1 is out of range, \"\"allowed\"\" 0.05 to 60 s\","
                      "motion_time_s"),
            std::string::npos)
      << line;
  const std::string header = api::min_time_csv_header();
  EXPECT_EQ(std::count(header.begin(), header.end(), ','),
            std::count(line.begin(), line.end(), ',') - 2)
      << "the two quoted commas aside, a cell per column";
  EXPECT_EQ(api::min_time_json_text(api::min_time_error_row(4, "x", false, e)),
            R"({"error_field":"motion_time_max_s","message":"motion_time_max_s = -1 is out of )"
            R"(range, \"allowed\" 0.05 to 60 s","recipe_id":"x","row":4,"status":"error"})");
}

}  // namespace test_batch_client_json
}  // namespace slosh
