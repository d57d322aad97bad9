// The cached serve path (SPEC §8): a cached plan's compact view and gzip coding are rendered once
// and served from memory; the bytes are exactly those rendered fresh from the plan, the gzip body
// inflates to the identity body, every reply that could be coded says Vary: Accept-Encoding, and
// nothing is coded for a client that did not ask. Checked on a real server over raw sockets (an
// HTTP client library would negotiate and inflate on its own).

#include <gtest/gtest.h>
#include <zlib.h>

#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "cache/plan_cache.hpp"
#include "http/gzip.hpp"
#include "slosh/api/plan_view.hpp"
#include "support/raw_client.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_serving {

using nlohmann::json;

const std::string kRecipe =
    R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,)"
    R"( "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}, "strategy": "notch"})";

struct RawReply {
  int status{};
  std::map<std::string, std::string> headers;  // lower-case names
  std::string body;
};

// One request on its own connection (Connection: close), the answer split by hand.
RawReply exchange(int port, const std::string& method, const std::string& target,
                  const std::string& body, const std::string& extra_headers = "") {
  test::Raw raw(port);
  EXPECT_TRUE(raw.connected());
  std::string request = method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" +
                        "Connection: close\r\n" + extra_headers;
  if (method == "POST") {
    request +=
        "Content-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) + "\r\n";
  }
  request += "\r\n" + body;
  EXPECT_TRUE(raw.send(request));
  const std::string text = raw.read_all();
  RawReply reply;
  const std::size_t end = text.find("\r\n\r\n");
  EXPECT_NE(end, std::string::npos) << text;
  if (end == std::string::npos) return reply;
  reply.status = std::stoi(text.substr(9, 3));
  std::size_t at = text.find("\r\n") + 2;
  while (at < end) {
    const std::size_t eol = text.find("\r\n", at);
    const std::string line = text.substr(at, eol - at);
    const std::size_t colon = line.find(':');
    std::string name = line.substr(0, colon);
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    reply.headers[name] = line.substr(line.find_first_not_of(' ', colon + 1));
    at = eol + 2;
  }
  reply.body = text.substr(end + 4);
  if (reply.status == 304) {
    // No body, and no Content-Length but the 200's (RFC 9110 8.6): the service sends none.
    EXPECT_EQ(reply.body, "");
    EXPECT_EQ(reply.headers.count("content-length"), 0U);
    return reply;
  }
  EXPECT_EQ(reply.body.size(), std::stoul(reply.headers["content-length"]));
  return reply;
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
  EXPECT_EQ(stream.avail_in, 0U);  // one member, nothing after it
  inflateEnd(&stream);
  return out;
}

// The reply text of `plan` with its leading `"cached":false` member turned true.
std::string as_cached(std::string plan) {
  const std::string from = R"({"cached":false,)";
  EXPECT_EQ(plan.rfind(from, 0), 0U) << plan.substr(0, 40);
  return R"({"cached":true,)" + plan.substr(from.size());
}

TEST(Serving, CachedCompactViewIsTheViewRenderedFromTheFreshPlan) {
  const test::Server server;
  const RawReply fresh = exchange(server.port(), "POST", "/v1/plans", kRecipe);
  ASSERT_EQ(fresh.status, 200) << fresh.body;
  EXPECT_EQ(fresh.headers.at("x-cache"), "miss");
  const std::string key = json::parse(fresh.body).at("key");
  // The compact view of the plan as a hit would say it, rendered here from the full text.
  const std::string expected = api::compact_plan_text(as_cached(fresh.body));
  for (int i = 0; i < 2; ++i) {  // the first hit may render the views, the second finds them
    const RawReply post = exchange(server.port(), "POST", "/v1/plans?view=compact", kRecipe);
    EXPECT_EQ(post.headers.at("x-cache"), "hit");
    EXPECT_EQ(post.body, expected);
    const RawReply get = exchange(server.port(), "GET", "/v1/plans/" + key + "?view=compact", "");
    EXPECT_EQ(get.body, expected);
    EXPECT_EQ(get.headers.at("etag"), "\"" + key + ";view=compact\"");
  }
  // The full plan of a hit is the fresh one, cached.
  EXPECT_EQ(exchange(server.port(), "POST", "/v1/plans", kRecipe).body, as_cached(fresh.body));
}

