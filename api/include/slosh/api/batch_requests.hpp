#pragma once
// The client side of POST /v1/plans/batch (`slosh batch --server` without batch jobs): the plan
// requests of one chunk, collected row by row, and the body that sends them.

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/recipe_row.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::api {

/// The plan requests of one POST /v1/plans/batch, in the order they were added.
class BatchRequests {
 public:
  /// Adds a plan request as a recipe table read it.
  void add(const RecipeRequest& request) { requests_.push_back(request.body()); }
  [[nodiscard]] std::size_t size() const { return requests_.size(); }
  [[nodiscard]] bool empty() const { return requests_.empty(); }
  /// The body {"requests": [...]}.
  [[nodiscard]] std::string body_text() const { return batch_body_text(requests_); }

 private:
  std::vector<nlohmann::json> requests_;
};

}  // namespace slosh::api
