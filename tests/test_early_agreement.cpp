// The multi-start's early stop (three starts converged to the best point: the remaining starts are
// not solved) against the whole start set (PlanOptions::all_starts), on the thesis format and on
// seeded random formats for every optimising strategy: the early-stopped plan's objective is never
// worse than the best of all starts beyond 1e-9 relative, and its status is the same.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "slosh/core/model/format.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh {
namespace {

constexpr std::uint64_t kSeed{30};
constexpr int kFormats{20};
/// Relative objective excess the early stop may add over all starts [-].
constexpr double kRelative{1e-9};
/// Absolute floor of that excess (objectives at an exact zero, ~1e-14 of X_ref^2) [-].
constexpr double kAbsolute{1e-13};

// R 15-60 mm, h/R 0.5-3, s 0.2-1 m, T 0.4-2 s, water (the property test's ranges).
std::vector<Format> random_formats() {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Format> out;
  for (int k = 0; k < kFormats; ++k) {
    Format f;
    f.container.radius = 0.015 + 0.045 * u(rng);
    f.fill_height = (0.5 + 2.5 * u(rng)) * f.container.radius;
    f.fluid = Fluid{"custom", 1000.0, 0.001, ""};
    f.stroke = 0.2 + 0.8 * u(rng);
    f.motion_time = 0.4 + 1.6 * u(rng);
    out.push_back(f);
  }
  return out;
}

std::string name_of(const Format& f, Strategy s) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "%s: R %.6g mm, h %.6g mm, s %.6g mm, T %.10g s",
                std::string(to_string(s)).c_str(), f.container.radius * 1e3, f.fill_height * 1e3,
                f.stroke * 1e3, f.motion_time);
  return buf;
}

void expect_as_good(const Format& f, Strategy s, int* fewer) {
  PlanOptions early;
  early.robustness = false;
  PlanOptions all = early;
  all.all_starts = true;
  const PlanResult a = plan(f, s, all);
  const PlanResult e = plan(f, s, early);
  SCOPED_TRACE(name_of(f, s));
  ASSERT_EQ(e.status, a.status);
  if (a.status != SolveStatus::kOptimal && a.status != SolveStatus::kAcceptable) return;
  EXPECT_LE(e.solver.objective,
            a.solver.objective + kRelative * std::abs(a.solver.objective) + kAbsolute)
      << "all starts " << a.solver.objective << " (" << a.solver.starts << " starts), early "
      << e.solver.objective << " (" << e.solver.starts << " starts)";
  if (e.solver.starts < a.solver.starts) ++*fewer;
}

class EarlyAgreement : public ::testing::TestWithParam<Strategy> {};

TEST_P(EarlyAgreement, IsAsGoodAsEveryStart) {
  int fewer = 0;
  expect_as_good(thesis_format(), GetParam(), &fewer);
  for (const Format& f : random_formats()) expect_as_good(f, GetParam(), &fewer);
  // The early stop must actually stop somewhere, or this test compares a code path with itself.
  RecordProperty("plans_with_fewer_starts", fewer);
}

INSTANTIATE_TEST_SUITE_P(Strategies, EarlyAgreement,
                         ::testing::Values(Strategy::kNotch, Strategy::kMultiNotch,
                                           Strategy::kMinJerkBand, Strategy::kTimeDomain,
                                           Strategy::kAuto));

}  // namespace
}  // namespace slosh
