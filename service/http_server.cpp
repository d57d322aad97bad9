#include "http_server.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <pthread.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <thread>

#include "plan_service.hpp"
#include "version.hpp"

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
thread_local std::chrono::steady_clock::time_point request_start;
std::atomic<std::uint64_t> request_counter{0};

void send(const Reply& reply, httplib::Response& res) {
  res.status = reply.status;
  for (const auto& [name, value] : reply.headers) res.set_header(name, value);
  res.set_header("X-Cache", reply.cache_hit ? "hit" : "miss");
  if (!reply.body.empty()) res.set_content(reply.body, reply.content_type);
}

}  // namespace

int run_server(const ServerConfig& config, const std::string& port_file) {
  // SIGINT / SIGTERM are blocked in every thread (so first, before any thread is started: the
  // worker pool inherits the mask) and taken synchronously by one waiter thread, which stops the
  // server outside any signal handler.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  PlanService service(config);
  if (const std::string error = service.cache().storage_error(); !error.empty()) {
    spdlog::error("plan cache: {}; answering from memory only", error);
  }
  httplib::Server server;
  server.new_task_queue = [n = config.http_threads] {
    return new httplib::ThreadPool(std::max<std::size_t>(1, n));
  };
  server.set_payload_max_length(config.max_body_bytes);
  server.set_read_timeout(10, 0);
  server.set_write_timeout(10, 0);
  server.set_keep_alive_max_count(100000);
  server.set_tcp_nodelay(true);  // no 40 ms Nagle + delayed-ACK stall between header and body

  // Every handler goes through here: one metrics label per route, exceptions become the envelope.
  auto route = [&service](std::string label, auto handler) {
    return [&service, label = std::move(label), handler](const httplib::Request& req,
                                                         httplib::Response& res) {
      Reply reply;
      try {
        reply = handler(req);
      } catch (const std::exception& e) {
        reply = PlanService::error_reply(500, "internal", e.what());
      } catch (...) {
        reply = PlanService::error_reply(500, "internal", "unknown error");
      }
      send(reply, res);
      service.metrics().count_request(label, reply.status);
    };
  };
  server.Post("/v1/plans", route("/v1/plans", [&](const httplib::Request& req) {
                return service.post_plan(req.body, req.get_header_value("If-None-Match"));
              }));
  server.Post("/v1/plans/batch", route("/v1/plans/batch", [&](const httplib::Request& req) {
                return service.post_batch(req.body);
              }));
  server.Get(R"(/v1/plans/([^/]+))", route("/v1/plans/{key}", [&](const httplib::Request& req) {
               return service.get_plan(req.matches[1], req.get_header_value("If-None-Match"));
             }));
  server.Post("/v1/simulate", route("/v1/simulate", [&](const httplib::Request& req) {
                return service.post_simulate(req.body);
              }));
  server.Get("/v1/fluids",
             route("/v1/fluids", [&](const httplib::Request&) { return service.fluids(); }));
  server.Get("/v1/openapi.json",
             route("/v1/openapi.json", [&](const httplib::Request&) { return service.openapi(); }));
  server.Get("/healthz",
             route("/healthz", [&](const httplib::Request&) { return service.health(); }));
  server.Get("/readyz", route("/readyz", [&](const httplib::Request&) { return service.ready(); }));
  server.Get("/metrics",
             route("/metrics", [&](const httplib::Request&) { return service.metrics_text(); }));

  // Errors the framework answers itself (unknown route, body too large, bad request line) get the
  // same envelope.
  const httplib::Server::HandlerWithResponse on_error =
      [&service, &config](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
        Reply reply;
        switch (res.status) {
          case 404:
            reply = PlanService::error_reply(404, "not_found",
                                             "no endpoint " + req.method + " " +
                                                 req.path.substr(0, 80) + "; see /v1/openapi.json");
            break;
          case 413:
            reply = PlanService::error_reply(413, "payload_too_large",
                                             "the body is larger than the limit of " +
                                                 std::to_string(config.max_body_bytes) + " bytes");
            break;
          default:
            reply = PlanService::error_reply(res.status,
                                             res.status < 500 ? "malformed_json" : "internal",
                                             "HTTP " + std::to_string(res.status));
        }
        send(reply, res);
        service.metrics().count_request("other", res.status);
        return httplib::Server::HandlerResponse::Handled;
      };
  server.set_error_handler(on_error);
  server.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
        std::string what = "unknown error";
        try {
          if (ep) std::rethrow_exception(ep);
        } catch (const std::exception& e) {
          what = e.what();
        } catch (...) {
        }
        send(PlanService::error_reply(500, "internal", what), res);
      });
  server.set_pre_routing_handler([](const httplib::Request&, httplib::Response& res) {
    request_start = std::chrono::steady_clock::now();
    res.set_header("X-Request-Id", std::to_string(++request_counter));
    return httplib::Server::HandlerResponse::Unhandled;
  });
  server.set_logger([](const httplib::Request& req, const httplib::Response& res) {
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - request_start)
            .count();
    spdlog::info("request id={} method={} path={} status={} cache={} ms={:.3f} bytes={}",
                 res.get_header_value("X-Request-Id"), req.method, req.path, res.status,
                 res.get_header_value("X-Cache"), ms, res.body.size());
  });

  int port = config.port;
  if (port == 0) {
    port = server.bind_to_any_port(config.host);
  } else if (!server.bind_to_port(config.host, port)) {
    port = -1;
  }
  if (port < 0) {
    spdlog::error("cannot bind {}:{}", config.host, config.port);
    return 1;
  }
  std::atomic<bool> finished{false};
  std::thread waiter([&] {
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    if (finished) return;
    spdlog::info("signal {} received: finishing the requests in flight, then stopping",
                 signal_number);
    service.begin_shutdown();
    // A signal that arrives before the accept loop runs must still stop it.
    while (!server.is_running() && !finished) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    server.stop();  // closes the listener; the HTTP pool finishes its requests before it returns
  });
  if (!port_file.empty() && !write_port_file(port_file, port)) {
    spdlog::error("cannot write the port file {}", port_file);
  }
  spdlog::info("slosh {} listening on http://{}:{} (workers {}, queue {}, cache {})", kVersion,
               config.host, port, config.workers, config.queue,
               config.cache_path.empty() ? "memory" : config.cache_path);
  const bool ok = server.listen_after_bind();
  finished = true;
  pthread_kill(waiter.native_handle(), SIGTERM);  // wakes sigwait if no signal came
  waiter.join();
  spdlog::info("slosh stopped");
  return ok ? 0 : 1;
}

}  // namespace slosh::service
