#include "slosh/core/law/seven_segment.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "solve/dual.hpp"

namespace slosh {

namespace {

std::string format_seconds(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

bool is_ramp(std::size_t i) {
  return i % 2 == 0;
}

}  // namespace

namespace {

double left_to_right_sum(const Durations& d) {
  double sum = 0.0;
  for (double x : d) sum += x;
  return sum;
}

}  // namespace

namespace {

/// Walks segment i towards closing the sum, inside [lo, hi]: the rounded residual first (one step
/// unless a later addition rounds), then single ulps (the left-to-right sum is monotone in d[i],
/// so stepping towards T reaches it or steps over it by rounding); when the ulps of a short
/// segment are too fine to get there, bisect_segment. True when the sum is T.
bool bisect_segment(Durations& d, double motion_time, std::size_t i, double lo, double hi);

bool walk_segment(Durations& d, double motion_time, std::size_t i, double lo, double hi) {
  const double start = d[i];
  for (int step = 0; step < 4; ++step) {
    const double residual = motion_time - left_to_right_sum(d);
    if (residual == 0.0) return true;
    d[i] = std::clamp(d[i] + residual, lo, hi);
  }
  for (int step = 0; step < 64; ++step) {
    const double residual = motion_time - left_to_right_sum(d);
    if (residual == 0.0) return true;
    const double next = std::nextafter(d[i], residual > 0.0 ? INFINITY : -INFINITY);
    if (next < lo || next > hi) break;
    d[i] = next;
  }
  if (left_to_right_sum(d) == motion_time) return true;
  d[i] = start;
  return bisect_segment(d, motion_time, i, lo, hi);
}

/// Moves segment i, inside [lo, hi], to the value whose left-to-right sum is T. The sum is
/// monotone in d[i]: a bracket [a, b] with sum(a) < T <= sum(b) is grown from the residual, then
/// bisected down to adjacent doubles; b is then the least value reaching T. True when its sum is
/// T (else no value of d[i] gives T, and d[i] is left at the nearer end).
bool bisect_segment(Durations& d, double motion_time, std::size_t i, double lo, double hi) {
  auto sum_at = [&](double x) {
    d[i] = x;
    return left_to_right_sum(d);
  };
  const double start = d[i];
  const double residual = motion_time - sum_at(start);
  if (residual == 0.0) return true;
  double step = 4.0 * std::abs(residual);
  double a = start, b = start;
  for (int grow = 0; grow < 64; ++grow, step *= 2.0) {
    if (residual > 0.0) {
      b = std::min(hi, start + step);
      if (sum_at(b) >= motion_time || b == hi) break;
      a = b;
    } else {
      a = std::max(lo, start - step);
      if (sum_at(a) < motion_time || a == lo) break;
      b = a;
    }
  }
  if (sum_at(b) < motion_time || sum_at(a) > motion_time) {
    d[i] = start;  // T is beyond the bounds of this segment
    return false;
  }
  if (sum_at(a) == motion_time) return true;
  // sum(a) < T <= sum(b)
  for (int halve = 0; halve < 2100 && std::nextafter(a, b) < b; ++halve) {
    const double m = a + 0.5 * (b - a);
    if (m <= a || m >= b) break;
    (sum_at(m) >= motion_time ? b : a) = m;
  }
  if (sum_at(b) == motion_time) return true;
  const double below = motion_time - sum_at(a);
  const double above = sum_at(b) - motion_time;
  d[i] = below <= above ? a : b;
  return false;
}

}  // namespace

void close_sum(Durations& d, double motion_time, std::size_t into) {
  Durations lower{};
  Durations upper;
  upper.fill(INFINITY);
  close_sum(d, motion_time, into, lower, upper);
}

void close_sum(Durations& d, double motion_time, std::size_t into, const Durations& lower,
               const Durations& upper) {
  // A segment that is exactly 0 stays 0 (durations below 1 ns are 0, never a subnormal), and no
  // segment leaves its bounds: a ramp on min_ramp may only grow.
  auto movable = [&](std::size_t i) { return d[i] != 0.0 && lower[i] < upper[i]; };
  const Durations start = d;
  if (movable(into) && walk_segment(d, motion_time, into, lower[into], upper[into])) return;
  d = start;
  // Rounding can leave no value of d[into] whose sum is T (the sum steps over T from one ulp to
  // the next): an ulp or two on another segment, inside its bounds, changes the rounding of the
  // partial sums; then d[into] closes the sum again.
  for (std::size_t j = 0; j < kSegments; ++j) {
    if (j == into || !movable(j)) continue;
    for (double direction : {INFINITY, -INFINITY}) {
      for (int k = 1; k <= 4; ++k) {
        Durations trial = start;
        for (int n = 0; n < k; ++n) trial[j] = std::nextafter(trial[j], direction);
        if (trial[j] < lower[j] || trial[j] > upper[j]) break;
        if (!movable(into)) {
          if (left_to_right_sum(trial) == motion_time) {
            d = trial;
            return;
          }
          continue;
        }
        if (walk_segment(trial, motion_time, into, lower[into], upper[into])) {
          d = trial;
          return;
        }
      }
    }
  }
  // No exact sum within a few ulps (not met in practice): the other segments, longest first,
  // each inside its bounds, in the same way; the sum stays within an ulp or two of T otherwise.
  std::array<std::size_t, kSegments> order{};
  for (std::size_t i = 0; i < kSegments; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return d[a] > d[b]; });
  for (std::size_t i : order) {
    if (movable(i) && walk_segment(d, motion_time, i, lower[i], upper[i])) return;
  }
}

Durations clean_durations(Durations d, double motion_time) {
  std::size_t longest = 0;
  for (std::size_t i = 0; i < kSegments; ++i) {
    if (std::abs(d[i]) < kZeroDuration) d[i] = 0.0;
    if (d[i] > d[longest]) longest = i;
  }
  close_sum(d, motion_time, longest);
  return d;
}

std::optional<std::string> check_admissible(const Durations& d, const AdmissibilityRules& rules) {
  double sum = 0.0;
  for (std::size_t i = 0; i < kSegments; ++i) {
    if (!std::isfinite(d[i])) {
      return "durations_s[" + std::to_string(i) + "] is not a finite number";
    }
    if (is_ramp(i) && d[i] < rules.min_ramp) {
      return "durations_s[" + std::to_string(i) + "] = " + format_seconds(d[i]) +
             " s is below the minimum ramp duration " + format_seconds(rules.min_ramp) + " s";
    }
    if (!is_ramp(i) && d[i] < 0.0) {
      return "durations_s[" + std::to_string(i) + "] = " + format_seconds(d[i]) +
             " s is negative: plateaus must be >= 0 s";
    }
    sum += d[i];
  }
  if (std::abs(sum - rules.motion_time) > rules.sum_tolerance) {
    return "durations_s sum to " + format_seconds(sum) + " s but the motion time is " +
           format_seconds(rules.motion_time) + " s (tolerance " +
           format_seconds(rules.sum_tolerance) + " s)";
  }
  return std::nullopt;
}

template <typename T>
PlateauLevelsT<T> plateau_levels(const std::array<T, kSegments>& d, T stroke) {
  const T t1 = d[0];
  const T t2 = t1 + d[1];
  const T t4 = t2 + d[2] + d[3];
  const T t5 = t4 + d[4];
  const T t6 = t5 + d[5];
  const T half(0.5);
  const T third = T(1.0) / T(3.0);
  const T sixth = T(1.0) / T(6.0);
  // Areas and first moments of the unit positive lobe (segments 1-3) and negative lobe (5-7).
  const T area_p = half * d[0] + d[1] + half * d[2];
  const T moment_p =
      third * d[0] * d[0] + half * d[1] * (t1 + t2) + half * t2 * d[2] + sixth * d[2] * d[2];
  const T area_n = half * d[4] + d[5] + half * d[6];
  const T moment_n = half * t4 * d[4] + third * d[4] * d[4] + half * d[5] * (t5 + t6) +
                     half * t6 * d[6] + sixth * d[6] * d[6];
  const T v = stroke / (moment_n / area_n - moment_p / area_p);
  return {v / area_p, v / area_n, v};
}

template PlateauLevelsT<double> plateau_levels(const std::array<double, kSegments>&, double);
template PlateauLevelsT<long double> plateau_levels(const std::array<long double, kSegments>&,
                                                    long double);
template PlateauLevelsT<Dual7> plateau_levels(const std::array<Dual7, kSegments>&, Dual7);

SevenSegmentLaw::SevenSegmentLaw(const Durations& durations, double stroke)
    : durations_(durations), stroke_(stroke) {
  for (std::size_t i = 0; i < kSegments; ++i) {
    if (!std::isfinite(durations[i]) || durations[i] < 0.0 || (is_ramp(i) && durations[i] <= 0.0)) {
      throw std::invalid_argument("seven-segment law: durations_s[" + std::to_string(i) +
                                  "] = " + format_seconds(durations[i]) +
                                  " s is not allowed (ramps > 0, plateaus >= 0)");
    }
  }
  const auto lv = plateau_levels(durations, stroke);
  if (!std::isfinite(lv.A) || !std::isfinite(lv.B) || lv.A <= 0.0 || lv.B <= 0.0) {
    throw std::invalid_argument("seven-segment law: durations give A = " + format_seconds(lv.A) +
                                ", B = " + format_seconds(lv.B) + " (must be finite and > 0)");
  }
  levels_ = {lv.A, lv.B, lv.v_peak};
  const auto J = jerks();
  for (std::size_t i = 0; i < kSegments; ++i) {
    if (!std::isfinite(J[i])) {
      throw std::invalid_argument("seven-segment law: durations_s[" + std::to_string(i) +
                                  "] gives an infinite jerk");
    }
  }
  const std::array<double, kSegments> a_start{0.0, lv.A, lv.A, 0.0, 0.0, -lv.B, -lv.B};
  std::vector<LawPiece> pieces;
  double t = 0.0;
  for (std::size_t i = 0; i < kSegments; ++i) {
    if (durations[i] > 0.0) {
      LawPiece p{t, t + durations[i]};
      p.poly = {a_start[i], J[i], 0.0, 0.0};
      pieces.push_back(p);
    }
    t += durations[i];
  }
  law_ = MotionLaw("seven_segment", std::move(pieces));
}

std::array<double, kSegments + 1> SevenSegmentLaw::switch_times() const {
  std::array<double, kSegments + 1> t{};
  for (std::size_t i = 0; i < kSegments; ++i) t[i + 1] = t[i] + durations_[i];
  return t;
}

double SevenSegmentLaw::motion_time() const {
  return switch_times().back();
}

std::array<double, kSegments> SevenSegmentLaw::jerks() const {
  const auto& d = durations_;
  return {levels_.A / d[0], 0.0, -levels_.A / d[2], 0.0, -levels_.B / d[4], 0.0, levels_.B / d[6]};
}

double SevenSegmentLaw::jerk_integral() const {
  const auto J = jerks();
  double sum = 0.0;
  for (std::size_t i = 0; i < kSegments; ++i) sum += J[i] * J[i] * durations_[i];
  return sum;
}

Durations uniform_durations(double motion_time) {
  Durations d;
  d.fill(motion_time / static_cast<double>(kSegments));
  // The cruise takes the ulps that make the sum T (the lobes stay mirror images).
  close_sum(d, motion_time, 3);
  return d;
}

}  // namespace slosh
