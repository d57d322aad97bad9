#pragma once
// The calls of `slosh batch --server` that a busy service may refuse for now: 503 answers are
// retried after their Retry-After, and Ctrl-C ends the waits at once.

#include <chrono>
#include <functional>
#include <initializer_list>
#include <string>

#include "cli/http_client.hpp"

namespace slosh::service::batch_cli {

/// Timeout of one POST /v1/plans/batch chunk in server mode.
constexpr std::chrono::seconds kServerTimeout{600};

/// Makes a call (`call`: one request of `client`), retrying 503 answers after their Retry-After
/// (1 to 30 s, 1 s without one) client.retries() times; the last answer. The waits are sliced so
/// that Ctrl-C ends them at once: the 503 is then returned. ServiceUnreachable when the service
/// cannot be reached.
HttpReply retrying_503(const HttpClient& client, const std::function<HttpReply()>& call);

/// retrying_503 for every status in `transient` (answers that say "not now" rather than "no", e.g.
/// 409 from a replica that does not see yet that a job has finished).
HttpReply retrying_transient(const HttpClient& client, const std::function<HttpReply()>& call,
                             std::initializer_list<int> transient);

/// POSTs `body` to `path`, retrying 503 answers; nothing is posted after an interrupt (BatchAbort,
/// saying why the last try had not been accepted).
HttpReply post_retrying_503(HttpClient& client, const std::string& path, const std::string& body);

/// GETs `path`, retrying 503 answers (the shared job store of the replicas cannot answer now).
HttpReply get_retrying_503(HttpClient& client, const std::string& path);

/// "<base url><path> answered HTTP <status>[: <the error envelope's message>]".
[[nodiscard]] std::string reply_problem(const HttpClient& client, const std::string& path,
                                        const HttpReply& reply);

}  // namespace slosh::service::batch_cli
