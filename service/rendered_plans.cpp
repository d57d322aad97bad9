#include "rendered_plans.hpp"

#include "gzip.hpp"
#include "slosh/api/plan_reply.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::service {

std::shared_ptr<const RenderedPlan> render_cached_plan(const std::string& key,
                                                       std::string_view stored) {
  auto plan = std::make_shared<RenderedPlan>();
  const std::string full = api::with_cached_flag(stored, true);
  plan->compact = api::compact_plan_text(full);
  plan->full_gzip = gzip_compress(full);
  if (plan->compact.size() >= kGzipMinBytes) plan->compact_gzip = gzip_compress(plan->compact);
  plan->facts = plan_facts_of(key, full, true);
  return plan;
}

std::shared_ptr<const RenderedPlan> RenderedPlans::get(const std::string& key) {
  const std::lock_guard lock(mutex_);
  const auto it = index_.find(key);
  if (it == index_.end()) return nullptr;
  lru_.splice(lru_.begin(), lru_, it->second);
  return it->second->second;
}

void RenderedPlans::put(const std::string& key, std::shared_ptr<const RenderedPlan> plan) {
  if (max_entries_ == 0 || !plan) return;
  const std::size_t size = key.size() + plan->bytes();
  if (size > max_bytes_) return;
  const std::lock_guard lock(mutex_);
  if (const auto it = index_.find(key); it != index_.end()) {
    bytes_ -= it->first.size() + it->second->second->bytes();
    lru_.erase(it->second);
    index_.erase(it);
  }
  lru_.emplace_front(key, std::move(plan));
  index_[key] = lru_.begin();
  bytes_ += size;
  while (!lru_.empty() && (lru_.size() > max_entries_ || bytes_ > max_bytes_)) {
    const Entry& last = lru_.back();
    bytes_ -= last.first.size() + last.second->bytes();
    index_.erase(last.first);
    lru_.pop_back();
  }
}

std::size_t RenderedPlans::entries() const {
  const std::lock_guard lock(mutex_);
  return lru_.size();
}

std::size_t RenderedPlans::bytes() const {
  const std::lock_guard lock(mutex_);
  return bytes_;
}

}  // namespace slosh::service
