#pragma once
// The cached plans' replies rendered once, kept in memory: a cache hit in the compact view or
// gzip-coded is a lookup, never a parse of the stored 40 kB plan or a compression per request.

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "plan_facts.hpp"

namespace slosh::service {

/// What a cache hit of one plan answers besides the plain full plan: the compact view and the gzip
/// coding of both views, each of the reply with `cached: true`.
struct RenderedPlan {
  std::string compact;       ///< the compact view (api::compact_plan_text of the cached reply)
  std::string full_gzip;     ///< gzip_compress of the full cached reply
  std::string compact_gzip;  ///< gzip_compress of `compact`; empty below kGzipMinBytes
  PlanFacts facts;           ///< strategy and status for the access log and the plan counters
  /// Bytes held (keys excluded).
  [[nodiscard]] std::size_t bytes() const {
    return compact.size() + full_gzip.size() + compact_gzip.size() + facts.strategy.size() +
           facts.status.size() + sizeof(RenderedPlan);
  }
};

/// Renders the views of the stored plan body `stored` (an api::StoredPlan body) of `key`.
[[nodiscard]] std::shared_ptr<const RenderedPlan> render_cached_plan(const std::string& key,
                                                                     std::string_view stored);

/// A least-recently-used map of rendered plans by recipe key, bounded in entries and bytes.
/// Thread-safe; a lookup copies a shared pointer, never a body. The rendering of a key never
/// changes (a key names one answer of one slosh version), so an entry is never stale.
class RenderedPlans {
 public:
  /// At most `max_entries` plans and `max_bytes` bytes (keys and RenderedPlan::bytes); 0 entries
  /// keeps nothing.
  RenderedPlans(std::size_t max_entries, std::size_t max_bytes)
      : max_entries_(max_entries), max_bytes_(max_bytes) {}

  /// The rendering of `key` (then the most recent); null when absent.
  [[nodiscard]] std::shared_ptr<const RenderedPlan> get(const std::string& key);
  /// Keeps `plan` for `key` as the most recent, evicting the least recent beyond the bounds.
  void put(const std::string& key, std::shared_ptr<const RenderedPlan> plan);

  [[nodiscard]] std::size_t entries() const;
  [[nodiscard]] std::size_t bytes() const;

 private:
  using Entry = std::pair<std::string, std::shared_ptr<const RenderedPlan>>;
  const std::size_t max_entries_;
  const std::size_t max_bytes_;
  mutable std::mutex mutex_;
  std::list<Entry> lru_;  // most recent first
  std::unordered_map<std::string, std::list<Entry>::iterator> index_;
  std::size_t bytes_{0};
};

}  // namespace slosh::service