TEST(Serving, CompactViewOfAPlanLoadedFromTheStoreAfterARestart) {
  const test::TempDir dir;
  std::string fresh;
  {
    test::Server first({}, &dir);
    fresh = exchange(first.port(), "POST", "/v1/plans", kRecipe).body;
    ASSERT_EQ(first.stop(), 0);
  }
  const test::Server second({}, &dir);
  const RawReply compact = exchange(second.port(), "POST", "/v1/plans?view=compact", kRecipe);
  EXPECT_EQ(compact.headers.at("x-cache"), "hit");
  EXPECT_EQ(compact.body, api::compact_plan_text(as_cached(fresh)));
}

// `"<tag>"` -> `"<tag>;gzip"`, the entity tag of a body's gzip coding, written out here.
std::string with_gzip_suffix(const std::string& tag) {
  EXPECT_TRUE(tag.size() >= 2 && tag.front() == '"' && tag.back() == '"') << tag;
  return tag.substr(0, tag.size() - 1) + ";gzip\"";
}

TEST(Serving, GzipBodyInflatesToTheIdentityBody) {
  const test::Server server;
  const RawReply fresh =
      exchange(server.port(), "POST", "/v1/plans", kRecipe, "Accept-Encoding: gzip\r\n");
  ASSERT_EQ(fresh.status, 200);
  // A fresh plan is coded per response.
  EXPECT_EQ(fresh.headers.at("content-encoding"), "gzip");
  EXPECT_EQ(fresh.headers.at("vary"), "Accept-Encoding");
  const std::string fresh_plan = gunzip(fresh.body);
  EXPECT_EQ(json::parse(fresh_plan).at("cached"), false);

  const RawReply identity = exchange(server.port(), "POST", "/v1/plans", kRecipe);
  EXPECT_EQ(identity.headers.count("content-encoding"), 0U);
  EXPECT_EQ(identity.headers.at("vary"), "Accept-Encoding");
  EXPECT_EQ(identity.body, as_cached(fresh_plan));
  for (const char* accept : {"gzip", "deflate, gzip;q=0.5", "br, gzip, deflate", "*"}) {
    const RawReply coded = exchange(server.port(), "POST", "/v1/plans", kRecipe,
                                    std::string("Accept-Encoding: ") + accept + "\r\n");
    EXPECT_EQ(coded.headers.at("x-cache"), "hit");
    EXPECT_EQ(coded.headers.at("content-encoding"), "gzip") << accept;
    EXPECT_EQ(coded.headers.at("vary"), "Accept-Encoding");
    // A strong tag names bytes: the coded body has its own (RFC 9110 8.8.3.3).
    EXPECT_EQ(coded.headers.at("etag"), with_gzip_suffix(identity.headers.at("etag")));
    EXPECT_LT(coded.body.size(), identity.body.size() / 2);
    EXPECT_EQ(gunzip(coded.body), identity.body) << accept;
  }
  // Codings the client refuses or the service does not offer: identity.
  for (const char* accept : {"gzip;q=0", "br", "identity", "*;q=0", "deflate"}) {
    const RawReply plain = exchange(server.port(), "POST", "/v1/plans", kRecipe,
                                    std::string("Accept-Encoding: ") + accept + "\r\n");
    EXPECT_EQ(plain.headers.count("content-encoding"), 0U) << accept;
    EXPECT_EQ(plain.body, identity.body) << accept;
  }
  // A revalidation in either coding is a 304 for either coding's tag (the body is the same).
  for (const std::string& tag :
       {identity.headers.at("etag"), with_gzip_suffix(identity.headers.at("etag"))}) {
    for (const char* accept : {"gzip", "identity"}) {
      const RawReply revalidated = exchange(
          server.port(), "POST", "/v1/plans", kRecipe,
          std::string("Accept-Encoding: ") + accept + "\r\nIf-None-Match: " + tag + "\r\n");
      EXPECT_EQ(revalidated.status, 304) << tag << " " << accept;
      EXPECT_EQ(revalidated.headers.at("vary"), "Accept-Encoding");
    }
  }
  // Another plan's coded tag is not this one's.
  const RawReply other = exchange(server.port(), "POST", "/v1/plans", kRecipe,
                                  "If-None-Match: \"0123;gzip\", \"x\"\r\n");
  EXPECT_EQ(other.status, 200);
}

