#pragma once
// Maxima of a continuous function on an interval: dense samples, then local refinement.

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "slosh/core/constants.hpp"

namespace slosh {

/// A located maximum.
struct Peak {
  double value{};  ///< f(time)
  double time{};   ///< [s]
};

/// Golden-section refinement of a maximum of f bracketed in [a, b], until the bracket is at most
/// `tolerance` wide or after `max_iterations` shrinks. `time` of the result is the abscissa,
/// whatever its unit.
/// Which end a golden-section step drops when its two probes are equal (the maximum lies between
/// them either way; the rule only decides which of two equal peaks is found).
enum class TieRule {
  kDiscardUpper,  ///< keep [a, x2] (the peak finder of the responses)
  kDiscardLower,  ///< keep [x1, b] (the band maximum of the spectral strategies)
};

template <typename F>
Peak refine_max(const F& f, double a, double b, double tolerance = kPeakTimeTolerance,
                int max_iterations = std::numeric_limits<int>::max(),
                TieRule tie = TieRule::kDiscardUpper) {
  constexpr double kInvPhi = 0.6180339887498949;
  double x1 = b - kInvPhi * (b - a);
  double x2 = a + kInvPhi * (b - a);
  double f1 = f(x1);
  double f2 = f(x2);
  for (int it = 0; it < max_iterations && b - a > tolerance; ++it) {
    if (tie == TieRule::kDiscardLower ? !(f1 > f2) : f1 < f2) {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + kInvPhi * (b - a);
      f2 = f(x2);
    } else {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - kInvPhi * (b - a);
      f1 = f(x1);
    }
  }
  return f1 > f2 ? Peak{f1, x1} : Peak{f2, x2};
}

/// Maximum of f on [a, b] (endpoints included). f is sampled at spacing <= step; every sampled
/// local maximum within `refine_fraction` of the best sample is refined by golden section.
template <typename F>
Peak find_max(const F& f, double a, double b, double step, double refine_fraction = 0.05) {
  if (!(b > a)) return {f(a), a};
  const auto n = static_cast<std::size_t>(std::ceil((b - a) / step));
  const double h = (b - a) / static_cast<double>(n);
  std::vector<double> values(n + 1);
  double best_sample = -INFINITY;
  for (std::size_t i = 0; i <= n; ++i) {
    values[i] = f(i == n ? b : a + h * static_cast<double>(i));
    best_sample = std::max(best_sample, values[i]);
  }
  const double threshold = best_sample - refine_fraction * std::abs(best_sample);
  Peak best{values[0], a};
  if (values[n] > best.value) best = {values[n], b};
  for (std::size_t i = 0; i <= n; ++i) {
    if (values[i] < threshold) continue;
    const bool left_ok = i == 0 || values[i] >= values[i - 1];
    const bool right_ok = i == n || values[i] >= values[i + 1];
    if (!left_ok || !right_ok) continue;
    // On a flat stretch nothing can be gained by refining: the sample is the maximum there.
    const bool flat =
        (i == 0 || values[i] == values[i - 1]) && (i == n || values[i] == values[i + 1]);
    if (flat) {
      if (values[i] > best.value) best = {values[i], a + h * static_cast<double>(i)};
      continue;
    }
    const double lo = a + h * static_cast<double>(i == 0 ? 0 : i - 1);
    const double hi = i == n ? b : a + h * static_cast<double>(std::min(i + 1, n));
    Peak p = refine_max(f, lo, hi);
    if (values[i] > p.value) p = {values[i], i == n ? b : a + h * static_cast<double>(i)};
    if (p.value > best.value) best = p;
  }
  return best;
}

}  // namespace slosh
