#pragma once
// The /metrics collectors of the HTTP server's parts (registered in its MetricsRegistry).

#include "calibration/calibration_service.hpp"
#include "engine/worker_pool.hpp"
#include "http/plan_service.hpp"
#include "jobs/batch_jobs.hpp"
#include "metrics/metrics_registry.hpp"

namespace slosh::service {

/// The batch jobs' and the pool's priority figures.
void collect_job_metrics(MetricsText& out, const BatchJobs& jobs, const WorkerPool& pool);
/// The solves stopped because their clients had gone (slosh_solves_cancelled_total) or because
/// their requests had been answered 504 (slosh_solves_timed_out_total).
void collect_cancelled_metrics(MetricsText& out, const PlanService& service,
                               const CalibrationService& calibrations);

}  // namespace slosh::service
