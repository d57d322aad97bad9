#pragma once
// The error a plan request is rejected with, for the tests of exact validation messages.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/plan.hpp"

namespace slosh::test {

/// The ApiError of parsing `body` as a plan request; fails the test when it parses.
inline api::ApiError plan_parse_error(const nlohmann::json& body) {
  try {
    (void)api::parse_plan_request(body);
  } catch (const api::ApiError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << body.dump();
  return api::ApiError(api::ErrorCode::kInternal, "", "");
}

}  // namespace slosh::test
