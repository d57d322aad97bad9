#pragma once
// The calls `slosh batch --server` makes about a job the service accepted: the handle that names
// it, its record read into a typed value, and its result rows.

#include <chrono>
#include <string>
#include <vector>

#include "cli/http_client.hpp"
#include "slosh/api/batch_job_reply.hpp"
#include "slosh/api/plan_table_row.hpp"

namespace slosh::service::batch_cli {

/// A started batch job. DELETEd (cancelled) when the handle goes before release(): an error no
/// stop path handled must not leave the job running unseen.
class RemoteJob {
 public:
  RemoteJob(HttpClient& client, std::string id) : client_(client), id_(std::move(id)) {}
  ~RemoteJob();
  RemoteJob(const RemoteJob&) = delete;
  RemoteJob& operator=(const RemoteJob&) = delete;
  [[nodiscard]] std::string path() const { return "/v1/batches/" + id_; }
  /// The job's URL, for messages that tell the user where to look.
  [[nodiscard]] std::string url() const { return client_.base_url() + path(); }
  [[nodiscard]] const std::string& id() const { return id_; }
  /// No DELETE when the handle goes (the job finished, or a stop has dealt with it).
  void release() { armed_ = false; }

 private:
  HttpClient& client_;
  std::string id_;
  bool armed_{true};
};

/// The record of `reply` (GET of the job): BatchAbort unless it is a 200 holding a job record;
/// ServiceUnreachable for 502 and 504 (a proxy in front of the replicas that could not reach the
/// one it asked: no answer either).
[[nodiscard]] api::JobProgress job_progress_of(const HttpClient& client, const RemoteJob& job,
                                               const HttpReply& reply);

/// The job's record (its first result row at most), 503 answers retried after their Retry-After
/// (retrying_503); as job_progress_of.
[[nodiscard]] api::JobProgress read_job_progress(HttpClient& client, const RemoteJob& job);

/// The rows of a results.jsonl body; BatchAbort naming the job when a line is not a row.
[[nodiscard]] std::vector<api::PlanTableRow> job_rows_of(const RemoteJob& job,
                                                         const std::string& body);

/// An HttpError's text without its closing hint (": is `slosh serve` running there?"), which
/// misleads once the service has accepted the job: it ran, and stopped answering.
[[nodiscard]] std::string without_hint(const std::string& text);

}  // namespace slosh::service::batch_cli
