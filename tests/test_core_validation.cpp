// The core validates its own inputs: plan() of every strategy and simulate() return a
// structured InvalidInput naming the core input, its value and its allowed set (core names, SI
// units), never a throw or a non-finite number; every PlanInput maps to an API field path.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "slosh/api/core_input.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/response/simulation.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/fixtures.hpp"

namespace slosh {
namespace test_core_validation {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// plan() of every strategy refuses (format, options) naming `input`; returns the refusal of the
/// last strategy (they are all the same).
InvalidInput expect_plan_refuses(const Format& f, const PlanOptions& o, PlanInput input) {
  InvalidInput last;
  for (Strategy s : enum_values<Strategy>()) {
    PlanResult r;
    EXPECT_NO_THROW(r = plan(f, s, o)) << to_string(s);
    EXPECT_TRUE(r.invalid_input.has_value()) << to_string(s) << ": " << r.message;
    if (!r.invalid_input) continue;
    EXPECT_EQ(r.invalid_input->input, input) << to_string(s) << ": " << r.message;
    EXPECT_EQ(r.status, SolveStatus::kFailed);
    EXPECT_EQ(r.message, "invalid input: " + r.invalid_input->message + "; nothing was planned");
    // The relation is worded by the floors it relates (min_ramp, plateau_min).
    const std::string named =
        input == PlanInput::kRampsAndPlateaus ? "min_ramp" : std::string(name_of(input));
    EXPECT_TRUE(contains(r.message, named)) << r.message;
    EXPECT_EQ(r.prediction.nonlinear.motion.value, 0.0);
    last = *r.invalid_input;
  }
  const std::optional<InvalidInput> direct = validate_plan_input(f, o);
  EXPECT_TRUE(direct.has_value());
  if (direct) {
    EXPECT_EQ(direct->message, last.message);
  }
  return last;
}

TEST(CoreValidation, NBandZeroNamesTheInputTheValueAndTheBound) {
  PlanOptions o;
  o.n_band = 0;
  const InvalidInput e = expect_plan_refuses(thesis_format(), o, PlanInput::kNBand);
  EXPECT_EQ(e.index, -1);
  EXPECT_EQ(e.value, 0.0);
  EXPECT_EQ(e.bounds.lo, 1.0);
  EXPECT_EQ(e.bounds.hi, static_cast<double>(kMaxBandPoints));
  EXPECT_FALSE(e.bounds.lo_open || e.bounds.hi_open);
  EXPECT_EQ(e.allowed(), "in [1, 2001]");
  EXPECT_EQ(e.message, "n_band = 0 must be finite and in [1, 2001]");
}

TEST(CoreValidation, ContainerRadiusZero) {
  Format f = thesis_format();
  f.container.radius = 0.0;
  const InvalidInput e = expect_plan_refuses(f, {}, PlanInput::kContainerRadius);
  EXPECT_EQ(e.value, 0.0);
  EXPECT_EQ(e.bounds.lo, kMinPlanRadius);
  EXPECT_EQ(e.bounds.hi, kMaxPlanLength);
  EXPECT_EQ(e.message, "container_radius = 0 m must be finite and in [0.0001, 1e+03] m");
}

TEST(CoreValidation, NaNInTheFormatAndTheOptions) {
  Format fill = thesis_format();
  fill.fill_height = kNaN;
  EXPECT_TRUE(std::isnan(expect_plan_refuses(fill, {}, PlanInput::kFillHeight).value));
  Format stroke = thesis_format();
  stroke.stroke = kNaN;
  const InvalidInput s = expect_plan_refuses(stroke, {}, PlanInput::kStroke);
  EXPECT_TRUE(contains(s.message, "stroke = nan m")) << s.message;
  PlanOptions a_max;
  a_max.limits.a_max = kNaN;
  const InvalidInput a = expect_plan_refuses(thesis_format(), a_max, PlanInput::kAMax);
  EXPECT_EQ(a.allowed(), "> 0 m/s^2");
  PlanOptions weights;
  weights.weights = {1.0, kNaN, 1.0};
  const InvalidInput w = expect_plan_refuses(thesis_format(), weights, PlanInput::kWeights);
  EXPECT_EQ(w.index, 1);
  EXPECT_EQ(w.message, "weights[1] = nan must be finite and >= 0");
}

TEST(CoreValidation, TheRelationOfTheFloorsCarriesTheSumAndTheMotionTime) {
  PlanOptions o;
  o.min_ramp = 0.2;
  o.plateau_min = {0.1, 0.12};
  const InvalidInput e = expect_plan_refuses(thesis_format(), o, PlanInput::kRampsAndPlateaus);
  EXPECT_NEAR(e.value, 1.02, 1e-12);
  EXPECT_EQ(e.bounds.hi, 1.0);
  EXPECT_EQ(e.allowed(), "<= 1 s");
}

TEST(CoreValidation, OptionsValidateAndIsValidAgree) {
  PlanOptions o;
  o.eta_rest_max = -1e-3;
  const std::optional<InvalidInput> e = o.validate(thesis_format());
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->input, PlanInput::kEtaRestMax);
  EXPECT_EQ(e->message, "eta_rest_max = -0.001 m must be finite and > 0 m");
  InvalidInput out;
  EXPECT_FALSE(o.is_valid(thesis_format(), &out));
  EXPECT_EQ(out.message, e->message);
  EXPECT_FALSE(o.is_valid(thesis_format(), nullptr));
  EXPECT_FALSE(PlanOptions{}.validate(thesis_format()).has_value());
}

TEST(CoreValidation, SimulateRefusesInsteadOfAssuming) {
  const Format good = thesis_format();
  const MotionLaw law = SevenSegmentLaw(uniform_durations(1.0), 0.8).law();
  const SimulationOptions options;
  EXPECT_FALSE(simulate(good, law, options).invalid_input.has_value());
  auto refused_as = [&](const Format& f, const MotionLaw& l, const SimulationOptions& o,
                        PlanInput input) {
    SimulationResult r;
    ASSERT_NO_THROW(r = simulate(f, l, o));
    ASSERT_TRUE(r.invalid_input.has_value()) << name_of(input);
    EXPECT_EQ(r.invalid_input->input, input) << r.invalid_input->message;
    EXPECT_TRUE(contains(r.invalid_input->message, std::string(name_of(input))))
        << r.invalid_input->message;
    EXPECT_FALSE(r.series.has_value());
    EXPECT_TRUE(r.warnings.empty());
  };
  Format fill = good;
  fill.fill_height = kNaN;
  refused_as(fill, law, options, PlanInput::kFillHeight);
  Format stroke = good;
  stroke.stroke = kNaN;
  refused_as(stroke, law, options, PlanInput::kStroke);
  Format radius = good;
  radius.container.radius = 0.0;
  refused_as(radius, law, options, PlanInput::kContainerRadius);
  SimulationOptions modes;
  modes.model.modes = 0;
  refused_as(good, law, modes, PlanInput::kModes);
  SimulationOptions alpha;
  alpha.model.alpha = kNaN;
  refused_as(good, law, alpha, PlanInput::kAlpha);
  SimulationOptions rest;
  rest.rest_time = kNaN;
  refused_as(good, law, rest, PlanInput::kRestTime);
  SimulationOptions period;
  period.sample_period = 0.0;
  refused_as(good, law, period, PlanInput::kSamplePeriod);
  refused_as(good, MotionLaw{}, options, PlanInput::kLaw);
}

TEST(CoreValidation, EveryInputHasACoreNameAUnitAndAnApiFieldPath) {
  for (PlanInput input : enum_values<PlanInput>()) {
    EXPECT_FALSE(name_of(input).empty());
    for (api::Endpoint endpoint : {api::Endpoint::kPlan, api::Endpoint::kSimulate}) {
      const std::string_view path = api::api_field_path(input, endpoint);
      EXPECT_FALSE(path.empty()) << name_of(input);
      EXPECT_TRUE(
          path == "format" || path == "options" || path == "law" || path == "sample_period_s" ||
          path == "rest_time_s" || path.starts_with("format.") || path.starts_with("options.") ||
          // the min-time options are top-level members of its request
          path == "motion_time_max_s" || path == "free_board_margin_mm" || path == "scan_step_s" ||
          path == "max_plans" || path == "curve_factor" || path == "refine_excess")
          << path;
    }
  }
  EXPECT_EQ(api::api_field_path(PlanInput::kMinRamp), "options.min_ramp_s");
  EXPECT_EQ(api::api_field_path(PlanInput::kAMax), "options.limits.a_max");
  EXPECT_EQ(api::api_field_path(PlanInput::kContainerRadius), "format.container.radius_mm");
  EXPECT_EQ(api::api_field_path(PlanInput::kRestTime, api::Endpoint::kSimulate), "rest_time_s");
  EXPECT_EQ(input_unit(PlanInput::kIirTau), "1/s");
}

TEST(CoreValidation, TheApiWordsARefusalAsItAlwaysHas) {
  PlanOptions o;
  o.min_ramp = 0.2;
  o.plateau_min = {0.15, 0.1};
  const Format f = thesis_format();
  const std::optional<InvalidInput> e = o.validate(f);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(api::input_sentence(*e, f, o),
            "min_ramp_s = 0.2 s and plateau_min_s = [0.15, 0.1] s need 4 ramps + 2 plateaus = "
            "1.05 s, more than the motion time 1 s: allowed min_ramp_s <= (T - plateau "
            "minimums) / 4 = 0.188 s");
  PlanOptions n_band;
  n_band.n_band = 0;
  EXPECT_EQ(api::plan_refusal(*validate_plan_input(f, n_band), f, n_band),
            "invalid input: n_band = 0 must be in [1, 2001]; nothing was planned");
  Format radius = f;
  radius.container.radius = 0.0;
  EXPECT_EQ(api::plan_refusal(*validate_plan_input(radius, {}), radius, {}),
            "invalid input: container radius 0 m must be finite and in [0.0001, 1e+03] m; "
            "nothing was planned");
  PlanOptions eta;
  eta.eta_rest_max = 0.0;
  EXPECT_EQ(api::input_sentence(*eta.validate(f), f, eta), "eta_rest_max_mm = 0 mm must be > 0");
}

}  // namespace test_core_validation
}  // namespace slosh

