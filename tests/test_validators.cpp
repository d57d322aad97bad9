// Validators name bytes (docs/service.md, "Rendered views and gzip"): a 304 carries the ETag the
// 200 would have carried for the same request (the `;gzip` tag for a client that accepts gzip),
// and a plan with series names its sample period exactly, so two periods never share a tag. An
// out-of-range value is quoted so that it visibly lies outside the range it is refused against.
// Real server on loopback.

#include <httplib.h>
#include <zlib.h>

#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "support/server.hpp"

namespace slosh {
namespace test_validators {

using nlohmann::json;

json thesis(const std::string& strategy) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}})");
  body["strategy"] = strategy;
  return body;
}

// A client that sends exactly the headers given (no Accept-Encoding of its own, no inflating).
httplib::Client raw_client(const test::Server& server) {
  httplib::Client c = server.client();
  c.set_decompress(false);
  return c;
}

TEST(Validators, A304ToAGzipClientCarriesTheGzipTag) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client c = raw_client(server);
  const auto made = c.Post("/v1/plans", thesis("notch").dump(), "application/json");
  ASSERT_TRUE(made);
  ASSERT_EQ(made->status, 200) << made->body;
  const std::string key = json::parse(made->body).at("key");
  const std::string coded = "\"" + key + ";gzip\"";
  const httplib::Headers gzip{{"Accept-Encoding", "gzip"}};
  const auto full = c.Get("/v1/plans/" + key, gzip);
  ASSERT_TRUE(full);
  ASSERT_EQ(full->status, 200);
  ASSERT_EQ(full->get_header_value("Content-Encoding"), "gzip");
  EXPECT_EQ(full->get_header_value("ETag"), coded);
  const auto again =
      c.Get("/v1/plans/" + key, {{"Accept-Encoding", "gzip"}, {"If-None-Match", coded}});
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
  EXPECT_EQ(again->get_header_value("ETag"), coded);
  EXPECT_EQ(again->get_header_value("Vary"), "Accept-Encoding");
  // The same for POST and for the page.
  const auto posted = c.Post("/v1/plans", {{"Accept-Encoding", "gzip"}, {"If-None-Match", coded}},
                             thesis("notch").dump(), "application/json");
  ASSERT_TRUE(posted);
  EXPECT_EQ(posted->status, 304);
  EXPECT_EQ(posted->get_header_value("ETag"), coded);
  const auto page = c.Get("/", gzip);
  ASSERT_TRUE(page);
  ASSERT_EQ(page->get_header_value("Content-Encoding"), "gzip");
  const std::string page_tag = page->get_header_value("ETag");
  const auto page_again = c.Get("/", {{"Accept-Encoding", "gzip"}, {"If-None-Match", page_tag}});
  ASSERT_TRUE(page_again);
  EXPECT_EQ(page_again->status, 304);
  EXPECT_EQ(page_again->get_header_value("ETag"), page_tag);
  // A client without gzip still gets the identity tag on its 304.
  const auto identity = c.Get("/v1/plans/" + key, {{"If-None-Match", coded}});
  ASSERT_TRUE(identity);
  EXPECT_EQ(identity->status, 304);
  EXPECT_EQ(identity->get_header_value("ETag"), "\"" + key + "\"");
}

TEST(Validators, TwoSamplePeriodsNeverShareASeriesTag) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client c = raw_client(server);
  json a = thesis("notch");
  a["sample_period_s"] = 0.0012345678901;
  json b = thesis("notch");
  b["sample_period_s"] = 0.00123456789012;
  const auto ra = c.Post("/v1/plans", a.dump(), "application/json");
  const auto rb = c.Post("/v1/plans", b.dump(), "application/json");
  ASSERT_TRUE(ra && rb);
  ASSERT_EQ(ra->status, 200) << ra->body;
  ASSERT_EQ(rb->status, 200) << rb->body;
  const std::string key = json::parse(ra->body).at("key");
  EXPECT_EQ(ra->get_header_value("ETag"), "\"" + key + ";series=0.0012345678901\"");
  EXPECT_EQ(rb->get_header_value("ETag"), "\"" + key + ";series=0.00123456789012\"");
  // b's body was never seen under a's tag: a full answer, not a 304.
  const auto cond = c.Post("/v1/plans", {{"If-None-Match", ra->get_header_value("ETag")}}, b.dump(),
                           "application/json");
  ASSERT_TRUE(cond);
  EXPECT_EQ(cond->status, 200);
  // A period that 10 digits show exactly keeps its short tag.
  json c3 = thesis("notch");
  c3["sample_period_s"] = 0.001;
  const auto r3 = c.Post("/v1/plans", c3.dump(), "application/json");
  ASSERT_TRUE(r3);
  EXPECT_EQ(r3->get_header_value("ETag"), "\"" + key + ";series=0.001\"");
}

