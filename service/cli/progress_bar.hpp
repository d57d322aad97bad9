#pragma once
// A one-line progress bar with rate and ETA, redrawn in place on a terminal.

#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>

namespace slosh::service {

/// When to draw: on a terminal only (auto), always, never.
enum class ProgressMode { kAuto, kAlways, kNever };

/// Whether the progress bar is drawn on stderr under `mode` (auto: stderr is a terminal and TERM
/// is not "dumb").
[[nodiscard]] bool progress_enabled(ProgressMode mode);

class ProgressBar {
 public:
  /// A bar over `total` items written to `out` when `enabled` (else every call does nothing).
  ProgressBar(std::ostream& out, std::size_t total, bool enabled, std::string unit = "recipes");
  /// Redraws with `done` items finished (at most 10 times a second unless `done` == total).
  void update(std::size_t done);
  /// Whether an update() now would redraw (enabled and the last draw is old enough).
  [[nodiscard]] bool due() const;
  /// Draws the final state and ends the line.
  void finish();
  /// Draws `done` (a run that stopped before the end: never shown as complete) and ends the line.
  void stop(std::size_t done);

  /// The text of the bar for `done` items after `elapsed` seconds (no carriage return).
  [[nodiscard]] std::string render(std::size_t done, double elapsed) const;

 private:
  std::ostream& out_;
  std::size_t total_;
  bool enabled_;
  std::string unit_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::size_t last_done_{static_cast<std::size_t>(-1)};
  std::size_t width_{0};
};

}  // namespace slosh::service
