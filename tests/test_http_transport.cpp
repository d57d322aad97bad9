// The connection transport (service/http/connection_stream, listening_server) as a client sees
// it, over a real server on loopback: a reply's head is held until its body and the two leave
// together, so what must reach the client before the service waits again (an interim
// "100 Continue", a reply without a body, the last reply of a pipeline) has to be sent all the
// same; large replies arrive whole; the keep-alive, read and write timeouts still end the
// connections they should.

#include <httplib.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/process.hpp"
#include "support/raw_client.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_http_transport {

using nlohmann::json;

const std::string kPlanBody =
    R"({"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82, "fluid": "water",)"
    R"( "stroke_mm": 800, "motion_time_s": 1.0}, "strategy": "notch"})";

// One reply of an HTTP/1.1 byte stream.
struct ParsedReply {
  int status{0};
  std::string head;
  std::string body;
};

// The value of header `name` (written as the service writes it) in `head`; "" when absent.
std::string header_of(const std::string& head, const std::string& name) {
  const auto at = head.find("\r\n" + name + ": ");
  if (at == std::string::npos) return "";
  const auto from = at + 4 + name.size();
  return head.substr(from, head.find("\r\n", from) - from);
}

// The replies in `stream`, each framed by its Content-Length; stops at the first incomplete one.
std::vector<ParsedReply> parse_replies(const std::string& stream) {
  std::vector<ParsedReply> replies;
  std::size_t at = 0;
  while (at < stream.size()) {
    const auto head_end = stream.find("\r\n\r\n", at);
    if (head_end == std::string::npos) break;
    ParsedReply r;
    r.head = stream.substr(at, head_end + 2 - at);
    r.status = std::stoi(r.head.substr(9, 3));
    const std::string length = header_of(r.head, "Content-Length");
    const std::size_t size = length.empty() ? 0 : std::stoul(length);
    if (head_end + 4 + size > stream.size()) break;
    r.body = stream.substr(head_end + 4, size);
    at = head_end + 4 + size;
    replies.push_back(std::move(r));
  }
  return replies;
}

// The next `count` replies on `raw` (fewer when the server closes or goes quiet).
std::vector<ParsedReply> read_replies(test::Raw& raw, std::size_t count) {
  std::string stream;
  std::vector<ParsedReply> replies;
  while ((replies = parse_replies(stream)).size() < count) {
    const std::string more = raw.read_some();
    if (more.empty()) break;
    stream += more;
  }
  return replies;
}

std::string post_plan(const std::string& id, bool close = false) {
  return "POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nX-Request-Id: " +
         id + "\r\nContent-Length: " + std::to_string(kPlanBody.size()) + "\r\n" +
         (close ? "Connection: close\r\n" : "") + "\r\n" + kPlanBody;
}

std::string get(const std::string& path, const std::string& id, bool close = false) {
  return "GET " + path + " HTTP/1.1\r\nHost: x\r\nX-Request-Id: " + id + "\r\n" +
         (close ? "Connection: close\r\n" : "") + "\r\n";
}

// Requests sent in one write are answered in order, each whole: bodies of 2 bytes and of 40 kB,
// a reply without a body (304) between them, and the last one before the connection closes.
TEST(HttpTransport, PipelinedRequestsAreAnsweredInOrderAndWhole) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client c = server.client();
  const auto first = c.Post("/v1/plans", kPlanBody, "application/json");
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 200) << first->body;
  const std::string tag = first->get_header_value("ETag");
  ASSERT_FALSE(tag.empty());
  const std::string key = json::parse(first->body).at("key").get<std::string>();

  test::Raw raw(server.port());
  ASSERT_TRUE(raw.connected());
  const std::string conditional =
      "GET /v1/plans/" + key + " HTTP/1.1\r\nHost: x\r\nX-Request-Id: p3\r\nIf-None-Match: " + tag +
      "\r\n\r\n";
  ASSERT_TRUE(raw.send(get("/healthz", "p1") + post_plan("p2") + conditional +
                       get("/v1/plans/" + key, "p4") + get("/healthz", "p5", true)));
  const std::vector<ParsedReply> replies = parse_replies(raw.read_all());
  ASSERT_EQ(replies.size(), 5u);
  const std::vector<int> statuses{200, 200, 304, 200, 200};
  for (std::size_t i = 0; i < replies.size(); ++i) {
    EXPECT_EQ(replies[i].status, statuses[i]) << i;
    EXPECT_EQ(header_of(replies[i].head, "X-Request-Id"), "p" + std::to_string(i + 1));
  }
  EXPECT_GT(replies[1].body.size(), 20000u);
  EXPECT_EQ(json::parse(replies[1].body).at("key"), key);
  EXPECT_EQ(replies[2].body, "");
  EXPECT_EQ(json::parse(replies[3].body).at("key"), key);
}

