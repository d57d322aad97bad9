#include "solve/duration_space.hpp"

#include <algorithm>
#include <cmath>

#include "solve/dual.hpp"

namespace slosh::detail {

namespace {

constexpr std::uint64_t kStartSeed{20251123};  // fixed: the same request gives the same starts
constexpr double kBoundSnap{kZeroDuration};    // [s]

std::array<Dual7, kSegments> variables(const double* d) {
  std::array<Dual7, kSegments> dd;
  for (std::size_t i = 0; i < kSegments; ++i) dd[i] = Dual7::variable(d[i], i);
  return dd;
}

}  // namespace

DurationSpace::DurationSpace(const Format& format, const PlanOptions& options)
    : motion_time(format.motion_time),
      stroke(format.stroke),
      limits(options.limits),
      warm_start(options.warm_start) {
  const double T = format.motion_time;
  lower = {options.min_ramp, options.plateau_min[0], options.min_ramp, 0.0,
           options.min_ramp, options.plateau_min[1], options.min_ramp};
  upper.fill(T);
  if (options.fix_constant_velocity_zero) upper[3] = 0.0;
  if (options.drive_profile == DriveProfile::kMoveAbsolute) {
    one_jerk.emplace(T, options.min_ramp, upper[3], options.plateau_min);
  }
}

int DurationSpace::limit_count() const {
  return (limits.a_max ? 2 : 0) + (limits.v_max ? 1 : 0) + (limits.j_max ? 4 : 0);
}

void DurationSpace::limit_constraints(const double* d, double* g, double* jac, int stride) const {
  const auto dd = variables(d);
  const auto lv = plateau_levels(dd, Dual7(stroke));
  int row = 0;
  auto put = [&](const Dual7& value) {
    g[row] = value.v - 1.0;
    if (jac != nullptr) {
      for (std::size_t i = 0; i < kSegments; ++i) jac[row * stride + i] = value.d[i];
    }
    ++row;
  };
  if (limits.a_max) {
    put(lv.A / Dual7(*limits.a_max));
    put(lv.B / Dual7(*limits.a_max));
  }
  if (limits.v_max) put(lv.v_peak / Dual7(*limits.v_max));
  if (limits.j_max) {
    const Dual7 j(*limits.j_max);
    put(lv.A / (j * dd[0]));
    put(lv.A / (j * dd[2]));
    put(lv.B / (j * dd[4]));
    put(lv.B / (j * dd[6]));
  }
}

NlpProblem DurationSpace::problem(int extra, double extra_upper) const {
  NlpProblem p;
  p.lower.assign(lower.begin(), lower.end());
  p.upper.assign(upper.begin(), upper.end());
  for (int i = 0; i < extra; ++i) {
    p.lower.push_back(0.0);
    p.upper.push_back(extra_upper);
  }
  NlpProblem::LinearEquality sum;
  sum.a.assign(kSegments, 1.0);
  sum.a.resize(kSegments + static_cast<std::size_t>(extra), 0.0);
  sum.b = motion_time;
  p.equalities.push_back(sum);
  if (extra > 0) {
    const std::size_t n = p.lower.size();
    p.objective = [n](const double* x, double* grad) {
      if (grad != nullptr) {
        std::fill(grad, grad + n, 0.0);
        grad[kSegments] = 1.0;
      }
      return x[kSegments];
    };
  }
  return p;
}

Durations DurationSpace::from_weights(const Durations& w) const {
  double room = motion_time;
  double total = 0.0;
  for (std::size_t i = 0; i < kSegments; ++i) {
    room -= lower[i];
    if (upper[i] > lower[i]) total += w[i];
  }
  Durations d = lower;
  for (std::size_t i = 0; i < kSegments; ++i) {
    if (upper[i] > lower[i] && total > 0.0) d[i] += room * w[i] / total;
  }
  return polish(d.data());
}

std::optional<Durations> DurationSpace::only_point() const {
  double room = motion_time;
  for (double l : lower) room -= l;
  if (std::abs(room) > kBoundSnap) return std::nullopt;
  return polish(lower.data());
}

std::vector<Durations> DurationSpace::starts(int random_count) const {
  const std::vector<Durations> all = general_starts(random_count);
  if (!one_jerk) return all;
  // In the family (from_weights and the warm start went through polish(), which restates a point
  // there; the uniform law is in it) distinct starts can coincide: each is kept once, in order.
  std::vector<Durations> distinct;
  for (const Durations& d : all) {
    if (std::find(distinct.begin(), distinct.end(), d) == distinct.end()) distinct.push_back(d);
  }
  return distinct;
}

bool DurationSpace::uniform_inside() const {
  const Durations uniform = uniform_durations(motion_time);
  for (std::size_t i = 0; i < kSegments; ++i) {
    // Within round-off of a bound (T/7 equal to min_ramp_s) the uniform law holds it, as
    // polish() and the verification of the options count it.
    if (!(uniform[i] >= lower[i] - kBoundSnap && uniform[i] <= upper[i] + kBoundSnap)) return false;
  }
  return true;
}

Durations DurationSpace::nearest_uniform() const {
  return uniform_inside() ? uniform_durations(motion_time)
                          : from_weights(Durations{1, 1, 1, 1, 1, 1, 1});
}

std::vector<Durations> DurationSpace::general_starts(int random_count) const {
  std::vector<Durations> out;
  const Durations first = nearest_uniform();
  if (warm_start) {
    double sum = 0.0;
    for (double d : *warm_start) sum += d;
    Durations scaled;
    for (std::size_t i = 0; i < kSegments; ++i) scaled[i] = (*warm_start)[i] * motion_time / sum;
    out.push_back(polish(scaled.data()));
    if (out.front() != first) out.push_back(first);
    return out;
  }
  out.push_back(first);
  // Symmetric families (ramp, plateau, ramp, cruise, ramp, plateau, ramp): short ramps with
  // long plateaus, long ramps without plateaus, and balanced shapes with and without cruise.
  const std::array<Durations, 4> families{
      Durations{1, 3, 1, 1, 1, 3, 1}, Durations{3, 0.2, 3, 1, 3, 0.2, 3},
      Durations{2, 1, 2, 4, 2, 1, 2}, Durations{1, 1, 1, 0.2, 1, 1, 1}};
  for (const auto& w : families) out.push_back(from_weights(w));
  std::mt19937_64 rng(kStartSeed);
  std::uniform_real_distribution<double> u(1e-12, 1.0);
  for (int k = 0; k < random_count; ++k) {
    Durations w;
    for (double& wi : w) wi = -std::log(u(rng));  // Dirichlet(1, ..., 1) weights
    out.push_back(from_weights(w));
  }
  return out;
}

Durations DurationSpace::polish(const double* x) const {
  Durations d;
  if (one_jerk) {
    const OneJerkChart::Point p = one_jerk->repair(one_jerk->coordinates(x));
    d = one_jerk->durations(p.data(), nullptr);
  } else {
    std::copy(x, x + kSegments, d.begin());
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < kSegments; ++i) {
    d[i] = std::clamp(d[i], lower[i], upper[i]);
    // Solver round-off next to a bound (1e-18 s plateaus) lands on the bound.
    if (d[i] - lower[i] < kBoundSnap) d[i] = lower[i];
    if (upper[i] - d[i] < kBoundSnap) d[i] = upper[i];
    sum += d[i];
  }
  // Spread the residual over the segments that can take it, twice so the round-off of the first
  // pass is absorbed as well; a segment on its lower bound (a zero plateau) takes none of it.
  for (int pass = 0; pass < 2; ++pass) {
    double residual = motion_time - sum;
    if (residual == 0.0) break;
    double room_total = 0.0;
    Durations room{};
    for (std::size_t i = 0; i < kSegments; ++i) {
      room[i] = residual > 0.0 ? (d[i] > lower[i] ? upper[i] - d[i] : 0.0) : d[i] - lower[i];
      room_total += room[i];
    }
    if (room_total <= 0.0) break;
    sum = 0.0;
    for (std::size_t i = 0; i < kSegments; ++i) {
      d[i] = std::clamp(d[i] + residual * room[i] / room_total, lower[i], upper[i]);
      sum += d[i];
    }
  }
  // The last ulps: on the segment with the most room above its bound, none of them pushing a
  // segment past its bounds (a ramp on min_ramp an ulp below it is refused by the law parser).
  std::size_t best = 0;
  for (std::size_t i = 1; i < kSegments; ++i) {
    if (d[i] - lower[i] > d[best] - lower[best]) best = i;
  }
  close_sum(d, motion_time, best, lower, upper);
  return d;
}

double jerk_integral(const double* d, double stroke, double* grad) {
  const auto dd = variables(d);
  const auto lv = plateau_levels(dd, Dual7(stroke));
  // J_i^2 dT_i = A^2 / dT_i on the ramps of the positive lobe, B^2 / dT_i on the negative one.
  const Dual7 value =
      lv.A * lv.A / dd[0] + lv.A * lv.A / dd[2] + lv.B * lv.B / dd[4] + lv.B * lv.B / dd[6];
  if (grad != nullptr) {
    for (std::size_t i = 0; i < kSegments; ++i) grad[i] = value.d[i];
  }
  return value.v;
}

double peak_acceleration(const Durations& d, double stroke) {
  const auto lv = plateau_levels(d, stroke);
  return std::max(lv.A, lv.B);
}

}  // namespace slosh::detail