TEST(Serving, LargeBodiesOfOtherEndpointsAreCodedOnlyWhenAccepted) {
  const test::Server server;
  const RawReply plain = exchange(server.port(), "GET", "/v1/openapi.json", "");
  ASSERT_GT(plain.body.size(), service::kGzipMinBytes);
  EXPECT_EQ(plain.headers.count("content-encoding"), 0U);
  EXPECT_EQ(plain.headers.at("vary"), "Accept-Encoding");
  const RawReply coded =
      exchange(server.port(), "GET", "/v1/openapi.json", "", "Accept-Encoding: gzip\r\n");
  EXPECT_EQ(coded.headers.at("content-encoding"), "gzip");
  EXPECT_EQ(gunzip(coded.body), plain.body);
  // A small body stays as it is (the coding would cost more than it saves).
  const RawReply health =
      exchange(server.port(), "GET", "/healthz", "", "Accept-Encoding: gzip\r\n");
  ASSERT_LT(health.body.size(), service::kGzipMinBytes);
  EXPECT_EQ(health.headers.count("content-encoding"), 0U);
  EXPECT_TRUE(json::accept(health.body)) << health.body;
}

// The web page's files are coded once and kept: every coded answer is the same bytes, which
// inflate to the identity body; the headers of the page stay those of the file, and the ETag is the
// file's with the coding named.
TEST(Serving, WebAssetsAreCodedOnceAndInflateToTheFile) {
  const test::Server server;
  for (const char* path : {"/", "/assets/app.js", "/assets/style.css"}) {
    const RawReply plain = exchange(server.port(), "GET", path, "");
    ASSERT_EQ(plain.status, 200) << path;
    ASSERT_GE(plain.body.size(), service::kGzipMinBytes) << path;
    EXPECT_EQ(plain.headers.count("content-encoding"), 0U) << path;
    const RawReply first = exchange(server.port(), "GET", path, "", "Accept-Encoding: gzip\r\n");
    const RawReply again = exchange(server.port(), "GET", path, "", "Accept-Encoding: gzip\r\n");
    EXPECT_EQ(first.headers.at("content-encoding"), "gzip") << path;
    EXPECT_EQ(first.headers.at("vary"), "Accept-Encoding") << path;
    EXPECT_EQ(first.headers.at("etag"), with_gzip_suffix(plain.headers.at("etag"))) << path;
    EXPECT_EQ(first.headers.at("content-type"), plain.headers.at("content-type")) << path;
    EXPECT_EQ(first.body, again.body) << path;
    EXPECT_EQ(gunzip(first.body), plain.body) << path;
    // The coding of one response (level 1), computed here: the kept bytes are those.
    EXPECT_EQ(first.body, service::gzip_compress(plain.body, service::kResponseGzipLevel)) << path;
  }
}

TEST(Serving, AcceptEncodingFollowsItsQualityValues) {
  using service::accepts_gzip;
  EXPECT_TRUE(accepts_gzip("gzip"));
  EXPECT_TRUE(accepts_gzip(" GZip ; q=0.3 "));
  EXPECT_TRUE(accepts_gzip("deflate, x-gzip"));
  EXPECT_TRUE(accepts_gzip("br;q=1, *;q=0.1"));
  EXPECT_FALSE(accepts_gzip(""));
  EXPECT_FALSE(accepts_gzip("br, deflate"));
  EXPECT_FALSE(accepts_gzip("gzip;q=0"));
  EXPECT_FALSE(accepts_gzip("gzip;q=0.000"));
  EXPECT_FALSE(accepts_gzip("*, gzip;q=0"));  // the named coding decides over "*"
  EXPECT_FALSE(accepts_gzip("gzipped"));
}

TEST(Serving, GzipIsDeterministicAndInflatesBack) {
  std::string text;
  for (int i = 0; i < 3000; ++i) text += std::to_string(i * 0.37) + ",";
  const std::string coded = service::gzip_compress(text);
  EXPECT_EQ(coded, service::gzip_compress(text));  // no time stamp in the header
  EXPECT_EQ(gunzip(coded), text);
  EXPECT_EQ(gunzip(service::gzip_compress("")), "");
}

