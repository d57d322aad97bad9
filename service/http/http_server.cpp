#include "http/http_server.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <regex>
#include <string_view>
#include <thread>
#include <vector>

#include "calibration/calibration_service.hpp"
#include "config/version.hpp"
#include "http/client_wait.hpp"
#include "http/connection_pool.hpp"
#include "http/connection_reaper.hpp"
#include "http/connection_stream.hpp"
#include "http/gzip.hpp"
#include "http/http_body.hpp"
#include "http/library_replies.hpp"
#include "http/listen_address.hpp"
#include "http/listening_server.hpp"
#include "http/malloc_tuning.hpp"
#include "http/plan_service.hpp"
#include "http/route_handlers.hpp"
#include "http/route_table.hpp"
#include "http/server_metrics.hpp"
#include "http/stop_signals.hpp"
#include "jobs/batch_jobs.hpp"
#include "jobs/job_stores.hpp"
#include "log/access_log.hpp"
#include "log/batched_log.hpp"
#include "metrics/metrics_registry.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/routes.hpp"

namespace slosh::service {

namespace {

// Writes the port to `path` atomically (temporary file + rename) so a reader never sees a
// partial number.
bool write_port_file(const std::string& path, int port) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << port << '\n';
    if (!out) return false;
  }
  return std::rename(tmp.c_str(), path.c_str()) == 0;
}

// Per-request bookkeeping between the pre-routing hook and the logger (same thread).
// Unset for what the library answers before routing (a malformed request line or header).
thread_local std::optional<std::chrono::steady_clock::time_point> request_start;
// The routes-table path that answered the request ("other" when none did), and what its reply
// said about a plan (Reply::plan), for the latency histogram and the access log.
thread_local std::string request_route;
thread_local std::optional<PlanFacts> request_plan;
// The request's Accept-Encoding accepts gzip (read, then removed from the request, by the
// pre-routing hook: the service codes its bodies itself, see send).
thread_local bool request_accepts_gzip = false;
std::atomic<std::uint64_t> request_counter{0};
// The reply could not be written: the client had closed its side (sent its FIN) before it, and the
// library writes nothing to such a connection. Logged and counted as 499, never as the status
// and bytes it would have had.
thread_local bool request_unwritten = false;
constexpr int kClientClosedStatus = 499;

/// Bytes a held body hands to the library per write [bytes].
constexpr std::size_t kHeldBodyChunk = std::size_t{64} << 10;

// Writes `reply` to `res`. Content coding is decided here, not by the HTTP library (which would
// compress every body again per response, and pick brotli at its slowest setting for a browser):
// a body already gzip-coded (a cached plan's stored bytes) is sent as it is; another text body of
// at least kGzipMinBytes is compressed for a client that accepts gzip. Every reply whose coding
// depends on Accept-Encoding says so (Vary), whether or not this client accepted it.
void send(Reply reply, httplib::Response& res) {
  res.status = reply.status;
  // A body not coded yet may be coded for this client (a held cam table too: its reservation
  // stays held while the coded bytes are written).
  const bool codable =
      reply.content_encoding.empty() && worth_compressing(reply.content_type, reply.body.size());
  if (codable && request_accepts_gzip && !reply.body.empty()) {
    reply.body = gzip_compress(reply.body, kResponseGzipLevel);
    reply.content_encoding = "gzip";
  }
  const bool coded = reply.content_encoding == "gzip" ||
                     (reply.coded_when_accepted && request_accepts_gzip && reply.status == 304);
  for (const auto& [name, value] : reply.headers) {
    res.set_header(name, name == "ETag" && coded ? gzip_etag(value) : value);
  }
  const bool varies = codable || coded || reply.plan.has_value() || reply.coded_when_accepted;
  if (varies) res.set_header("Vary", "Accept-Encoding");
  if (reply.body.empty()) return;
  if (!reply.content_encoding.empty()) res.set_header("Content-Encoding", reply.content_encoding);
  if (!reply.hold) {
    // Moved, not copied (set_content copies): a full plan is 40 kB.
    res.body = std::move(reply.body);
    res.set_header("Content-Type", reply.content_type);
    return;
  }
  // The body (and what the reply holds, e.g. an export's share of the budget) lives until the
  // library has written it or given up, and is not copied on the way.
  auto body = std::make_shared<const std::string>(std::move(reply.body));
  res.set_content_provider(body->size(), reply.content_type,
                           [body, hold = std::move(reply.hold)](
                               std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                             return sink.write(body->data() + offset,
                                               std::min(length, kHeldBodyChunk));
                           });
}

