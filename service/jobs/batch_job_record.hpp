#pragma once
// The record of a batch job (POST /v1/batches, SPEC §13) as the job manager handles it: the
// typed state of a job (api::JobStatus, rendered by api into the JobStore) and a record read
// back (api::JobRecord), judged stale here.

#include <cstdint>

#include "slosh/api/job_record.hpp"

namespace slosh::service {

using api::JobRecord;
using api::JobState;
using api::JobStatus;

/// Milliseconds since the Unix epoch, now.
[[nodiscard]] std::int64_t unix_ms_now();

/// A record read back: a queued or running job whose owner has not rewritten it for more than
/// `stale_s` reads as failed ("the replica running it stopped"). Returns whether it was stale.
bool mark_if_stale(JobRecord& record, std::int64_t now_ms, double stale_s);

}  // namespace slosh::service
