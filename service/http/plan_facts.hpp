#pragma once
// What a reply that carries a plan says about it, for the access log and the metrics (the HTTP
// handler passes it on without knowing either).

#include <string>
#include <string_view>

namespace slosh::service {

struct PlanFacts {
  std::string key;       ///< the recipe key
  std::string strategy;  ///< the plan's strategy (as in its "strategy" member)
  std::string status;    ///< the plan's status: optimal, time_limit, infeasible, ...
  bool cached{false};    ///< answered from the cache
};

/// The top-level "strategy" and "status" members of a plan's JSON text (stored or rendered), found
/// without parsing the whole plan: a plan's members are sorted, so the last "status" and the last
/// "strategy" member in the text are the top-level ones (nothing after them holds either). Empty
/// strings when absent.
[[nodiscard]] PlanFacts plan_facts_of(const std::string& key, std::string_view plan, bool cached);

}  // namespace slosh::service
