#pragma once
// The bodies a cache hit of a plan answers, rendered from the cached plan at their first use and
// kept with it in the plan cache's memory tier (PlanCache::rendering): a repeated hit in the
// compact view or gzip-coded is a lookup, never a parse of the stored 40 kB plan or a compression
// per request. Each view is rendered only when a request asks for it.

#include <memory>
#include <string>

#include "cache/plan_cache.hpp"
#include "http/plan_facts.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::service {

/// The renderings of a cached plan, by CachedValue slot. The plain full plan is none of them: it
/// is the stored body with its `cached` member put in front, one copy, as cheap as copying a
/// kept rendering and half the memory.
enum class PlanRendering : std::size_t {
  kFullGzip = 0,     ///< gzip_compress of the full reply with `cached: true`
  kCompact = 1,      ///< the compact view (api::compact_plan_text of that reply)
  kCompactGzip = 2,  ///< gzip_compress of the compact view; empty below kGzipMinBytes
  kFacts = 3,        ///< the plan's strategy and status (plan_facts_of), a line each
};

/// A cache hit's body in one view and coding.
struct HitBody {
  std::string body;
  bool gzip{false};  ///< `body` is gzip-coded
};

/// The body of a cache hit of the plan `plan` (an entry of `cache`, whose value is an
/// api::StoredPlan body) in `view`: gzip-coded when `gzip` and the view is worth coding, the
/// identity body otherwise. Renders (and keeps) the view at its first use.
[[nodiscard]] HitBody hit_body(PlanCache& cache, const std::shared_ptr<const CachedValue>& plan,
                               api::PlanView view, bool gzip);

/// What a hit of the plan `plan` (an entry of `cache`) says about it: found in the stored text at
/// the first hit (a search backwards through it) and kept.
[[nodiscard]] PlanFacts hit_facts(PlanCache& cache, const std::shared_ptr<const CachedValue>& plan);

/// Renders and keeps what a hit in `view` (gzip-coded when `gzip`) will answer, without building
/// the body: nothing for the plain full plan.
void prepare_hit_body(PlanCache& cache, const std::shared_ptr<const CachedValue>& plan,
                      api::PlanView view, bool gzip);

}  // namespace slosh::service
