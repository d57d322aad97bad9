#pragma once
// Shared inputs of the numerics tests.

#include "slosh/core/law/seven_segment.hpp"

namespace slosh::test {

/// An asymmetric admissible set of durations summing to 1 s (every segment distinct).
constexpr Durations kAsymmetricDurations{0.08, 0.17, 0.06, 0.21, 0.12, 0.09, 0.27};

}  // namespace slosh::test
