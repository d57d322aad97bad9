// min_jerk_band's band-constrained solves carry only the band rows that can be active near the
// current point (the rest are checked at each solution and join when above their bound). A
// seeded property test over random formats and band limits: the reduced solve's law meets the
// band on the fine check (recomputed here on a grid of its own), holds its durations, and its
// jerk integral is as low as the plain formulation's, which carries every row (the independent
// path, BandRowSelection::kAll). SLOSH_PROPERTY_FORMATS=N runs N formats instead of 40.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "strategy/strategies.hpp"
#include "support/random_format.hpp"

namespace slosh {
namespace test_band_rows {

constexpr int kDefaultFormats{40};
constexpr std::uint64_t kSeed{3011};
/// Relative difference of two optima of one problem found along two solver paths [-]: the
/// solver's tolerance is 1e-10, the exchange's bound tightening moves the optimum by less.
constexpr double kSameOptimum{1e-6};

int format_count() {
  return test::property_format_count(kDefaultFormats);
}

struct Case {
  Format format;
  PlanOptions options;
};

/// R 15-60 mm, h/R 0.5-3, s 0.2-1 m, T from the uniform law's peak acceleration of 2-10 m/s^2
/// (A = 49/12 s / T^2 for equal durations), tol_rel 5-40 %, band 5-25 %.
Case random_case(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Case c;
  const double R = 0.015 + 0.045 * u(rng);
  c.format.container.radius = R;
  c.format.fill_height = (0.5 + 2.5 * u(rng)) * R;
  c.format.fluid = Fluid{"custom", 1000.0, 0.001, ""};
  c.format.stroke = 0.2 + 0.8 * u(rng);
  const double a_peak = 2.0 + 8.0 * u(rng);
  c.format.motion_time = std::sqrt(49.0 / 12.0 * c.format.stroke / a_peak);
  c.options.tol_rel = 0.05 + 0.35 * u(rng);
  c.options.band = 0.05 + 0.2 * u(rng);
  return c;
}

std::string name_of(const Case& c) {
  char buf[240];
  std::snprintf(buf, sizeof buf, "R %.6g mm, h %.6g mm, s %.6g mm, T %.10g s, tol %.4g, band %.4g",
                c.format.container.radius * 1e3, c.format.fill_height * 1e3, c.format.stroke * 1e3,
                c.format.motion_time, c.options.tol_rel, c.options.band);
  return buf;
}

/// Largest |X| over [(1 - band), (1 + band)] w1 on 4001 points, each local maximum refined by
/// bisection on the sign of the derivative's difference quotient of |X|^2 (written here, not the
/// planner's band_peak).
double band_max(const Durations& d, double stroke, double w1, double band) {
  const auto mag = [&](double w) { return std::abs(seven_segment_spectrum(d, stroke, w)); };
  constexpr int kPoints{4001};
  const double lo = (1.0 - band) * w1;
  const double step = 2.0 * band * w1 / (kPoints - 1);
  double best = 0.0;
  double prev2 = -1.0, prev = -1.0;
  for (int k = 0; k < kPoints; ++k) {
    const double here = mag(lo + step * k);
    best = std::max(best, here);
    if (k >= 2 && prev >= prev2 && prev >= here) {
      double a = lo + step * (k - 2), b = lo + step * k;
      for (int it = 0; it < 80; ++it) {
        const double m = 0.5 * (a + b);
        const double h = 1e-7 * (b - a) + 1e-12 * m;
        if (mag(m + h) > mag(m - h)) {
          a = m;
        } else {
          b = m;
        }
      }
      best = std::max(best, mag(0.5 * (a + b)));
    }
    prev2 = prev;
    prev = here;
  }
  return best;
}

TEST(BandRows, ActiveRowsReachTheOptimumOfAllRowsOverRandomFormats) {
  std::mt19937_64 rng(kSeed);
  const int count = format_count();
  int met = 0;
  for (int k = 0; k < count; ++k) {
    const Case cs = random_case(rng);
    SCOPED_TRACE(name_of(cs));
    const SloshingModel model = make_sloshing_model(cs.format, cs.options.model);
    const detail::Deadline deadline(60.0);
    detail::StrategyContext c{cs.format, cs.options, model,
                              detail::DurationSpace(cs.format, cs.options), deadline};
    detail::set_design(c);
    detail::set_references(c, 1.0);
    const auto active = detail::solve_min_jerk_band(c, detail::BandRowSelection::kActive);
    const auto all = detail::solve_min_jerk_band(c, detail::BandRowSelection::kAll);
    const bool active_met =
        active.status == SolveStatus::kOptimal || active.status == SolveStatus::kAcceptable;
    const bool all_met =
        all.status == SolveStatus::kOptimal || all.status == SolveStatus::kAcceptable;
    // Every row the plain formulation meets, the reduced one meets too.
    EXPECT_EQ(active_met, all_met) << active.detail << " / " << all.detail;
    if (!active_met || !all_met) continue;
    ++met;
    double sum = 0.0;
    for (std::size_t i = 0; i < kSegments; ++i) {
      EXPECT_GE(active.durations[i], c.space.lower[i]);
      sum += active.durations[i];
    }
    EXPECT_NEAR(sum, cs.format.motion_time, 1e-12 * cs.format.motion_time);
    // x_ref recomputed the same way: the uniform law's largest |X| on the band.
    const Durations uniform = uniform_durations(cs.format.motion_time);
    const double w1 = model.omega1();
    const double x_ref = band_max(uniform, cs.format.stroke, w1, cs.options.band);
    EXPECT_NEAR(x_ref, c.x_ref, 1e-9 * x_ref);
    const double ratio = band_max(active.durations, cs.format.stroke, w1, cs.options.band) / x_ref;
    EXPECT_LE(ratio, cs.options.tol_rel * (1.0 + 2e-6));
    // As good as the plain formulation (never worse by more than the solvers' round-off).
    const double jerk = detail::jerk_integral(active.durations.data(), cs.format.stroke, nullptr);
    const double jerk_all = detail::jerk_integral(all.durations.data(), cs.format.stroke, nullptr);
    EXPECT_LE(jerk, jerk_all * (1.0 + kSameOptimum));
  }
  // The campaign exercises the band constraint, not only infeasible cases.
  EXPECT_GT(met, count / 4);
}

}  // namespace test_band_rows
}  // namespace slosh
