#pragma once
// What a min-time test accepts as a found T_min (SPEC §9 with §5's honest status).

#include <gtest/gtest.h>

#include <string>

#include "slosh/core/strategy/min_time.hpp"

namespace slosh::test {

/// The search found its T_min: `optimal`, or `acceptable` because the plan at T_min is not
/// optimal by its own warnings (SPEC §5; on the thesis container with eta_motion <= the free board
/// on the nonlinear model, the linear model's wave at some strategies' T_min spills), which the
/// message then leads with.
inline ::testing::AssertionResult found_t_min(const MinTimeResult& r) {
  if (r.status == SolveStatus::kOptimal && r.not_optimal.empty()) {
    return ::testing::AssertionSuccess();
  }
  if (r.status == SolveStatus::kAcceptable && !r.not_optimal.empty() && r.plan &&
      r.plan->status == SolveStatus::kAcceptable &&
      r.message.starts_with("not optimal: the plan at T_min is not (" + r.not_optimal + "); ")) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << to_string(r.status) << ": " << r.message;
}

}  // namespace slosh::test
