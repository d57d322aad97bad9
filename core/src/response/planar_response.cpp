// The wall height of a planar response over one step, and its accessors.

#include <algorithm>
#include <cmath>

#include "response/planar_scheme.hpp"

namespace slosh {

namespace detail {

namespace {

/// Coefficients of the product of two step polynomials (degree 14).
using Poly2 = std::array<double, 2 * kDenseTerms - 1>;
Poly2 square_sum(const Poly& a, const Poly& b) {
  Poly2 r{};
  for (std::size_t i = 0; i < kDenseTerms; ++i) {
    for (std::size_t j = 0; j < kDenseTerms; ++j) r[i + j] += a[i] * a[j] + b[i] * b[j];
  }
  return r;
}

/// p(s) and p'(s) by Horner.
void value_and_slope(const Poly2& p, double s, double& value, double& slope) {
  value = p.back();
  slope = 0.0;
  for (std::size_t k = p.size() - 1; k > 0; --k) {
    slope = slope * s + value;
    value = value * s + p[k - 1];
  }
}

/// The height over the step and its derivative in s: f = sqrt(P) + Q.
struct Height {
  Poly2 P{}, Q{};
  bool spin{};
  [[nodiscard]] double value(double s) const {
    double p = 0.0, dp = 0.0, q = 0.0, dq = 0.0;
    value_and_slope(P, s, p, dp);
    if (spin) value_and_slope(Q, s, q, dq);
    return std::sqrt(std::max(p, 0.0)) + q;
  }
  [[nodiscard]] double slope(double s) const {
    double p = 0.0, dp = 0.0, q = 0.0, dq = 0.0;
    value_and_slope(P, s, p, dp);
    if (spin) value_and_slope(Q, s, q, dq);
    const double root = std::sqrt(std::max(p, 0.0));
    // Where E vanishes the height's slope is that of the spin alone (|E| has a corner there
    // that is a minimum, never a maximum).
    return (root > 0.0 ? 0.5 * dp / root : 0.0) + dq;
  }
};

/// The root of the slope in [a, b] where it falls from fa > 0 to fb < 0 (Illinois false
/// position, to 1e-13 of the step).
double root(const Height& f, double a, double b, double fa, double fb) {
  int side = 0;
  for (int it = 0; it < 100 && b - a > 1e-13; ++it) {
    const double m = (a * fb - b * fa) / (fb - fa);
    const double fm = f.slope(m);
    if (fm == 0.0) return m;
    if (fm > 0.0) {
      a = m;
      fa = fm;
      if (side == -1) fb *= 0.5;
      side = -1;
    } else {
      b = m;
      fb = fm;
      if (side == 1) fa *= 0.5;
      side = 1;
    }
  }
  return 0.5 * (a + b);
}

double poly_value(const Poly& p, double s) {
  return dense_value(p, s);
}

}  // namespace

double step_bound(const Poly& ex, const Poly& ey, const Poly& w, double vortex_gain) {
  double bx = 0.0, by = 0.0, bw = 0.0;
  for (std::size_t k = 0; k < kDenseTerms; ++k) {
    bx += std::abs(ex[k]);
    by += std::abs(ey[k]);
    bw += std::abs(w[k]);
  }
  return std::hypot(bx, by) + vortex_gain * bw * bw;
}

StepMax step_max(const Poly& ex, const Poly& ey, const Poly& w, double vortex_gain) {
  Height f;
  f.P = square_sum(ex, ey);
  f.spin = vortex_gain > 0.0;
  if (f.spin) {
    const Poly zero{};
    f.Q = square_sum(w, zero);
    for (double& c : f.Q) c *= vortex_gain;
  }
  StepMax best;
  auto consider = [&](double s) {
    const double v = f.value(s);
    if (v > best.value) best = {v, s, 0.0};
  };
  consider(0.0);
  constexpr int kParts = 4;
  double s0 = 0.0, d0 = f.slope(0.0);
  for (int j = 1; j <= kParts; ++j) {
    const double s1 = static_cast<double>(j) / kParts;
    const double d1 = f.slope(s1);
    if (d0 > 0.0 && d1 < 0.0) consider(root(f, s0, s1, d0, d1));
    if (d1 == 0.0) consider(s1);
    s0 = s1;
    d0 = d1;
  }
  consider(1.0);
  best.direction = std::atan2(poly_value(ey, best.s), poly_value(ex, best.s));
  return best;
}

}  // namespace detail

const PlanarStep* PlanarResponse::step_at(double t, double& s) const {
  if (steps_.empty() || t <= 0.0) return nullptr;
  const auto it = std::upper_bound(steps_.begin(), steps_.end(), t,
                                   [](double v, const PlanarStep& p) { return v < p.t0; });
  const PlanarStep& step = *(it - 1);
  s = std::min((t - step.t0) / step.h, 1.0);
  return &step;
}

double PlanarResponse::eta(double t) const {
  double s = 0.0;
  const PlanarStep* p = step_at(t, s);
  if (p == nullptr) return 0.0;
  const double w = detail::dense_value(p->spin, s);
  return std::hypot(detail::dense_value(p->ex, s), detail::dense_value(p->ey, s)) +
         vortex_gain_ * w * w;
}

double PlanarResponse::direction(double t) const {
  double s = 0.0;
  const PlanarStep* p = step_at(t, s);
  if (p == nullptr) return 0.0;
  return std::atan2(detail::dense_value(p->ey, s), detail::dense_value(p->ex, s));
}

double PlanarResponse::liquid_spin(double t) const {
  double s = 0.0;
  const PlanarStep* p = step_at(t, s);
  return p == nullptr ? 0.0 : detail::dense_value(p->spin, s);
}

}  // namespace slosh
