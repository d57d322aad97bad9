#include "cache/rendered_plans.hpp"

#include "http/gzip.hpp"
#include "slosh/api/plan_reply.hpp"

namespace slosh::service {

namespace {

std::size_t slot(PlanRendering rendering) {
  return static_cast<std::size_t>(rendering);
}

// The kept rendering `which` of `plan`, made now when it is the first use. Nullptr for the plain
// full plan (not kept). The compact view's gzip bytes are empty when the view is too short to be
// worth coding.
const std::string* rendered(PlanCache& cache, const std::shared_ptr<const CachedValue>& plan,
                            api::PlanView view, bool gzip) {
  if (view == api::PlanView::kCompact) {
    const std::string& compact =
        cache.rendering(plan, slot(PlanRendering::kCompact), [](const std::string& stored) {
          return api::compact_plan_text(api::with_cached_flag(stored, true));
        });
    if (!gzip) return &compact;
    return &cache.rendering(plan, slot(PlanRendering::kCompactGzip), [&](const std::string&) {
      return compact.size() >= kGzipMinBytes ? gzip_compress(compact) : std::string();
    });
  }
  if (!gzip) return nullptr;
  return &cache.rendering(plan, slot(PlanRendering::kFullGzip), [](const std::string& stored) {
    return gzip_compress(api::with_cached_flag(stored, true));
  });
}

}  // namespace

HitBody hit_body(PlanCache& cache, const std::shared_ptr<const CachedValue>& plan,
                 api::PlanView view, bool gzip) {
  const std::string* kept = rendered(cache, plan, view, gzip);
  if (kept == nullptr) return {api::with_cached_flag(plan->value(), true), false};
  if (!kept->empty() || !gzip) return {*kept, gzip};
  // The compact view below kGzipMinBytes: its identity body.
  return {*rendered(cache, plan, view, false), false};
}

PlanFacts hit_facts(PlanCache& cache, const std::shared_ptr<const CachedValue>& plan) {
  const std::string& kept =
      cache.rendering(plan, slot(PlanRendering::kFacts), [&plan](const std::string& stored) {
        const PlanFacts facts = plan_facts_of(plan->key(), stored, true);
        return facts.strategy + '\n' + facts.status;
      });
  const std::size_t newline = kept.find('\n');
  return PlanFacts{plan->key(), kept.substr(0, newline), kept.substr(newline + 1), true};
}

void prepare_hit_body(PlanCache& cache, const std::shared_ptr<const CachedValue>& plan,
                      api::PlanView view, bool gzip) {
  (void)rendered(cache, plan, view, gzip);
}

}  // namespace slosh::service
