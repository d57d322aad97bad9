// notch and multi_notch spend their starts economically (StartPolicy): a run is left once it
// reaches an optimum an earlier start found, and notch's random starts stop after two in a row
// find nothing lower. A seeded property test over random formats, half of them with random
// machine limits: the economical search reaches the optimum (or, limits unreachable, the least
// violation) of the plain multi-start that runs every start to its end (StartUse::kEvery, the
// independent path), and its law holds the notch checked here.
// SLOSH_PROPERTY_FORMATS=N runs N formats instead of 40.

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
namespace test_start_policy {

constexpr int kDefaultFormats{40};
constexpr std::uint64_t kSeed{3012};
/// Relative difference of one optimum reached by two runs (the solver's tolerance is 1e-10;
/// runs stopped by round-off end within a few 1e-9) [-].
constexpr double kSameOptimum{1e-6};

int format_count() {
  return test::property_format_count(kDefaultFormats);
}

struct Case {
  Format format;
  PlanOptions options;
};

/// R 15-60 mm, h/R 0.5-3, s 0.2-1 m, T from the uniform law's peak acceleration of 2-10 m/s^2
/// (A = 49/12 s / T^2 for equal durations); odd cases with limits drawn around the uniform law's
/// figures (a_max 0.95-1.55 A, j_max 0.6-2.1 A / (T/7), v_max 1.2-1.8 s / T), some unreachable.
Case random_case(std::mt19937_64& rng, bool limits) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Case c;
  const double R = 0.015 + 0.045 * u(rng);
  c.format.container.radius = R;
  c.format.fill_height = (0.5 + 2.5 * u(rng)) * R;
  c.format.fluid = Fluid{"custom", 1000.0, 0.001, ""};
  c.format.stroke = 0.2 + 0.8 * u(rng);
  const double a_peak = 2.0 + 8.0 * u(rng);
  const double T = std::sqrt(49.0 / 12.0 * c.format.stroke / a_peak);
  c.format.motion_time = T;
  if (limits) {
    const double A = a_peak;
    if (u(rng) < 0.7) c.options.limits.a_max = A * (0.95 + 0.6 * u(rng));
    if (u(rng) < 0.7) c.options.limits.j_max = A / (T / 7.0) * (0.6 + 1.5 * u(rng));
    if (u(rng) < 0.5) c.options.limits.v_max = c.format.stroke / T * (1.2 + 0.6 * u(rng));
  }
  return c;
}

std::string name_of(const Case& c) {
  char buf[300];
  const MachineLimits& l = c.options.limits;
  std::snprintf(buf, sizeof buf,
                "R %.6g mm, h %.6g mm, s %.6g mm, T %.10g s, a_max %.6g, j_max %.6g, v_max %.6g",
                c.format.container.radius * 1e3, c.format.fill_height * 1e3, c.format.stroke * 1e3,
                c.format.motion_time, l.a_max.value_or(0.0), l.j_max.value_or(0.0),
                l.v_max.value_or(0.0));
  return buf;
}

bool met(SolveStatus s) {
  return s == SolveStatus::kOptimal || s == SolveStatus::kAcceptable;
}

/// The outcome's objective recomputed here from its durations: the jerk integral relative to the
/// uniform law's (notch), or the weighted |X|^2 at the three notches relative to X_ref^2.
double notch_objective(const detail::StrategyContext& c, const Durations& d) {
  const SevenSegmentLaw law(d, c.format.stroke);
  const SevenSegmentLaw uniform(uniform_durations(c.format.motion_time), c.format.stroke);
  return law.jerk_integral() / uniform.jerk_integral();
}

double multi_notch_objective(const detail::StrategyContext& c, const Durations& d) {
  const double w1 = c.design_model.omega1();
  const double p = c.p_notch;
  double f = 0.0;
  const double omegas[3] = {(1.0 - p) * w1, w1, (1.0 + p) * w1};
  for (int k = 0; k < 3; ++k) {
    f += c.options.weights[static_cast<std::size_t>(k)] *
         std::norm(seven_segment_spectrum(d, c.format.stroke, omegas[k])) / (c.x_ref * c.x_ref);
  }
  return f;
}

TEST(StartPolicy, EconomicalStartsReachThePlainMultiStartsOptimaOverRandomFormats) {
  std::mt19937_64 rng(kSeed);
  const int count = format_count();
  int notches = 0;
  for (int k = 0; k < count; ++k) {
    const Case cs = random_case(rng, k % 2 == 1);
    SCOPED_TRACE(name_of(cs));
    const SloshingModel model = make_sloshing_model(cs.format, cs.options.model);
    const detail::Deadline deadline(60.0);
    detail::StrategyContext c{cs.format, cs.options, model,
                              detail::DurationSpace(cs.format, cs.options), deadline};
    detail::set_design(c);
    detail::set_references(c, 1.0);

    const auto notch = detail::solve_notch(c, detail::StartUse::kEconomical);
    const auto notch_all = detail::solve_notch(c, detail::StartUse::kEvery);
    EXPECT_EQ(met(notch.status), met(notch_all.status))
        << notch.detail << " / " << notch_all.detail;
    EXPECT_LE(notch.evaluations, notch_all.evaluations);
    // An exact notch when the plain search finds one, else the deepest notch.
    const bool exact = notch.detail.rfind("exact notch", 0) == 0;
    EXPECT_EQ(exact, notch_all.detail.rfind("exact notch", 0) == 0);
    const auto X = seven_segment_spectrum(notch.durations, cs.format.stroke, model.omega1());
    const auto X_all =
        seven_segment_spectrum(notch_all.durations, cs.format.stroke, model.omega1());
    if (exact && met(notch.status)) {
      ++notches;
      // |Re X|, |Im X| <= 1e-6 X_ref at w1 (and a little round-off), the least jerk.
      EXPECT_LE(std::abs(X.real()), 1.01e-6 * c.x_ref);
      EXPECT_LE(std::abs(X.imag()), 1.01e-6 * c.x_ref);
      EXPECT_LE(notch_objective(c, notch.durations),
                notch_objective(c, notch_all.durations) * (1.0 + kSameOptimum));
    } else if (met(notch.status) && met(notch_all.status)) {
      EXPECT_LE(std::abs(X), std::abs(X_all) * (1.0 + kSameOptimum) + 1e-7 * c.x_ref);
    }

    const auto multi = detail::solve_multi_notch(c, detail::StartUse::kEconomical);
    const auto multi_all = detail::solve_multi_notch(c, detail::StartUse::kEvery);
    EXPECT_EQ(met(multi.status), met(multi_all.status))
        << multi.detail << " / " << multi_all.detail;
    EXPECT_LE(multi.evaluations, multi_all.evaluations);
    if (met(multi.status) && met(multi_all.status)) {
      EXPECT_LE(multi_notch_objective(c, multi.durations),
                multi_notch_objective(c, multi_all.durations) * (1.0 + kSameOptimum) + 1e-14);
    }
  }
  // The campaign exercises exact notches, not only unreachable limits.
  EXPECT_GT(notches, count / 3);
}

}  // namespace test_start_policy
}  // namespace slosh
