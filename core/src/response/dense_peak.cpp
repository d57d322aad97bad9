// Exact maxima of |p| for the order-7 dense output of the nonlinear scheme.

#include <cmath>

#include "response/nonlinear_scheme.hpp"

namespace slosh::detail {

namespace {

// p'(s) and p''(s) by Horner.
void derivatives(const DensePoly<double>& p, double s, double& d1, double& d2) {
  d1 = 7.0 * p[7];
  d2 = 42.0 * p[7];
  for (std::size_t k = 6; k >= 2; --k) {
    d2 = d2 * s + static_cast<double>(k * (k - 1)) * p[k];
    d1 = d1 * s + static_cast<double>(k) * p[k];
  }
  d1 = d1 * s + p[1];
}

double derivative(const DensePoly<double>& p, double s) {
  double d1 = 7.0 * p[7];
  for (std::size_t k = 6; k >= 1; --k) d1 = d1 * s + static_cast<double>(k) * p[k];
  return d1;
}

// The root of p' in [a, b] where p'(a), p'(b) have opposite signs (or one is 0): Newton's method
// from the bracket's middle, falling back to bisection whenever a Newton step leaves the bracket
// or does not halve it, until the bracket is below 1e-14 (time resolution ~1e-16 s).
double root_of_derivative(const DensePoly<double>& p, double a, double b, double da) {
  double s = 0.5 * (a + b);
  for (int it = 0; it < 60 && b - a > 1e-14; ++it) {
    double d1 = 0.0, d2 = 0.0;
    derivatives(p, s, d1, d2);
    if (d1 == 0.0) return s;
    if ((d1 < 0.0) == (da < 0.0)) {
      a = s;
      da = d1;
    } else {
      b = s;
    }
    const double newton = s - d1 / d2;
    s = (d2 != 0.0 && newton > a && newton < b) ? newton : 0.5 * (a + b);
  }
  return s;
}

}  // namespace

PolyMax dense_max_abs(const DensePoly<double>& p, double lo, double hi) {
  PolyMax best;
  if (lo > hi) return best;
  auto consider = [&](double s) {
    const double v = std::abs(dense_value(p, s));
    if (v > best.value) best = {v, s};
  };
  consider(lo);
  if (hi == lo) return best;
  // An extremum inside is a sign change of p' on one of the sub-intervals: one step spans at
  // most a sixteenth of the period, over which p' changes sign at most about once; a pair of
  // roots closer than a quarter step would be a wiggle far below the peak's resolution.
  constexpr int kParts = 4;
  double s0 = lo;
  double d0 = derivative(p, s0);
  for (int j = 1; j <= kParts; ++j) {
    const double s1 = j == kParts ? hi : lo + (hi - lo) * (static_cast<double>(j) / kParts);
    const double d1 = derivative(p, s1);
    if (d0 == 0.0) {
      consider(s0);
    } else if ((d0 < 0.0) != (d1 < 0.0) && d1 != 0.0) {
      consider(root_of_derivative(p, s0, s1, d0));
    }
    s0 = s1;
    d0 = d1;
  }
  consider(hi);
  return best;
}

}  // namespace slosh::detail