std::string peer_of(const httplib::Request& req) {
  return req.remote_addr + ":" + std::to_string(req.remote_port);
}

// An incoming X-Request-Id is kept when it is a short token of visible ASCII (it is logged and
// echoed); otherwise the service numbers the request itself.
std::string request_id(const httplib::Request& req) {
  std::string id = req.get_header_value("X-Request-Id");
  const bool usable = !id.empty() && id.size() <= 128 &&
                      std::all_of(id.begin(), id.end(), [](char c) { return c > ' ' && c < 127; });
  return usable ? id : std::to_string(++request_counter);
}

// The methods the HTTP library routes; it answers any other with a bare 400.
bool known_method(const std::string& method) {
  for (const char* m : {"GET", "HEAD", "POST", "PUT", "DELETE", "OPTIONS", "PATCH"}) {
    if (method == m) return true;
  }
  return false;
}

// The path of the request line as the client sent it (percent escapes kept, query cut): the
// decoded path would log "%2F" as a real '/' and "%0A" as a line break. The decoded path for a
// request without a target.
std::string path_as_sent(const httplib::Request& req) {
  if (req.target.empty()) return req.path;
  return req.target.substr(0, req.target.find_first_of("?#"));
}

// Everything the server answers with, built in order: the handlers and their engine, the job
// stores and jobs, the calibrations; the batch jobs' and the cancellations' metrics registered.
struct ServerParts {
  PlanService service;
  JobStores job_stores;
  BatchJobs jobs;
  CalibrationService calibrations;

  explicit ServerParts(const ServerConfig& config)
      : service(config),
        job_stores(config, service.redis()),
        jobs(service, job_stores.store()),
        calibrations(config, service.worker_pool()) {
    calibrations.share_through(service.redis());  // any replica plans with a stored calibration
    if (const std::string error = service.cache().storage_error(); !error.empty()) {
      spdlog::error("plan cache: {}; answering from memory only", error);
    }
    jobs.resolve_models_with(
        [this](const std::string& body) { return calibrations.resolve_model_names(body); });
    if (!calibrations.store_error().empty()) {
      spdlog::error("calibration store: {}; calibrations are kept in memory only",
                    calibrations.store_error());
    }
    service.metrics_registry().add(
        [this](MetricsText& out) { collect_job_metrics(out, jobs, service.pool()); });
    service.metrics_registry().add(
        [this](MetricsText& out) { collect_cancelled_metrics(out, service, calibrations); });
  }
  ServerParts(const ServerParts&) = delete;
  ServerParts& operator=(const ServerParts&) = delete;
};

// Everything a running server holds; the routes and hooks refer to it.
struct Runtime {
  const ServerConfig& config;
  ServerParts& parts;
  ListeningServer& server;
  std::unique_ptr<ConnectionReaper> reaper;  // started once the port is known
  RouteTable routes{api::routes()};
  std::string replica;  // the X-Slosh-Replica header of every response
  Resources resources;  // what the route handlers answer with
};

// Whether the client of `req` has closed its side of the connection: work nobody waits for is
// stopped. Asked of the reaper at most every kClientPoll (each answer lists the process's
// descriptors); never true without the reaper.
std::function<bool()> client_gone(const Runtime& rt, const httplib::Request& req) {
  return [&rt, peer = peer_of(req), next = std::chrono::steady_clock::time_point{},
          gone = false]() mutable {
    const auto now = std::chrono::steady_clock::now();
    if (!gone && rt.reaper && now >= next) {
      gone = rt.reaper->closed_by_peer(peer);
      next = now + kClientPoll;
    }
    return gone;
  };
}

// The reply of a request with its route label, whatever answered it: sent, counted under the
// label, and the label (and the plan) kept for the access log and the latency histogram the
// logger writes.
void answer(Runtime&, std::string label, Reply reply, httplib::Response& res) {
  request_route = std::move(label);
  request_plan = reply.plan;
  send(std::move(reply), res);  // counted right before it is written (post-routing hook)
}

