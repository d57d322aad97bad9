#include "cli/batch_chunks.hpp"

#include <algorithm>

#include "cli/batch_errors.hpp"
#include "cli/batch_retry.hpp"
#include "slosh/api/batch_requests.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service::batch_cli {

namespace {

// POSTs one chunk, retrying 503 answers after their Retry-After.
std::vector<api::BatchItemReply> post_chunk(HttpClient& client,
                                            const api::BatchRequests& requests) {
  const HttpReply reply = post_retrying_503(client, "/v1/plans/batch", requests.body_text());
  auto results = reply.status == 200 ? api::parse_batch_reply(reply.body) : std::nullopt;
  if (!results) {
    std::string message = "HTTP " + std::to_string(reply.status);
    if (const std::string m = api::envelope_message(reply.body); !m.empty()) {
      message += ": " + m;
    }
    throw BatchAbort(client.base_url() + "/v1/plans/batch answered " + message);
  }
  return std::move(*results);
}

}  // namespace

void run_remote(const std::vector<RecipeRow>& rows, const BatchCommandOptions& options,
                HttpClient& client, RowSink& sink, ProgressBar& bar) {
  for (std::size_t begin = 0; begin < rows.size(); begin += options.chunk) {
    const std::size_t end = std::min(rows.size(), begin + options.chunk);
    api::BatchRequests requests;
    std::vector<std::size_t> sent;
    for (std::size_t i = begin; i < end; ++i) {
      if (!rows[i].error) {
        requests.add(rows[i].request);
        sent.push_back(i);
      }
    }
    const std::vector<api::BatchItemReply> results =
        requests.empty() ? std::vector<api::BatchItemReply>{} : post_chunk(client, requests);
    if (results.size() != sent.size()) {
      throw BatchAbort("the service answered " + std::to_string(results.size()) + " results for " +
                       std::to_string(sent.size()) + " requests");
    }
    std::size_t next = 0;
    for (std::size_t i = begin; i < end; ++i) {
      if (next < sent.size() && sent[next] == i) {
        const api::BatchItemReply& item = results[next++];
        BatchResult result;
        result.plan = item.plan;
        result.cached = item.cached;
        result.error = item.error;
        sink.write(rows[i], result);
      } else {
        sink.write(rows[i], row_error_result(rows[i]));
      }
    }
    bar.update(sink.written());
  }
}

}  // namespace slosh::service::batch_cli
