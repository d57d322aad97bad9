#pragma once
// The memory the cam exports in flight may hold together (GET /v1/plans/{key}/cam.csv and
// cam.st): each export reserves an upper bound of its bytes (its rows and its file) before it
// samples, and keeps the reservation until its response has been written. An export that does not
// fit is refused (503 with Retry-After) instead of waiting, so a burst of large exports cannot
// exhaust memory (200 parallel 200 000-row exports reached more than 3 GB).

#include <cstddef>
#include <memory>
#include <mutex>

namespace slosh::service {

class ExportBudget {
 public:
  /// A budget of `capacity` bytes (>= 1).
  explicit ExportBudget(std::size_t capacity);

  /// Reserves `bytes` (counted as at most the whole budget: an export larger than the budget
  /// runs alone). The reservation is released when the last copy of the returned ticket is
  /// dropped; nullptr when the budget has no room for it now.
  [[nodiscard]] std::shared_ptr<const void> try_reserve(std::size_t bytes);

  [[nodiscard]] std::size_t in_flight() const;  ///< bytes reserved now
  [[nodiscard]] std::size_t capacity() const;   ///< the budget [bytes]

 private:
  struct State {
    mutable std::mutex mutex;
    std::size_t capacity{};
    std::size_t used{};
  };
  // Shared with the tickets: a response may outlive the service that made it.
  std::shared_ptr<State> state_;
};

}  // namespace slosh::service