// A client that asks `Expect: 100-continue` waits for the interim reply before it sends the body:
// the interim reply must leave before the service waits for the body (it is not held for a body
// that will not come first).
TEST(HttpTransport, TheInterimReplyReachesAClientThatWaitsForIt) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  test::Raw raw(server.port());
  ASSERT_TRUE(
      raw.send("POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
               "Expect: 100-continue\r\nConnection: close\r\nContent-Length: " +
               std::to_string(kPlanBody.size()) + "\r\n\r\n"));
  const std::string interim = raw.read_until("\r\n\r\n");
  EXPECT_EQ(interim, "HTTP/1.1 100 Continue\r\n\r\n");
  ASSERT_TRUE(raw.send(kPlanBody));
  const std::vector<ParsedReply> replies = parse_replies(raw.read_all());
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(replies[0].status, 200) << replies[0].body.substr(0, 300);
}

// A reply far larger than any buffer of the transport (a cam table of 100 001 rows, 7.9 MB, written
// by the service in 64 kB pieces) arrives whole: as many bytes as its Content-Length, every row.
TEST(HttpTransport, AMegabyteReplyArrivesWhole) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client c = server.client();
  const auto plan = c.Post("/v1/plans", kPlanBody, "application/json");
  ASSERT_TRUE(plan);
  const std::string key = json::parse(plan->body).at("key").get<std::string>();
  test::Raw raw(server.port());
  ASSERT_TRUE(raw.send(get("/v1/plans/" + key + "/cam.csv?period_ms=0.01", "cam", true)));
  const std::vector<ParsedReply> replies = parse_replies(raw.read_all());
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(replies[0].status, 200);
  const std::string& table = replies[0].body;
  EXPECT_GT(table.size(), std::size_t{1} << 20);
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 1 + 100001) << table.substr(0, 200);
  // The same bytes as the library's client reads them.
  const auto again = c.Get("/v1/plans/" + key + "/cam.csv?period_ms=0.01");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->body, table);
}