namespace slosh {
namespace test_core_validation {

PlanCandidate candidate(SolveStatus status, double eta_motion, double eta_rest, double a_peak) {
  PlanCandidate c;
  c.status = status;
  c.prediction.nonlinear.motion.value = eta_motion;
  c.prediction.nonlinear.rest.value = eta_rest;
  c.prediction.kinematics.a_peak_positive = a_peak;
  c.prediction.kinematics.a_peak_negative = a_peak;
  return c;
}

// choose_auto is a pure function of the verified candidates (SPEC §5's rule).
TEST(ChooseAuto, LowestRestAmongTheMotionsWithinFivePercentOfTheBest) {
  const std::vector<PlanCandidate> c{
      candidate(SolveStatus::kOptimal, 0.010, 0.004, 4.0),    // baseline
      candidate(SolveStatus::kOptimal, 0.0050, 0.0020, 5.0),  // best motion
      candidate(SolveStatus::kOptimal, 0.0052, 0.0010, 6.0),  // within 5 %, least rest
      candidate(SolveStatus::kOptimal, 0.0060, 0.0001, 3.0),  // outside 5 %
      candidate(SolveStatus::kInfeasible, 0.001, 0.0, 1.0),   // does not compete
  };
  const AutoChoice choice = choose_auto(c, {false, false, false, false, false});
  EXPECT_TRUE(choice.eligible);
  EXPECT_TRUE(choice.any_not_worse);
  EXPECT_EQ(choice.index, 2u);
}

TEST(ChooseAuto, TiesGoToTheLowerPeakAccelerationAndWorseCandidatesWait) {
  const std::vector<PlanCandidate> tie{
      candidate(SolveStatus::kOptimal, 0.005, 0.001, 5.0),
      candidate(SolveStatus::kAcceptable, 0.005, 0.001 * (1.0 + 1e-9), 4.0),
  };
  EXPECT_EQ(choose_auto(tie, {false, false}).index, 1u);
  // A worse-than-baseline candidate does not compete while one that is not remains.
  EXPECT_EQ(choose_auto(tie, {false, true}).index, 0u);
  const AutoChoice none =
      choose_auto({candidate(SolveStatus::kFailed, 0.0, 0.0, 0.0)}, std::vector<bool>{false});
  EXPECT_FALSE(none.eligible);
  EXPECT_EQ(none.index, 0u);
}

// Each candidate that lost says why, in the order the rule excludes, with the deciding figures.
TEST(ChooseAuto, SaysWhyEachOtherCandidateLost) {
  std::vector<PlanCandidate> c{
      candidate(SolveStatus::kOptimal, 0.010, 0.004, 4.0),
      candidate(SolveStatus::kOptimal, 0.0050, 0.0020, 5.0),
      candidate(SolveStatus::kOptimal, 0.0052, 0.0010, 6.0),
      candidate(SolveStatus::kOptimal, 0.0051, 0.0010 * (1.0 + 1e-9), 6.5),
      candidate(SolveStatus::kInfeasible, 0.001, 0.0, 1.0),
      candidate(SolveStatus::kOptimal, 0.0049, 0.0001, 1.0),
  };
  const Strategy names[] = {Strategy::kBaseline,   Strategy::kNotch,    Strategy::kMultiNotch,
                            Strategy::kTimeDomain, Strategy::kFirChain, Strategy::kShaper};
  for (std::size_t k = 0; k < c.size(); ++k) c[k].strategy = names[k];
  const AutoChoice choice = choose_auto(c, {false, false, false, false, false, true});
  ASSERT_EQ(choice.index, 2u);
  const std::vector<CandidateLoss> lost{CandidateLoss::kMotionAboveBest,
                                        CandidateLoss::kHigherRest,
                                        CandidateLoss::kNone,
                                        CandidateLoss::kTieOnRest,
                                        CandidateLoss::kNotUsable,
                                        CandidateLoss::kWorseThanBaseline};
  EXPECT_EQ(choice.lost, lost);
  const std::vector<std::string> detail{
      "eta_motion 10 mm is more than 5 % above the best 5 mm",
      "eta_rest 2 mm vs 1 mm of the chosen multi_notch",
      "",
      "eta_rest 1 mm ties with the chosen multi_notch and its peak acceleration 6.5 m/s^2 is not "
      "below 6 m/s^2",
      "status infeasible: only optimal, acceptable and time_limit candidates compete",
      "worse than the uniform law (its worse_than_baseline warning) while a candidate that is not "
      "competes"};
  EXPECT_EQ(choice.lost_detail, detail);
}

}  // namespace test_core_validation
}  // namespace slosh