// A routed request: its body read (POST), its query checked against the route's parameters
// (api::check_query_names: a parameter the route does not take is refused, never ignored), then
// its handler, every exception turned into its envelope by the one wrapper. A 405 is labelled
// with the route of its path, which may be another than the handler's: GET /v1/plans/batch
// reaches GET /v1/plans/{key}, whose handler refuses it for POST /v1/plans/batch.
void respond(Runtime& rt, const api::Route& route, const Handler& handler,
             const httplib::Request& req, httplib::Response& res,
             const httplib::ContentReader* reader) {
  bool refused = false;
  Reply reply = guarded_reply([&] {
    std::string body;
    if (reader != nullptr) {
      Reply error;
      std::optional<std::string> read = read_body(req, *reader, rt.config, error);
      if (!read) {
        refused = true;
        return error;
      }
      body = std::move(*read);
    }
    const Query query(req.target);
    api::check_query_names(route, query.names());
    return handler(Call{req, body, query, request_accepts_gzip});
  });
  // The rest of a refused body is not read.
  if (refused) close_after_answer(req, res);
  std::string label =
      reply.status == 405 ? rt.routes.match(req.path).label : std::string(route.path);
  answer(rt, std::move(label), std::move(reply), res);
}

// Every entry of the route table, registered with the library by its method, each answered by
// respond() (so that every method's request is labelled with its route); POST handlers read
// their bodies themselves (read_body).
void register_routes(Runtime& rt) {
  for (const RouteTable::Entry& entry : rt.routes.entries()) {
    const api::Route& route = *entry.route;
    Handler handler = handler_of(route.operation, rt.resources);
    const auto with_body = [&rt, &route, handler](const httplib::Request& req,
                                                  httplib::Response& res,
                                                  const httplib::ContentReader& reader) {
      respond(rt, route, handler, req, res, &reader);
    };
    const auto plain = [&rt, &route, handler](const httplib::Request& req, httplib::Response& res) {
      respond(rt, route, handler, req, res, nullptr);
    };
    if (route.method == "POST") {
      rt.server.Post(entry.pattern, httplib::Server::HandlerWithContentReader(with_body));
    } else if (route.method == "GET") {
      rt.server.Get(entry.pattern, plain);
    } else if (route.method == "DELETE") {
      rt.server.Delete(entry.pattern, plain);
    } else {
      throw std::logic_error("a route of a method the server does not register");
    }
  }
}

// 404 or 405 (with Allow) for a path the routes do not answer with this method (`match`: the
// table's answer for the path).
Reply unrouted_reply(const httplib::Request& req, const RouteTable::Match& match) {
  if (match.allowed.empty()) {
    return error_reply(api::ErrorCode::kNotFound, "no endpoint " + req.method.substr(0, 16) + " " +
                                                      req.path.substr(0, 80) +
                                                      "; see /v1/openapi.json");
  }
  Reply reply =
      error_reply(api::ErrorCode::kMethodNotAllowed,
                  req.method.substr(0, 16) + " is not allowed on " + req.path.substr(0, 80) +
                      "; allowed: " + allow_header(match.allowed));
  reply.headers.emplace_back("Allow", allow_header(match.allowed));
  return reply;
}

// PUT and PATCH, which no route answers: a 405 with Allow (or a 404 for a path of no route) at
// once. The library reads the body of a PUT or PATCH before routing to a plain handler, and one
// without Content-Length is read until the client closes or the read times out (a 400 after
// 5 s); a handler with a content reader is routed before any of the body is read. The body is
// never read, so the connection is closed.
void register_unrouted_body_methods(Runtime& rt) {
  const auto refuse = [&rt](const httplib::Request& req, httplib::Response& res,
                            const httplib::ContentReader&) {
    close_after_answer(req, res);
    const RouteTable::Match match = rt.routes.match(req.path);
    answer(rt, match.label, unrouted_reply(req, match), res);
  };
  rt.server.Put(".*", httplib::Server::HandlerWithContentReader(refuse));
  rt.server.Patch(".*", httplib::Server::HandlerWithContentReader(refuse));
}