// One connection carries many requests (the keep-alive loop), then is closed after the
// keep-alive timeout of silence; a request inside the timeout is still answered.
TEST(HttpTransport, KeepAliveServesManyRequestsThenClosesAfterItsTimeout) {
  const test::TempDir dir;
  test::write_file(dir / "keep.json", R"({"keep_alive_timeout_s": 1})");
  test::Server server({"--config", (dir / "keep.json").string()});
  ASSERT_GT(server.port(), 0) << server.log();
  test::Raw raw(server.port());
  for (int i = 0; i < 200; ++i) {
    ASSERT_TRUE(raw.send(get("/healthz", "k" + std::to_string(i))));
    const std::vector<ParsedReply> reply = read_replies(raw, 1);
    ASSERT_EQ(reply.size(), 1u) << i;
    ASSERT_EQ(reply[0].status, 200) << i;
    ASSERT_EQ(header_of(reply[0].head, "X-Request-Id"), "k" + std::to_string(i));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_TRUE(raw.send(get("/healthz", "inside")));
  const std::vector<ParsedReply> inside = read_replies(raw, 1);
  ASSERT_EQ(inside.size(), 1u);
  EXPECT_EQ(inside[0].status, 200);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(raw.read_all(), "");  // the server closes the idle connection
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GT(waited, 0.8);
  EXPECT_LT(waited, 5.0);
}

// A client that sends requests and stops reading holds its thread only until the write timeout:
// the connection is then closed (the client gets fewer replies than it asked for), and the
// service goes on serving others.
TEST(HttpTransport, AClientThatStopsReadingIsDroppedAtTheWriteTimeout) {
  const test::TempDir dir;
  test::write_file(dir / "write.json", R"({"write_timeout_s": 0.5})");
  test::Server server({"--config", (dir / "write.json").string()});
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client c = server.client();
  const auto plan = c.Post("/v1/plans", kPlanBody, "application/json");
  ASSERT_TRUE(plan);
  const std::string key = json::parse(plan->body).at("key").get<std::string>();
  test::Raw raw(server.port());
  // 10 requests of a 7.9 MB cam table: 79 MB, far more than the sockets' buffers hold. A send
  // that accepts part of its bytes within the timeout is followed by another; the connection
  // ends when one accepts nothing (here about three timeouts, the kernel's buffers growing).
  constexpr std::size_t kAsked = 10;
  std::string requests;
  for (std::size_t i = 0; i < kAsked; ++i) {
    requests += get("/v1/plans/" + key + "/cam.csv?period_ms=0.01", "w" + std::to_string(i));
  }
  ASSERT_TRUE(raw.send(requests));
  std::this_thread::sleep_for(std::chrono::seconds(5));
  const auto probe = c.Get("/healthz");
  ASSERT_TRUE(probe);
  EXPECT_EQ(probe->status, 200);
  // What the kernel had buffered, then the end of the connection (not 10 s of silence).
  const auto t0 = std::chrono::steady_clock::now();
  const std::string got = raw.read_all();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 8.0);
  EXPECT_EQ(got.substr(0, 12), "HTTP/1.1 200");
  EXPECT_LT(parse_replies(got).size(), kAsked);
}

// A reply that says `Connection: close` ends the connection: the rest of a refused body is never
// parsed as a request of its own, whatever it holds.
TEST(HttpTransport, TheRestOfARefusedBodyIsNeverARequest) {
  const test::TempDir dir;
  test::write_file(dir / "small.json", R"({"max_body_bytes": 1024})");
  test::Server server({"--config", (dir / "small.json").string()});
  ASSERT_GT(server.port(), 0) << server.log();
  const std::string smuggled = "GET /healthz HTTP/1.1\r\nHost: x\r\nX-Request-Id: smuggled\r\n\r\n";
  const std::string body = smuggled + std::string(2000 - smuggled.size(), ' ');
  test::Raw raw(server.port());
  ASSERT_TRUE(
      raw.send("POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
               "Content-Length: 2000\r\n\r\n" +
               body));
  const std::string stream = raw.read_all();
  const std::vector<ParsedReply> replies = parse_replies(stream);
  ASSERT_EQ(replies.size(), 1u) << stream;
  EXPECT_EQ(replies[0].status, 413);
  EXPECT_EQ(header_of(replies[0].head, "Connection"), "close");
  EXPECT_EQ(stream.find("smuggled"), std::string::npos) << stream;
}

