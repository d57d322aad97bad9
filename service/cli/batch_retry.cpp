#include "cli/batch_retry.hpp"

#include <algorithm>
#include <cstdlib>
#include <functional>

#include "cli/batch_errors.hpp"
#include "cli/batch_interrupt.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service::batch_cli {

HttpReply retrying_503(const HttpClient& client, const std::function<HttpReply()>& call) {
  return retrying_transient(client, call, {503});
}

HttpReply retrying_transient(const HttpClient& client, const std::function<HttpReply()>& call,
                             std::initializer_list<int> transient) {
  for (int attempt = 0;; ++attempt) {
    HttpReply reply;
    try {
      reply = call();
    } catch (const HttpError& e) {
      throw ServiceUnreachable(e.what());
    }
    const bool again =
        std::find(transient.begin(), transient.end(), reply.status) != transient.end();
    if (!again || attempt >= client.retries() || interrupt_requested()) return reply;
    const int wait =
        reply.retry_after.empty() ? 1 : std::clamp(std::atoi(reply.retry_after.c_str()), 1, 30);
    sleep_unless_interrupted(std::chrono::seconds(wait));
    if (interrupt_requested()) return reply;
  }
}

// POSTs `body` to `path`, retrying 503 answers; nothing is posted after an interrupt.
HttpReply post_retrying_503(HttpClient& client, const std::string& path, const std::string& body) {
  if (interrupt_requested()) throw BatchAbort("interrupted before " + path + " accepted the table");
  HttpReply reply = retrying_503(client, [&] { return client.post_json(path, body); });
  if (reply.status == 503 && interrupt_requested()) {
    // Say why it had not been accepted (e.g. the replicas' Redis is down) and that nothing runs.
    std::string why = "HTTP 503";
    if (const std::string m = api::envelope_message(reply.body); !m.empty()) why += ": " + m;
    throw BatchAbort("interrupted before " + path + " accepted the table (it answered " + why +
                     "); nothing was started on the service");
  }
  return reply;
}

// GETs `path`, retrying 503 answers (the shared job store of the replicas cannot answer now).
HttpReply get_retrying_503(HttpClient& client, const std::string& path) {
  return retrying_503(client, [&] { return client.get(path); });
}

std::string reply_problem(const HttpClient& client, const std::string& path,
                          const HttpReply& reply) {
  std::string message = client.base_url() + path + " answered HTTP " + std::to_string(reply.status);
  if (const std::string m = api::envelope_message(reply.body); !m.empty()) message += ": " + m;
  return message;
}

}  // namespace slosh::service::batch_cli
