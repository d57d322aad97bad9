#include "jobs/batch_job_record.hpp"

#include <chrono>
#include <cmath>

#include "slosh/api/fields.hpp"

namespace slosh::service {

std::int64_t unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

bool mark_if_stale(JobRecord& record, std::int64_t now_ms, double stale_s) {
  if (api::is_final(record.state)) return false;
  const double silent_s = static_cast<double>(now_ms - record.updated_unix_ms) / 1e3;
  if (silent_s <= stale_s) return false;
  api::mark_failed(record, "the replica running it stopped: no update for " +
                               api::number_text(std::floor(silent_s)) +
                               " s (batch_job_stale_s = " + api::number_text(stale_s) +
                               " s); POST the job again (its plans are cached)");
  return true;
}

}  // namespace slosh::service
