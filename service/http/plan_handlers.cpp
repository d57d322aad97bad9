// The handlers of plans (POST /v1/plans, GET /v1/plans/{key}), their cam tables and
// POST /v1/simulate: the HTTP parts of the engine's answers.

#include <optional>
#include <string>
#include <utility>

#include "engine/engine_errors.hpp"
#include "http/plan_service.hpp"
#include "slosh/api/exact_number.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/api/spatial_simulate.hpp"

namespace slosh::service {

namespace {

// The ETag of a plan reply names the body: the same plan with series of another period, or in the
// compact view, is another body (the period is written so that it reads back as exactly that
// double: two periods never share a tag). The gzip coding gets its own tag in send().
std::string plan_etag(const std::string& key, api::PlanView view,
                      const std::optional<double>& sample_period) {
  return view == api::PlanView::kCompact ? etag(key + ";view=compact")
         : sample_period ? etag(key + ";series=" + api::exact_number_text(*sample_period))
                         : etag(key);
}

// The allow_infeasible query value: "true" or "false" (default), else 422 naming it.
bool allow_infeasible_of(const CamQuery& query) {
  const std::string allow_infeasible =
      single_query_value(query.allow_infeasible, "allow_infeasible").value_or("false");
  if (allow_infeasible != "true" && allow_infeasible != "false") {
    throw api::ApiError(
        api::ErrorCode::kInvalidValue, "allow_infeasible",
        "allow_infeasible = " +
            (allow_infeasible.empty() ? "(empty)" : allow_infeasible.substr(0, 32)) +
            " is not allowed: one of \"true\", \"false\"");
  }
  return allow_infeasible == "true";
}

}  // namespace

Reply PlanService::plan_reply(const PlanAnswer& answer, const std::string& if_none_match,
                              bool gzip) {
  Reply r;
  const std::string tag = plan_etag(answer.key, answer.view, answer.sample_period);
  // A plan cut short by its time budget is not cached: the key's tag names the complete plan a
  // later request gets, so this body has no tag (a client revalidating it must never get a 304
  // and keep it).
  if (!answer.partial) r.headers.emplace_back("ETag", tag);
  r.headers.emplace_back("X-Cache", answer.cached ? "hit" : "miss");
  r.plan = engine_.plan_facts(answer);
  engine_.count_plan(*r.plan);
  if (answer.cached && etag_matches(if_none_match, tag)) {
    r.status = 304;
    // The 200 of a hit is gzip-coded when its coding is worth it (its kept rendering says); a plan
    // with series is always over the 1 kB where coding starts.
    r.coded_when_accepted = gzip && (!answer.hit || engine_.plan_body(answer, true).gzip);
    return r;
  }
  HitBody body = engine_.plan_body(answer, gzip);
  r.body = std::move(body.body);
  if (body.gzip) r.content_encoding = "gzip";
  return r;
}

Reply PlanService::post_plan(const std::string& text, const std::string& if_none_match,
                             const std::vector<std::string>& view_query, bool gzip,
                             const std::function<bool()>& abandoned) {
  return guarded_reply([&] {
    const api::PlanView view = api::parse_view_query(view_query);
    return plan_reply(engine_.answer_plan(text, view, gzip, abandoned), if_none_match, gzip);
  });
}

Reply PlanService::get_plan(const std::string& key, const std::string& if_none_match,
                            const std::vector<std::string>& view_query, bool gzip) {
  return guarded_reply([&] {
    if (key == "batch") {  // the path of POST /v1/plans/batch, not a key
      Reply r = error_reply(api::ErrorCode::kMethodNotAllowed,
                            "GET is not allowed on /v1/plans/batch; allowed: POST");
      r.headers.emplace_back("Allow", "POST");
      return r;
    }
    const api::PlanView view = api::parse_view_query(view_query);
    if (auto answer = engine_.cached_plan(key, view)) {
      return plan_reply(*answer, if_none_match, gzip);
    }
    return reply_of(plan_not_found(key));
  });
}

Reply PlanService::cam_table(const std::string& key, CamFileFormat format, const CamQuery& query) {
  return guarded_reply([&] {
    const CamOptions options = parse_cam_query(query, format);
    CamExport exported = engine_.cam_export(key, options, allow_infeasible_of(query));
    const bool st = format == CamFileFormat::kSt;
    Reply r;
    r.content_type = st ? "text/plain; charset=utf-8" : "text/csv; charset=utf-8";
    r.body = std::move(exported.file);
    r.hold = std::move(exported.hold);
    const std::string table =
        options.master_period
            ? "master"
            : api::number_text(options.period_ms.value_or(kDefaultPeriodMs)) + "ms";
    r.headers.emplace_back("Content-Disposition", "attachment; filename=\"cam-" +
                                                      key.substr(0, 64) + "-" + table +
                                                      (st ? ".st\"" : ".csv\""));
    return r;
  });
}

Reply PlanService::post_simulate(const std::string& text) {
  return guarded_reply([&] {
    Reply r;
    r.body = api::dump_json(api::simulate_response(api::parse_json_body(text)));
    return r;
  });
}

}  // namespace slosh::service
