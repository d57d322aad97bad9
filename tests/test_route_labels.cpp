// Every route of the table (api::routes()), with each method it answers (HEAD with GET), is
// counted, timed and logged under its own path template on a real `slosh serve`, whatever its
// handler answers (200, 404, 422): no pair falls into "other" or another route's label.

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "slosh/api/routes.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_route_labels {

// The template with each {parameter} filled in (a name the web page has for /assets/{name}).
std::string concrete(std::string_view path) {
  std::string out;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (path[i] == '{') {
      out += path.substr(i, path.find('}', i) - i + 1) == "{name}" && path.starts_with("/assets")
                 ? "app.js"
                 : "x1";
      i = path.find('}', i);
    } else {
      out += path[i];
    }
  }
  return out;
}

TEST(RouteLabels, EveryRouteAndMethodOfTheTableHasItsOwnLabel) {
  test::Server server;
  auto client = server.client();
  client.set_keep_alive(true);  // logged and timed before the next request is read
  struct Sent {
    std::string id, method, path, label;
  };
  std::vector<Sent> sent;
  for (const api::Route& route : api::routes()) {
    std::vector<std::string> methods{std::string(route.method)};
    if (route.method == "GET") methods.emplace_back("HEAD");
    for (const std::string& method : methods) {
      const std::string id = "label-" + std::to_string(sent.size());
      const std::string path = concrete(route.path);
      const httplib::Headers headers{{"X-Request-Id", id}};
      const httplib::Result r = method == "POST"
                                    ? client.Post(path, headers, "{}", "application/json")
                                : method == "DELETE" ? client.Delete(path, headers)
                                : method == "HEAD"   ? client.Head(path, headers)
                                                     : client.Get(path, headers);
      ASSERT_TRUE(r) << method << " " << path;
      EXPECT_NE(r->status, 405) << method << " " << path;  // routed to the route's own handler
      sent.push_back({id, method, path, std::string(route.path)});
    }
  }
  const std::string metrics = client.Get("/metrics")->body;
  std::map<std::pair<std::string, std::string>, int> expected;
  for (const Sent& s : sent) ++expected[{s.label, s.method}];
  for (const auto& [pair, n] : expected) {
    EXPECT_EQ(test::metric(metrics, "slosh_http_request_duration_seconds_count{route=\"" +
                                        pair.first + "\",method=\"" + pair.second + "\"}"),
              n)
        << pair.second << " " << pair.first;
  }
  for (const char* method : {"GET", "HEAD", "POST", "DELETE"}) {
    EXPECT_EQ(test::metric(metrics,
                           "slosh_http_request_duration_seconds_count{route=\"other\","
                           "method=\"" +
                               std::string(method) + "\"}"),
              -1)
        << method;
  }
  ASSERT_EQ(server.stop(), 0);
  const std::string log = server.log();
  for (const Sent& s : sent) {
    const std::size_t at = log.find("request id=" + s.id + " ");
    ASSERT_NE(at, std::string::npos) << s.id << " " << s.method << " " << s.path;
    const std::string line = log.substr(at, log.find('\n', at) - at);
    EXPECT_NE(line.find(" method=" + s.method + " path=" + s.path + " "), std::string::npos)
        << line;
    EXPECT_TRUE(line.ends_with(" route=" + s.label)) << line;
  }
}

}  // namespace test_route_labels
}  // namespace slosh
