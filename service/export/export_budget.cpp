#include "export/export_budget.hpp"

#include <algorithm>

namespace slosh::service {

ExportBudget::ExportBudget(std::size_t capacity) : state_(std::make_shared<State>()) {
  state_->capacity = std::max<std::size_t>(1, capacity);
}

std::shared_ptr<const void> ExportBudget::try_reserve(std::size_t bytes) {
  const std::size_t charged = std::min(bytes, state_->capacity);
  {
    std::lock_guard lock(state_->mutex);
    if (state_->used + charged > state_->capacity) return nullptr;
    state_->used += charged;
  }
  const auto release = [state = state_, charged](const void*) {
    std::lock_guard lock(state->mutex);
    state->used -= charged;
  };
  try {
    // The ticket owns nothing but the release of its bytes.
    return {static_cast<const void*>(state_.get()), release};
  } catch (...) {  // no control block: the bytes are released at once
    release(nullptr);
    throw;
  }
}

std::size_t ExportBudget::in_flight() const {
  std::lock_guard lock(state_->mutex);
  return state_->used;
}

std::size_t ExportBudget::capacity() const {
  return state_->capacity;
}

}  // namespace slosh::service
