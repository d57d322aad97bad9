// The handler of POST /v1/min-time: the HTTP parts (ETag, 304, X-Cache) of the engine's answer.

#include <string>

#include "http/gzip.hpp"
#include "http/plan_service.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::service {

namespace {

// The reply of a stored min-time answer: ETag = the key (one body per key), 304 for a cached
// answer whose ETag `if_none_match` names. An answer that is not cached (a search cut short by its
// budget) has no tag: the key's tag names the complete answer a later request gets.
Reply min_time_reply(const MinTimeAnswer& answer, const std::string& if_none_match) {
  Reply r;
  if (!answer.partial) r.headers.emplace_back("ETag", etag(answer.key));
  r.headers.emplace_back("X-Cache", answer.cached ? "hit" : "miss");
  if (answer.cached && etag_matches(if_none_match, etag(answer.key))) {
    r.status = 304;
    // The 200 is coded for a gzip client when the body is worth it (send() decides the same).
    r.coded_when_accepted = worth_compressing(r.content_type, answer.stored.size());
    return r;
  }
  r.body = api::render_min_time_reply(answer.stored, answer.cached);
  return r;
}

}  // namespace

Reply PlanService::post_min_time(const std::string& text, const std::string& if_none_match,
                                 const std::function<bool()>& abandoned) {
  return guarded_reply([&] {
    const api::MinTimeRequest request =
        api::parse_min_time_request(api::parse_json_body(text), engine_.config().solve_budget_s);
    return min_time_reply(engine_.answer_min_time(request, abandoned), if_none_match);
  });
}

}  // namespace slosh::service
