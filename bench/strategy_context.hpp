#pragma once
// The context plan() builds before it solves, on the thesis format, for benchmarks that call one
// strategy or one phase of a plan directly.

#include "slosh/core/strategy/planner.hpp"
#include "strategy/strategies.hpp"

namespace slosh::bench {

struct StrategyContextFixture {
  Format format = thesis_format();
  PlanOptions options;
  SloshingModel model = make_sloshing_model(format, options.model);
  detail::Deadline deadline{60.0};
  detail::StrategyContext context{format, options, model, detail::DurationSpace(format, options),
                                  deadline};
};

}  // namespace slosh::bench
