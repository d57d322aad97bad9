// The server's own /metrics collectors: what the batch jobs, the pool's priorities and the
// cancellations add to the engine's figures.

#include "http/server_metrics.hpp"

namespace slosh::service {

// The batch jobs' and the pool's priority figures for /metrics.
void collect_job_metrics(MetricsText& out, const BatchJobs& jobs, const WorkerPool& pool) {
  out.family("slosh_batch_jobs_active", "gauge", "Batch jobs queued or running on this replica.");
  out.sample("slosh_batch_jobs_active", "", std::uint64_t{jobs.active()});
  out.family("slosh_batch_job_items_total", "counter",
             "Batch job items (rows) this replica solved and stored; a shared job's row counts "
             "on the one replica that stored it.");
  out.sample("slosh_batch_job_items_total", "", jobs.items_stored());
  out.family("slosh_pool_tasks_started_total", "counter",
             "Solve tasks started by priority (interactive: plans of requests and batches; "
             "background: items of batch jobs, min-time searches' strategies, calibration fits).");
  out.sample("slosh_pool_tasks_started_total", "priority=\"interactive\"",
             std::uint64_t{pool.started(TaskPriority::kInteractive)});
  out.sample("slosh_pool_tasks_started_total", "priority=\"background\"",
             std::uint64_t{pool.started(TaskPriority::kBackground)});
  out.family("slosh_pool_background_queue_depth", "gauge",
             "Background tasks waiting for a worker.");
  out.sample("slosh_pool_background_queue_depth", "",
             std::uint64_t{pool.queue_depth(TaskPriority::kBackground)});
}

// The solves stopped because their clients had gone or been answered 504, for /metrics.
void collect_cancelled_metrics(MetricsText& out, const PlanService& service,
                               const CalibrationService& calibrations) {
  out.family("slosh_solves_cancelled_total", "counter",
             "Solves stopped because every client waiting for them had closed its connection "
             "(plans, min-time searches, calibration fits).");
  out.sample("slosh_solves_cancelled_total", "kind=\"plan\"",
             std::uint64_t{service.cancelled_plans()});
  out.sample("slosh_solves_cancelled_total", "kind=\"min_time\"",
             std::uint64_t{service.cancelled_min_times()});
  out.sample("slosh_solves_cancelled_total", "kind=\"calibration\"",
             std::uint64_t{calibrations.cancelled()});
  out.family("slosh_solves_timed_out_total", "counter",
             "Solves stopped because every request waiting for them had been answered 504 (their "
             "budget plus queue_wait_s passed first): plans and min-time searches.");
  out.sample("slosh_solves_timed_out_total", "kind=\"plan\"",
             std::uint64_t{service.timed_out_plans()});
  out.sample("slosh_solves_timed_out_total", "kind=\"min_time\"",
             std::uint64_t{service.timed_out_min_times()});
}

}  // namespace slosh::service
