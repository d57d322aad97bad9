#include "cli/progress_bar.hpp"

#include <algorithm>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace slosh::service {

namespace {

constexpr std::size_t kBarCells = 30;
constexpr auto kRedrawInterval = std::chrono::milliseconds(100);

std::string clock_text(double seconds) {
  const long s = std::lround(seconds);
  char buffer[32];
  if (s >= 3600) {
    std::snprintf(buffer, sizeof buffer, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  } else {
    std::snprintf(buffer, sizeof buffer, "%ld:%02ld", s / 60, s % 60);
  }
  return buffer;
}

}  // namespace

bool progress_enabled(ProgressMode mode) {
  if (mode != ProgressMode::kAuto) return mode == ProgressMode::kAlways;
  const char* term = std::getenv("TERM");
  return ::isatty(STDERR_FILENO) == 1 && (term == nullptr || std::strcmp(term, "dumb") != 0);
}

ProgressBar::ProgressBar(std::ostream& out, std::size_t total, bool enabled, std::string unit)
    : out_(out),
      total_(total),
      enabled_(enabled),
      unit_(std::move(unit)),
      start_(std::chrono::steady_clock::now()) {}

std::string ProgressBar::render(std::size_t done, double elapsed) const {
  const double fraction =
      total_ == 0 ? 1.0 : static_cast<double>(done) / static_cast<double>(total_);
  const auto filled = static_cast<std::size_t>(fraction * kBarCells);
  std::string bar(filled, '#');
  bar.resize(kBarCells, '.');
  const double rate = elapsed > 0.0 ? static_cast<double>(done) / elapsed : 0.0;
  std::string eta = "--:--";
  if (done == total_) {
    eta = clock_text(elapsed);
  } else if (rate > 0.0) {
    eta = clock_text(static_cast<double>(total_ - done) / rate);
  }
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "[%s] %zu/%zu %3.0f%%  %.1f %s/s  %s %s", bar.c_str(), done,
                total_, 100.0 * fraction, rate, unit_.c_str(), done == total_ ? "in" : "ETA",
                eta.c_str());
  return buffer;
}

bool ProgressBar::due() const {
  return enabled_ && (last_done_ == static_cast<std::size_t>(-1) ||
                      std::chrono::steady_clock::now() - last_draw_ >= kRedrawInterval);
}

void ProgressBar::update(std::size_t done) {
  if (!enabled_ || done == last_done_ || (done != total_ && !due())) return;
  const auto now = std::chrono::steady_clock::now();
  std::string text = render(done, std::chrono::duration<double>(now - start_).count());
  const std::size_t shown = text.size();
  if (text.size() < width_) text.append(width_ - text.size(), ' ');  // erase a longer last line
  width_ = shown;
  out_ << '\r' << text << std::flush;
  last_draw_ = now;
  last_done_ = done;
}

void ProgressBar::finish() {
  if (!enabled_) return;
  last_done_ = static_cast<std::size_t>(-1);
  update(total_);
  out_ << '\n' << std::flush;
}

void ProgressBar::stop(std::size_t done) {
  if (!enabled_) return;
  last_done_ = static_cast<std::size_t>(-1);
  update(std::min(done, total_));
  out_ << '\n' << std::flush;
}

}  // namespace slosh::service
