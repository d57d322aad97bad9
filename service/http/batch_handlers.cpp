// The handler of POST /v1/plans/batch: every item's plan or error in request order, in one body
// bounded by max_response_bytes.

#include <string>

#include "engine/engine_errors.hpp"
#include "http/client_wait.hpp"
#include "http/plan_service.hpp"
#include "slosh/api/plan_reply.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service {

Reply PlanService::post_batch(const std::string& text, const std::function<bool()>& abandoned,
                              const std::vector<std::string>& view_query) {
  return guarded_reply([&] {
    const ServerConfig& config = engine_.config();
    const api::BatchBody body = api::parse_batch_body(text, config.batch_max);
    const api::PlanView view = api::batch_view(view_query, body.view);
    const PendingBatch batch =
        engine_.start_batch(api::read_batch_items(body.requests, config.solve_budget_s), abandoned);
    // While waiting, the client is asked every kClientPoll whether it is still there: once it has
    // gone, the items still queued or running stop (unless another request waits for them).
    for (std::size_t i = 0; abandoned && i < batch.size(); ++i) {
      while (!batch.wait_for(i, kClientPoll)) {
        if (abandoned()) {
          engine_.leave_batch(batch);
          throw cancelled_error();
        }
      }
    }
    api::BatchReplyWriter writer(config.max_response_bytes);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      const BatchResult item = batch.get(i);
      if (item.ok()) {
        engine_.count_plan(plan_facts_of("", item.plan, item.cached));
        writer.add_plan(
            i, view == api::PlanView::kCompact ? api::compact_plan_text(item.plan) : item.plan);
      } else {
        writer.add_error(i, *item.error);
      }
    }
    Reply r;
    r.body = writer.finish();
    return r;
  });
}

}  // namespace slosh::service