// The envelope of a status the HTTP library answers itself (unknown route, wrong method, bad
// request line, bad Range).
Reply framework_reply(const httplib::Request& req, int status, const RouteTable::Match& match,
                      const Runtime& rt) {
  if (status == 404) return unrouted_reply(req, match);
  if (const ConnectionStream* connection = ConnectionStream::on_this_thread();
      status == 400 && connection != nullptr && connection->head_overflowed()) {
    return error_reply(api::ErrorCode::kBadRequest,
                       "the request line and headers are longer than the limit of " +
                           std::to_string(ConnectionStream::kMaxHeadBytes) + " bytes");
  }
  if (status == 413) return too_large_reply(rt.config);
  if (status == 415) return not_json_reply(req);
  if (status == 400 && !req.method.empty() && !known_method(req.method)) {
    return error_reply(
        api::ErrorCode::kNotImplemented,
        "the method " + req.method.substr(0, 16) + " is not implemented; see /v1/openapi.json");
  }
  return error_reply(api::error_code_of_status(status), framework_message(status));
}

void install_error_handlers(Runtime& rt) {
  rt.server.set_error_handler(httplib::Server::HandlerWithResponse(
      [&rt](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
        // This service answers whole bodies: a Range of the request never cuts the envelope.
        const_cast<httplib::Request&>(req).ranges.clear();
        // Under the route of the path whatever the method (a 405, a 413 before the body): "other"
        // only for a path no route has.
        RouteTable::Match match = rt.routes.match(req.path);
        Reply reply = framework_reply(req, res.status, match, rt);
        if (!res.has_header("X-Request-Id")) res.set_header("X-Request-Id", request_id(req));
        // A malformed request never reaches the pre-routing hook that names the replica.
        if (!res.has_header("X-Slosh-Replica")) res.set_header("X-Slosh-Replica", rt.replica);
        answer(rt, std::move(match.label), std::move(reply), res);
        // The request's framing is unknown or its body unread: what follows is not a request.
        if (ends_connection(res.status)) close_after_answer(req, res);
        return httplib::Server::HandlerResponse::Handled;
      }));
  rt.server.set_expect_100_continue_handler(
      [&rt](const httplib::Request& req, httplib::Response& res) {
        // The library asks before the pre-routing hook runs (and never runs it for a refusal):
        // the request is timed from here.
        request_start = std::chrono::steady_clock::now();
        // A refusal is the answer; after a 100 the request is routed as any other (its status
        // stays unset, so an unknown route is still a 404).
        const int status = expect_continue_status(req, rt.config);
        if (status != 100) res.status = status;
        return status;
      });
  rt.server.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
        std::string what = "unknown error";
        try {
          if (ep) std::rethrow_exception(ep);
        } catch (const std::exception& e) {
          what = e.what();
        } catch (...) {
        }
        send(error_reply(api::ErrorCode::kInternal, what), res);
      });
}

// 503 (with Retry-After, as every 503) for a connection the connection pool could not start a
// thread for.
Reply thread_refusal_reply() {
  return error_reply(
      api::ErrorCode::kOverloaded,
      "the service cannot start a thread for this connection (the system refused one): retry "
      "later");
}

// 404 for a path with a '/' sent as %2F (api::check_encoded_slashes); nullopt for any other. The
// library decodes the path before routing: "/v1/plans/abc%2Fcam.csv" would reach abc's cam table.
std::optional<Reply> encoded_slash_reply(const httplib::Request& req) {
  try {
    api::check_encoded_slashes(
        req.method, std::string_view(req.target).substr(0, req.target.find_first_of("?#")));
    return std::nullopt;
  } catch (const api::ApiError& e) {
    return reply_of(e);
  }
}

// The field lines of header `name` as one line: RFC 9110 5.3 combines repeated lines, in order,
// with commas (a list split over two lines means the same as on one).
std::string combined_field_lines(const httplib::Request& req, const char* name) {
  std::string value;
  const std::size_t lines = req.get_header_value_count(name);
  for (std::size_t i = 0; i < lines; ++i) {
    value += (i == 0 ? "" : ", ") + req.get_header_value(name, i);
  }
  return value;
}