TEST(Validators, AnOutOfRangeValueIsQuotedSoThatItLiesOutsideTheRange) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  json body = thesis("notch");
  body.erase("strategy");
  body["format"]["motion_time_s"] = 0.21;
  body["format"]["stroke_mm"] = 100;
  body["law"] = {
      {"type", "seven_segment"},
      {"durations_s", {0.04999999999999999, 0.0, 0.05, 0.01000000000000001, 0.05, 0.0, 0.05}}};
  const auto r = server.client().Post("/v1/simulate", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 422) << r->body;
  EXPECT_EQ(json::parse(r->body)["error"]["message"],
            "law.durations_s[0] = 0.04999999999999999 is out of range: allowed 0.05 to 0.21 s "
            "(segment 1 is a jerk ramp: >= options.min_ramp_s)");
  body["law"]["durations_s"][0] = 0.05;
  body["format"]["motion_time_s"] = 0.0499999999999999;
  const auto t = server.client().Post("/v1/simulate", body.dump(), "application/json");
  ASSERT_TRUE(t);
  EXPECT_EQ(json::parse(t->body)["error"]["message"],
            "format.motion_time_s = 0.0499999999999999 is out of range: allowed 0.05 to 60 s");
}

// Inflates a gzip member with zlib's own reader (the test's independent side of the coding).
std::string gunzip(const std::string& data) {
  z_stream stream{};
  EXPECT_EQ(inflateInit2(&stream, 15 + 16), Z_OK);
  std::string out;
  char buffer[16384];
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  stream.avail_in = static_cast<uInt>(data.size());
  int rc = Z_OK;
  while (rc == Z_OK) {
    stream.next_out = reinterpret_cast<Bytef*>(buffer);
    stream.avail_out = sizeof buffer;
    rc = inflate(&stream, Z_NO_FLUSH);
    out.append(buffer, sizeof buffer - stream.avail_out);
  }
  EXPECT_EQ(rc, Z_STREAM_END);
  inflateEnd(&stream);
  return out;
}

// The cam table, the largest body the service sends, is gzip-coded for a client that accepts it
// and inflates to the identity table byte for byte.
TEST(Validators, ACamTableIsGzipCodedForAGzipClient) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client c = raw_client(server);
  const auto made = c.Post("/v1/plans", thesis("notch").dump(), "application/json");
  ASSERT_TRUE(made);
  const std::string path =
      "/v1/plans/" + json::parse(made->body).at("key").get<std::string>() + "/cam.csv";
  const auto identity = c.Get(path);
  ASSERT_TRUE(identity);
  ASSERT_EQ(identity->status, 200) << identity->body.substr(0, 200);
  EXPECT_EQ(identity->get_header_value("Content-Encoding"), "");
  EXPECT_EQ(identity->get_header_value("Vary"), "Accept-Encoding");
  const auto coded = c.Get(path, {{"Accept-Encoding", "gzip"}});
  ASSERT_TRUE(coded);
  ASSERT_EQ(coded->status, 200);
  EXPECT_EQ(coded->get_header_value("Content-Encoding"), "gzip");
  EXPECT_LT(coded->body.size(), identity->body.size() / 2);
  EXPECT_EQ(gunzip(coded->body), identity->body);
}

}  // namespace test_validators
}  // namespace slosh