// A request the library cannot read (an unknown method, a bad request line) is answered, and the
// connection ends: the bytes after it are not requests.
TEST(HttpTransport, AnUnreadableRequestEndsItsConnection) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const std::vector<std::pair<std::string, int>> cases{
      {"FOO / HTTP/1.1\r\nGET /healthz HTTP/1.1\r\nX-Request-Id: smuggled\r\n\r\n", 501},
      {"GET /healthz HTTP/1.1 junk\r\nHost: x\r\n\r\nGET /healthz HTTP/1.1\r\n"
       "X-Request-Id: smuggled\r\n\r\n",
       400},
  };
  for (const auto& [request, status] : cases) {
    test::Raw raw(server.port());
    ASSERT_TRUE(raw.send(request));
    const std::string stream = raw.read_all();
    const std::vector<ParsedReply> replies = parse_replies(stream);
    ASSERT_EQ(replies.size(), 1u) << stream;
    EXPECT_EQ(replies[0].status, status) << stream;
    EXPECT_EQ(header_of(replies[0].head, "Connection"), "close") << stream;
  }
  ASSERT_EQ(server.stop(), 0);  // every access-log line written
  EXPECT_EQ(server.log().find("id=smuggled"), std::string::npos) << server.log();
}

// The library reads no body of a GET: one that comes with a body is answered and its connection
// ends, so the body is never taken for the next request.
TEST(HttpTransport, TheBodyOfAGetIsNeverARequest) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const std::string inner = "GET /metrics HTTP/1.1\r\nHost: x\r\nX-Request-Id: smuggled\r\n\r\n";
  test::Raw raw(server.port());
  ASSERT_TRUE(raw.send("GET /healthz HTTP/1.1\r\nHost: x\r\nContent-Length: " +
                       std::to_string(inner.size()) + "\r\n\r\n" + inner));
  const std::string stream = raw.read_all();
  const std::vector<ParsedReply> replies = parse_replies(stream);
  ASSERT_EQ(replies.size(), 1u) << stream;
  EXPECT_EQ(replies[0].status, 200);
  EXPECT_EQ(header_of(replies[0].head, "Connection"), "close");
  ASSERT_EQ(server.stop(), 0);  // every access-log line written
  EXPECT_EQ(server.log().find("id=smuggled"), std::string::npos) << server.log();
}

// The request line and headers together are bounded (each line alone is, by the library): past
// the bound the answer is a 400 naming it and the connection ends; just under it, the request is
// answered.
TEST(HttpTransport, HeadersPastTheirBoundAreRefusedNamingIt) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const auto headers_of = [](std::size_t bytes) {
    std::string h;
    for (std::size_t i = 0; h.size() < bytes; ++i) {
      h += "X-Filler-" + std::to_string(i) + ": " + std::string(1000, 'f') + "\r\n";
    }
    return h;
  };
  {
    test::Raw raw(server.port());
    ASSERT_TRUE(raw.send("GET /healthz HTTP/1.1\r\nHost: x\r\n" + headers_of(60000) + "\r\n"));
    const std::vector<ParsedReply> replies = read_replies(raw, 1);
    ASSERT_EQ(replies.size(), 1u);
    EXPECT_EQ(replies[0].status, 200);
  }
  test::Raw raw(server.port());
  ASSERT_TRUE(raw.send("GET /healthz HTTP/1.1\r\nHost: x\r\n" + headers_of(70000) + "\r\n"));
  const std::string stream = raw.read_all();
  const std::vector<ParsedReply> replies = parse_replies(stream);
  ASSERT_EQ(replies.size(), 1u) << stream.substr(0, 500);
  EXPECT_EQ(replies[0].status, 400);
  EXPECT_EQ(json::parse(replies[0].body)["error"]["message"],
            "the request line and headers are longer than the limit of 65536 bytes");
  EXPECT_EQ(header_of(replies[0].head, "Connection"), "close");
}

// A client that waits for "100 Continue" gets it, then the final answer of its request, also when
// the path has no route (a 404) or the route not the method (a 405).
TEST(HttpTransport, AnExpectationIsFollowedByTheFinalAnswer) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  for (const auto& [line, status] : std::vector<std::pair<std::string, int>>{
           {"POST /nope", 404}, {"POST /healthz", 405}, {"GET /nope", 404}}) {
    test::Raw raw(server.port());
    ASSERT_TRUE(raw.send(line + " HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\n"
                                "Content-Length: 2\r\nConnection: close\r\n\r\n{}"));
    const std::string stream = raw.read_all();
    ASSERT_EQ(stream.rfind("HTTP/1.1 100 Continue\r\n\r\n", 0), 0u) << line << ": " << stream;
    const std::vector<ParsedReply> replies = parse_replies(stream.substr(25));
    ASSERT_EQ(replies.size(), 1u) << line << ": " << stream;
    EXPECT_EQ(replies[0].status, status) << line << ": " << stream;
  }
}