// Request ids, the request's codings and header lines, the reaper's bookkeeping, early refusals.
void install_request_hooks(Runtime& rt) {
  rt.server.set_pre_routing_handler([&rt](const httplib::Request& req, httplib::Response& res) {
    request_start = std::chrono::steady_clock::now();
    ConnectionStream* connection = ConnectionStream::on_this_thread();
    if (connection != nullptr) connection->head_read();
    // A body the library never reads would be parsed as the next request, and the library reads
    // only an exact "close": the connection ends with this answer instead.
    if (has_unread_body(req) || asks_to_close(req)) close_after_answer(req, res);
    // Whole bodies only: the library would otherwise cut answers to a Range header.
    const_cast<httplib::Request&>(req).ranges.clear();
    // The service codes its bodies itself (send): the library must not compress them again.
    auto& headers = const_cast<httplib::Request&>(req).headers;
    request_accepts_gzip = accepts_gzip(combined_field_lines(req, "Accept-Encoding"));
    headers.erase("Accept-Encoding");
    // The handlers read one If-None-Match line: a list of tags over several lines becomes one.
    if (req.get_header_value_count("If-None-Match") > 1) {
      std::string tags = combined_field_lines(req, "If-None-Match");
      headers.erase("If-None-Match");
      headers.emplace("If-None-Match", std::move(tags));
    }
    res.set_header("X-Request-Id", request_id(req));
    res.set_header("X-Slosh-Replica", rt.replica);
    if (rt.reaper) rt.reaper->begin_request(peer_of(req));
    if (const std::string error =
            connection ? framing_error(connection->head(), rt.config.max_body_bytes) : "";
        !error.empty()) {
      // Read one way here and perhaps another by a proxy: refused, and the connection ends.
      answer(rt, rt.routes.match(req.path).label, error_reply(api::ErrorCode::kBadRequest, error),
             res);
      close_after_answer(req, res);
      return httplib::Server::HandlerResponse::Handled;
    }
    if (auto slashed = encoded_slash_reply(req)) {
      // Under the route whose segment holds the %2F (the sent path matches its template).
      answer(rt, rt.routes.match(path_as_sent(req)).label, std::move(*slashed), res);
      close_after_answer(req, res);  // a body of the request is not read
      return httplib::Server::HandlerResponse::Handled;
    }
    if (ConnectionPool::refusing()) {
      // This connection got no thread of its own (the system refused one): 503, and the client
      // is asked to close it.
      // Counted as "other": a connection without a thread is refused whatever it asks.
      answer(rt, "other", thread_refusal_reply(), res);
      close_after_answer(req, res);
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
}

// What is done right before a reply is written (post-routing) and once it was (the logger): the
// 304's framing, the request counter, the reaper's bookkeeping and one log line per request.
void install_write_hooks(Runtime& rt) {
  // The library gives a reply without a body "Content-Length: 0"; a 304 must carry no
  // Content-Length other than its 200's (RFC 9110 8.6), so it carries none.
  rt.server.set_post_routing_handler([&rt](const httplib::Request& /*req*/,
                                           httplib::Response& res) {
    if (res.status == 304) res.headers.erase("Content-Length");
    // Right before the reply is written: a client that has sent its FIN gets nothing (the
    // connection refuses the reply), so the reply is recorded as unwritten.
    ConnectionStream* connection = ConnectionStream::on_this_thread();
    request_unwritten = connection != nullptr && connection->refuse_if_peer_finished();
    // Counted before the bytes go out, so that a client that reads /metrics after its answer
    // finds it counted.
    rt.parts.service.metrics().count_request(request_route.empty() ? "other" : request_route,
                                             request_unwritten ? kClientClosedStatus : res.status);
  });
  rt.server.set_logger([&rt](const httplib::Request& req, const httplib::Response& res) {
    if (rt.reaper) rt.reaper->end_request(peer_of(req));
    ConnectionStream* connection = ConnectionStream::on_this_thread();
    if (connection != nullptr && res.get_header_value("Connection") == "close") {
      connection->end_after_reply();
    }
    AccessLogEntry entry{.request_id = res.get_header_value("X-Request-Id"),
                         .method = req.method.substr(0, 16),
                         .route = request_route.empty() ? "other" : request_route,
                         .path = path_as_sent(req).substr(0, 200),
                         .status = request_unwritten ? kClientClosedStatus : res.status,
                         .ms = std::nullopt,
                         .bytes = request_unwritten       ? 0
                                  : res.content_provider_ ? res.content_length_
                                                          : res.body.size(),
                         .cache = res.get_header_value("X-Cache"),
                         .plan = std::move(request_plan)};
    if (request_start) {
      const std::chrono::duration<double> took = std::chrono::steady_clock::now() - *request_start;
      entry.ms = took.count() * 1e3;
      rt.parts.service.metrics().observe_http(
          entry.route, known_method(req.method) ? req.method : "other", took.count());
    }
    request_start.reset();
    request_unwritten = false;
    request_route.clear();
    request_plan.reset();
    request_accepts_gzip = false;
    log_access(entry);
  });
}

// The bound port (config.port, or the one the system chose for 0); -1 when binding failed.
int bind_port(ListeningServer& server, const ServerConfig& config) {
  const int port = config.port == 0 ? server.bind_to_any_port(config.host)
                   : server.bind_to_port(config.host, config.port) ? config.port
                                                                   : -1;
  if (port < 0) {
    spdlog::error("{}", bind_failure_message(config.host, config.port));
  } else if (!server.raise_backlog()) {
    spdlog::warn("cannot raise the listen backlog: bursts may stall");
  }
  return port;
}

// Stops the server on a signal: what is queued is refused, requests being answered finish.
void stop_on_signal(Runtime& rt, const StopSignals& signals, int signal_number) {
  spdlog::info("signal {} received: finishing the requests in flight, then stopping",
               signal_number);
  rt.parts.jobs.shutdown();  // running and queued batch jobs end as failed, with a message
  rt.parts.service.begin_shutdown();
  // A signal that arrives before the accept loop runs must still stop it.
  while (!rt.server.is_running() && !signals.finished()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  rt.server.stop();             // closes the listener; requests being answered finish
  rt.reaper->close_idle_now();  // idle and trickling connections are closed, not waited for
}

// Routes, hooks and handlers installed on `rt.server`.
void install_http(Runtime& rt) {
  rt.server.configure(rt.config);
  register_routes(rt);
  register_unrouted_body_methods(rt);
  install_error_handlers(rt);
  install_request_hooks(rt);
  install_write_hooks(rt);
}

// Listens until stopped; true when the accept loop ended normally.
bool listen_until_stopped(Runtime& rt) {
  try {
    return rt.server.listen_after_bind();
  } catch (const std::exception& e) {
    // Whatever escapes the library's accept loop ends the server with a message, not an abort.
    spdlog::error("the server stopped: {}", e.what());
    rt.parts.service.begin_shutdown();
    return false;
  }
}

}  // namespace

int run_server(const ServerConfig& config, const std::string& port_file) {
  StopSignals signals;    // before any thread, which then leaves the signals to the waiter
  limit_malloc_arenas();  // before any thread; freed memory is trimmed by the signal waiter
  const BatchedLog batched_log;
  use_log_format(config.log_format);
  ServerParts parts(config);
  ListeningServer server;
  Runtime rt{config,
             parts,
             server,
             nullptr,
             RouteTable(api::routes()),
             replica_name(config),
             Resources{parts.service, parts.jobs, parts.calibrations, {}}};
  rt.resources.client_gone = [&rt](const httplib::Request& req) { return client_gone(rt, req); };
  try {
    install_http(rt);
  } catch (const std::exception& e) {  // the connection pool's first thread refused
    spdlog::error("the server cannot start: {}", e.what());
    return 1;
  }
  const int port = bind_port(server, config);
  if (port < 0) return 1;
  rt.reaper = std::make_unique<ConnectionReaper>(
      port,
      std::chrono::duration_cast<ConnectionReaper::Clock::duration>(
          std::chrono::duration<double>(config.keep_alive_timeout_s + config.request_timeout_s)));
  signals.start([&rt, &signals](int signal_number) { stop_on_signal(rt, signals, signal_number); });
  if (!port_file.empty() && !write_port_file(port_file, port)) {
    spdlog::error("cannot write the port file {}", port_file);
  }
  spdlog::info(
      "slosh {} listening on http://{}:{} (workers {}, queue {}, http threads up to {}, cache {}, "
      "replica {})",
      kVersion, config.host, port, parts.service.workers(), config.queue, config.http_threads,
      parts.service.cache_description(), rt.replica);
  const bool ok = listen_until_stopped(rt);
  signals.join();
  rt.reaper.reset();
  spdlog::info("slosh stopped");
  return ok ? 0 : 1;
}

}  // namespace slosh::service
