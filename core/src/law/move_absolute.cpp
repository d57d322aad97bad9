#include "slosh/core/law/move_absolute.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace slosh {

std::optional<MoveAbsoluteProfile> move_absolute_profile(const Durations& d, double stroke) {
  if (!(d[0] > 0.0 && d[2] > 0.0 && d[4] > 0.0 && d[6] > 0.0)) return std::nullopt;
  std::optional<SevenSegmentLaw> law;
  try {
    law.emplace(d, stroke);
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
  const auto jerks = law->jerks();
  const double j = std::abs(jerks[0]);
  for (std::size_t i : {2u, 4u, 6u}) {
    if (!(std::abs(std::abs(jerks[i]) - j) <= kOneJerkTolerance * j)) return std::nullopt;
  }
  // The mean of the four ramps' jerks: they agree to round-off.
  const double mean =
      (std::abs(jerks[0]) + std::abs(jerks[2]) + std::abs(jerks[4]) + std::abs(jerks[6])) / 4.0;
  return MoveAbsoluteProfile{stroke, law->v_peak(), law->A(), law->B(), mean};
}

}  // namespace slosh