// The memory tier's one bound holds the values and what is rendered from them: a rendering is
// made once, counted while its value is resident, and evicts the least recent values beyond the
// bound; a replaced value loses its renderings, and a value memory does not keep is rendered for
// its caller alone.
TEST(Serving, RenderingsCountInTheMemoryTiersOneBound) {
  const std::string value(1000, 'v');
  service::PlanCache cache(
      service::CacheConfig{.path = "", .memory_entries = 10, .memory_bytes = 4 * 1001});
  for (const char* key : {"b", "c", "a"}) cache.put(key, value);
  EXPECT_EQ(cache.stats().memory_bytes, 3 * 1001U);
  int renders = 0;
  const auto render = [&renders](const std::string& v) {
    ++renders;
    return std::string(1500, 'r') + v.substr(0, 1);
  };
  const auto a = cache.find("a");
  ASSERT_NE(a, nullptr);
  const std::string& text = cache.rendering(a, 1, render);
  EXPECT_EQ(text, std::string(1500, 'r') + "v");
  EXPECT_EQ(&cache.rendering(a, 1, render), &text);  // kept: rendered once
  EXPECT_EQ(renders, 1);
  // 3 003 + 1 501 bytes exceed 4 004: the least recent value ("b") went.
  EXPECT_FALSE(cache.in_memory("b"));
  EXPECT_TRUE(cache.in_memory("a"));
  EXPECT_TRUE(cache.in_memory("c"));
  EXPECT_EQ(cache.stats().memory_bytes, 2 * 1001U + 1501U);
  // A replaced value starts without renderings; the old one's bytes are no longer counted.
  cache.put("a", value);
  EXPECT_EQ(cache.stats().memory_bytes, 2 * 1001U);
  (void)cache.rendering(cache.find("a"), 1, render);
  EXPECT_EQ(renders, 2);
  // A rendering that throws leaves its slot empty: the next use renders it.
  const auto c = cache.find("c");
  EXPECT_THROW((void)cache.rendering(c, 0,
                                     [](const std::string&) -> std::string {
                                       throw std::runtime_error("out of memory");
                                     }),
               std::runtime_error);
  EXPECT_EQ(cache.rendering(c, 0, render).size(), 1501U);
  // Without a memory tier a value read from the store is rendered for its caller alone.
  const test::TempDir dir;
  service::PlanCache store(
      service::CacheConfig{.path = (dir / "plans.sqlite").string(), .memory_entries = 0});
  store.put("a", value);
  for (int i = 0; i < 2; ++i) {
    const auto lone = store.find("a");
    ASSERT_NE(lone, nullptr);
    EXPECT_EQ(store.rendering(lone, 2, render).size(), 1501U);
    EXPECT_EQ(store.stats().memory_bytes, 0U);
  }
  EXPECT_EQ(renders, 5);  // 2 above, "c" once, and once per read of the store
}

// Each view of a cached plan is rendered when a request first asks for it, and only it: the memory
// tier grows by exactly the bytes of the body that hit answered (read from /readyz).
TEST(Serving, EachViewIsRenderedAtItsFirstHitAndOnlyIt) {
  const test::Server server;
  const auto memory_bytes = [&server] {
    const RawReply ready = exchange(server.port(), "GET", "/readyz", "");
    return json::parse(ready.body).at("cache").at("memory_bytes").get<std::size_t>();
  };
  const RawReply fresh = exchange(server.port(), "POST", "/v1/plans", kRecipe);
  ASSERT_EQ(fresh.status, 200);
  const std::size_t stored = memory_bytes();  // the key and the stored plan, nothing rendered
  const RawReply full = exchange(server.port(), "POST", "/v1/plans", kRecipe);
  EXPECT_EQ(full.headers.at("x-cache"), "hit");
  // A hit keeps the plan's strategy and status (a line each), never the full plan a second time.
  const json plan = json::parse(full.body);
  const std::size_t plain = memory_bytes();
  EXPECT_EQ(plain, stored + plan.at("strategy").get<std::string>().size() + 1 +
                       plan.at("status").get<std::string>().size());
  const RawReply compact = exchange(server.port(), "POST", "/v1/plans?view=compact", kRecipe);
  EXPECT_EQ(compact.headers.count("content-encoding"), 0U);
  EXPECT_EQ(memory_bytes(), plain + compact.body.size());
  const RawReply full_gzip =
      exchange(server.port(), "POST", "/v1/plans", kRecipe, "Accept-Encoding: gzip\r\n");
  EXPECT_EQ(full_gzip.headers.at("content-encoding"), "gzip");
  EXPECT_EQ(memory_bytes(), plain + compact.body.size() + full_gzip.body.size());
  // Asked again: nothing more is rendered.
  (void)exchange(server.port(), "POST", "/v1/plans?view=compact", kRecipe);
  (void)exchange(server.port(), "POST", "/v1/plans", kRecipe, "Accept-Encoding: gzip\r\n");
  EXPECT_EQ(memory_bytes(), plain + compact.body.size() + full_gzip.body.size());
}

}  // namespace test_serving
}  // namespace slosh
