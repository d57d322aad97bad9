#pragma once
// What the HTTP endpoints do, without the HTTP library: parse, cache, solve on the worker pool,
// render. Every method returns a Reply and never throws (errors become the JSON envelope).

#include <atomic>
#include <future>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "metrics.hpp"
#include "plan_cache.hpp"
#include "server_config.hpp"
#include "slosh/api/plan.hpp"
#include "worker_pool.hpp"

namespace slosh::service {

/// An HTTP-level answer.
struct Reply {
  int status{200};
  std::string body;
  std::string content_type{"application/json"};
  std::vector<std::pair<std::string, std::string>> headers;
  bool cache_hit{false};
};

class PlanService {
 public:
  explicit PlanService(const ServerConfig& config);
  /// Finishes queued and running solves.
  ~PlanService();

  Reply post_plan(const std::string& body, const std::string& if_none_match);
  Reply get_plan(const std::string& key, const std::string& if_none_match);
  Reply post_batch(const std::string& body);
  Reply post_simulate(const std::string& body);
  Reply fluids() const;
  Reply openapi() const;
  Reply health() const;
  Reply ready() const;
  Reply metrics_text() const;

  /// Readiness turns 503 and no new solve is queued; in-flight solves finish.
  void begin_shutdown();

  Metrics& metrics() { return metrics_; }
  [[nodiscard]] const PlanCache& cache() const { return cache_; }

  /// The envelope reply of an error status with a message (and optional field).
  static Reply error_reply(int status, const std::string& code, const std::string& message,
                           const std::string& field = "");

 private:
  struct Outcome {
    int status{200};
    std::string body;
  };
  // The rendered plan of `key`: from a running solve of the same recipe, or a new solve queued
  // on the pool (`wait_for_room`: block for a queue slot instead of answering 503).
  std::shared_future<Outcome> solve(const std::string& key, const api::PlanRequest& request,
                                    bool wait_for_room, bool* refused);
  Reply plan_reply(const std::string& key, const std::string& body, bool cached,
                   const std::string& if_none_match) const;

  ServerConfig config_;
  Metrics metrics_;
  PlanCache cache_;
  std::mutex inflight_mutex_;
  std::unordered_map<std::string, std::shared_future<Outcome>> inflight_;
  std::atomic<bool> ready_{true};
  WorkerPool pool_;  // last: destroyed first, finishing the solves that use the members above
};

}  // namespace slosh::service
