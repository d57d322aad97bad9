#pragma once
// The state of a batch job on the replica that runs it (BatchJobs::Job), shared by the files of
// the job manager: batch_jobs.cpp (the HTTP answers) and batch_job_runner.cpp (the runner).

#include <atomic>
#include <optional>
#include <vector>

#include "jobs/batch_job_record.hpp"
#include "jobs/batch_jobs.hpp"
#include "jobs/recipe_table.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::service {

struct BatchJobs::Job {
  JobStatus status;
  std::vector<RecipeRow> rows;
  std::optional<api::PlanView> view;
  std::atomic<bool> cancel{false};
};

}  // namespace slosh::service