// A request whose framing a proxy could read another way is refused (400 naming why) and its
// connection ends, so its body never runs as a request: a second Content-Length, white space
// before a colon, an empty length, a coding other than chunked, both framings, a line without ':'.
TEST(HttpTransport, AnAmbiguouslyFramedRequestIsRefusedAndEndsItsConnection) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const std::string inner = "GET /metrics HTTP/1.1\r\nHost: x\r\nX-Request-Id: smuggled\r\n\r\n";
  const std::string n = std::to_string(inner.size());
  const std::string ambiguous = "the request is framed ambiguously: ";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"GET /healthz HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\nContent-Length: " + n,
       ambiguous + "Content-Length is given more than once"},
      {"POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Length : " + n,
       ambiguous + "header line 3 has white space in its field name"},
      {"GET /healthz HTTP/1.1\r\nHost: x\r\nContent-Length:",
       "Content-Length = \"\" is not a length: a whole number of bytes, at most 1048576"},
      {"POST /v1/plans HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: gzip",
       ambiguous + "Transfer-Encoding \"gzip\" is not supported (only chunked)"},
      {"POST /v1/plans HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\nContent-Length: 5",
       "the request declares both Content-Length and Transfer-Encoding: send one of them (RFC "
       "9112 6.3)"},
      {"POST /v1/plans HTTP/1.1\r\nHost: x\r\nTransfer-Encoding chunked",
       ambiguous + "header line 3 has no ':'"},
  };
  for (const auto& [head, why] : cases) {
    test::Raw raw(server.port());
    ASSERT_TRUE(raw.send(head + "\r\n\r\n" + inner));
    const std::string stream = raw.read_all();
    const std::vector<ParsedReply> replies = parse_replies(stream);
    ASSERT_EQ(replies.size(), 1u) << head << "\n" << stream;
    EXPECT_EQ(replies[0].status, 400) << head;
    EXPECT_EQ(json::parse(replies[0].body)["error"]["message"], why) << head;
    EXPECT_EQ(header_of(replies[0].head, "Connection"), "close") << head;
  }
  ASSERT_EQ(server.stop(), 0);  // every access-log line written
  EXPECT_EQ(server.log().find("id=smuggled"), std::string::npos) << server.log();
}

// A client that asks to close in any case or among other tokens is answered once, with
// `Connection: close` said once, and nothing after.
TEST(HttpTransport, ACloseInAnyCaseOrListEndsTheConnection) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  for (const std::string value : {"Close", "CLOSE", "keep-alive, close"}) {
    test::Raw raw(server.port());
    ASSERT_TRUE(raw.send("GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: " + value + "\r\n\r\n" +
                         get("/healthz", "after")));
    const std::string stream = raw.read_all();
    const std::vector<ParsedReply> replies = parse_replies(stream);
    ASSERT_EQ(replies.size(), 1u) << value << "\n" << stream;
    EXPECT_EQ(replies[0].status, 200);
    EXPECT_EQ(header_of(replies[0].head, "Connection"), "close") << value;
  }
  test::Raw raw(server.port());
  ASSERT_TRUE(raw.send("TRACE /healthz HTTP/1.1\r\nHost: x\r\nContent-Length: 2\r\n\r\n{}"));
  const std::string stream = raw.read_all();
  const auto first = stream.find("\r\nConnection: close\r\n");
  ASSERT_NE(first, std::string::npos) << stream;
  EXPECT_EQ(stream.find("\r\nConnection: close\r\n", first + 1), std::string::npos) << stream;
}

}  // namespace test_http_transport
}  // namespace slosh
