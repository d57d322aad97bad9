#pragma once
// A 7-segment law rebuilt from its durations alone, for the export tests (nothing here calls
// into slosh::core). With unit peak velocity the plateaus are A = 1 / (d1/2 + d2 + d3/2),
// B = 1 / (d5/2 + d6 + d7/2); the position reached is integrated segment by segment with cubic
// Taylor steps (exact for a constant jerk) and every level is scaled to the stroke.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace slosh::test {

/// Position, velocity, acceleration and jerk (SI).
struct LawState {
  double s{}, v{}, a{}, j{};
};

class ReferenceSevenSegment {
 public:
  using Durations = std::array<double, 7>;

  ReferenceSevenSegment(const Durations& d, double stroke) : d_(d), stroke_(stroke) {
    const double A1 = 1.0 / (d[0] / 2 + d[1] + d[2] / 2);
    const double B1 = 1.0 / (d[4] / 2 + d[5] + d[6] / 2);
    const double s1 = integrate(A1, B1, nullptr);
    A_ = A1 * stroke / s1;
    B_ = B1 * stroke / s1;
    (void)integrate(A_, B_, &start_);
    t_[0] = 0.0;
    for (std::size_t i = 0; i < 7; ++i) t_[i + 1] = t_[i] + d[i];
  }
  [[nodiscard]] double A() const { return A_; }
  [[nodiscard]] double B() const { return B_; }
  [[nodiscard]] double T() const { return t_[7]; }
  [[nodiscard]] const std::array<double, 8>& switches() const { return t_; }
  [[nodiscard]] double jerk(std::size_t i) const { return start_[i].j; }
  /// Velocity of the cruise (segment 4) [m/s].
  [[nodiscard]] double v_peak() const { return start_[3].v; }
  /// max(A, B) [m/s^2].
  [[nodiscard]] double a_peak() const { return std::max(A_, B_); }
  [[nodiscard]] double max_jerk() const {
    double m = 0.0;
    for (const LawState& s : start_) m = std::max(m, std::abs(s.j));
    return m;
  }
  /// The state at `t`; a time within `tol` of switch times belongs to the last segment of
  /// positive duration starting there; at and after T - tol, rest at the stroke.
  [[nodiscard]] LawState at(double t, double tol = 1e-12) const {
    if (t >= T() - tol) return {stroke_, 0.0, 0.0, 0.0};
    std::size_t seg = 0;
    for (std::size_t i = 0; i < 7; ++i) {
      if (d_[i] > 0.0 && t_[i] <= t + tol) seg = i;
    }
    const LawState& b = start_[seg];
    const double h = std::max(0.0, t - t_[seg]);
    return {b.s + b.v * h + b.a * h * h / 2 + b.j * h * h * h / 6, b.v + b.a * h + b.j * h * h / 2,
            b.a + b.j * h, b.j};
  }

 private:
  // Integrates with plateaus A, B; the final position; the segment start states when asked.
  double integrate(double A, double B, std::array<LawState, 7>* starts) const {
    const std::array<double, 7> jerk{A / d_[0], 0.0, -A / d_[2], 0.0, -B / d_[4], 0.0, B / d_[6]};
    const std::array<double, 7> a0{0.0, A, A, 0.0, 0.0, -B, -B};
    double s = 0.0, v = 0.0;
    for (std::size_t i = 0; i < 7; ++i) {
      const double h = d_[i];
      if (starts != nullptr) (*starts)[i] = {s, v, a0[i], jerk[i]};
      s += v * h + a0[i] * h * h / 2 + jerk[i] * h * h * h / 6;
      v += a0[i] * h + jerk[i] * h * h / 2;
    }
    return s;
  }

  Durations d_;
  double stroke_;
  double A_{}, B_{};
  std::array<double, 8> t_{};
  std::array<LawState, 7> start_{};
};

}  // namespace slosh::test
