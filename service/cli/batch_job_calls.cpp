#include "cli/batch_job_calls.hpp"

#include <stdexcept>

#include "cli/batch_errors.hpp"
#include "cli/batch_retry.hpp"

namespace slosh::service::batch_cli {

RemoteJob::~RemoteJob() {
  if (!armed_) return;
  try {
    (void)client_.del(path());
  } catch (const HttpError&) {  // the service is gone: nothing to cancel
  }
}

api::JobProgress job_progress_of(const HttpClient& client, const RemoteJob& job,
                                 const HttpReply& reply) {
  if (reply.status == 502 || reply.status == 504) {
    throw ServiceUnreachable(reply_problem(client, job.path(), reply));
  }
  if (reply.status != 200) throw BatchAbort(reply_problem(client, job.path(), reply));
  auto progress = api::parse_job_progress(reply.body);
  if (!progress) throw BatchAbort(job.url() + " answered something that is not a job");
  return *progress;
}

api::JobProgress read_job_progress(HttpClient& client, const RemoteJob& job) {
  return job_progress_of(client, job, get_retrying_503(client, job.path() + "?limit=1"));
}

std::vector<api::PlanTableRow> job_rows_of(const RemoteJob& job, const std::string& body) {
  try {
    return api::parse_table_rows(body);
  } catch (const std::runtime_error& e) {
    throw BatchAbort("batch job " + job.id() + ": " + e.what());
  }
}

std::string without_hint(const std::string& text) {
  const std::size_t hint = text.find(": is `slosh serve` running there?");
  return hint == std::string::npos ? text : text.substr(0, hint);
}

}  // namespace slosh::service::batch_cli
