#pragma once
// Seeded random formats for property tests: each member drawn uniformly from its range, in a
// fixed order (radius, fill ratio, stroke, motion time), so a seed names the same formats.

#include <algorithm>
#include <cstdlib>
#include <random>

#include "slosh/core/model/format.hpp"
#include "support/sanitizers.hpp"

namespace slosh::test {

/// How many seeded formats a property test runs: SLOSH_PROPERTY_FORMATS when set (at least 1,
/// for a longer run by hand), else `fallback` in the release build and a quarter of it (at least
/// 2) under the sanitizers: that run looks for memory and undefined-behaviour faults along the
/// same code, several times slower, and the release run keeps the whole sample.
inline int property_format_count(int fallback) {
  if (const char* n = std::getenv("SLOSH_PROPERTY_FORMATS")) return std::max(1, std::atoi(n));
  return product_sanitized() ? std::max(2, (fallback + 3) / 4) : fallback;
}

/// Ranges of a random format [SI units; the fill height as a ratio of the radius].
struct FormatRanges {
  double radius_lo{0.03}, radius_hi{0.1};  ///< container radius [m]
  double ratio_lo{0.4}, ratio_hi{2.5};     ///< fill height / radius [-]
  double stroke_lo{0.2}, stroke_hi{1.0};   ///< stroke [m]
  double time_lo{0.6}, time_hi{1.6};       ///< motion time [s]
};

/// A water format (the default fluid and container height) drawn from `ranges`.
inline Format random_format(std::mt19937& rng, const FormatRanges& ranges = {}) {
  const auto draw = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  Format f;
  f.container.radius = draw(ranges.radius_lo, ranges.radius_hi);
  f.fill_height = draw(ranges.ratio_lo, ranges.ratio_hi) * f.container.radius;
  f.stroke = draw(ranges.stroke_lo, ranges.stroke_hi);
  f.motion_time = draw(ranges.time_lo, ranges.time_hi);
  return f;
}

}  // namespace slosh::test
