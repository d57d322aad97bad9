// simulate(): validity warnings of SPEC §2 (exact texts at their thresholds) and consistency of
// the one-call result with the responses it is built from.

#include <gtest/gtest.h>

#include "slosh/core/response/simulation.hpp"
#include "support/fixtures.hpp"

namespace slosh {
namespace test_simulation {

TEST(ValidityWarnings, NoneOnTheThesisFormatWithinLimits) {
  EXPECT_TRUE(validity_warnings(thesis_format(), 10.0, 0.05, 0.05).empty());
}

TEST(ValidityWarnings, AccelerationAboveTheLinearModelLimit) {
  const auto w = validity_warnings(thesis_format(), 10.5, 0.01, 0.01);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].text,
            "peak |acceleration| 10.50 m/s^2 exceeds 10 m/s^2: the linear model is unreliable at "
            "this level (JDSMC 2022 sec. 5, 7); rely on the nonlinear prediction");
}

TEST(ValidityWarnings, SmallRadiusAndShallowFill) {
  Format f = thesis_format();
  f.container.radius = 0.012;
  f.fill_height = 0.003;
  const auto w = validity_warnings(f, 1.0, 0.001, 0.001);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].text,
            "radius 12.0 mm is below 15 mm: surface tension matters and is not modelled");
  EXPECT_EQ(w[1].text, "fill ratio h/R = 0.250 is below 0.3: shallow-liquid regime, not modelled");
  f.container.radius = 0.015;
  f.fill_height = 0.0045;  // exactly at both limits: no warning
  EXPECT_TRUE(validity_warnings(f, 1.0, 0.001, 0.001).empty());
}

TEST(ValidityWarnings, FreeBoardUsesTheLargerPrediction) {
  Format f = thesis_format();
  f.container.height = 0.120;  // 38 mm of free board
  EXPECT_TRUE(validity_warnings(f, 5.0, 0.037, 0.030).empty());
  const auto w = validity_warnings(f, 5.0, 0.030, 0.0391);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].text,
            "predicted sloshing height during the motion 39.1 mm (nonlinear model; linear model "
            "30.0 mm) exceeds the free board 38.0 mm (container height - fill height): liquid "
            "will spill");
  const auto linear = validity_warnings(f, 5.0, 0.0773, 0.0582);
  ASSERT_EQ(linear.size(), 1u);
  EXPECT_EQ(linear[0].text,
            "predicted sloshing height during the motion 77.3 mm (linear model; nonlinear model "
            "58.2 mm) exceeds the free board 38.0 mm (container height - fill height): liquid "
            "will spill");
}

TEST(Simulate, AgreesWithTheResponsesAndSamplesTheSeries) {
  const Format f = thesis_format();
  const SevenSegmentLaw law(test::kAsymmetricDurations, f.stroke);
  SimulationOptions options;
  options.rest_time = 0.5;
  options.sample_period = 0.01;
  const SimulationResult r = simulate(f, law.law(), options);
  const SloshingModel model = make_sloshing_model(f, options.model);
  const SloshPeaks lin = LinearResponse(model, law.law(), 0.5).peaks();
  const SloshPeaks nl = NonlinearResponse(model, law.law(), 0.5).peaks();
  EXPECT_EQ(r.linear.motion.value, lin.motion.value);
  EXPECT_EQ(r.nonlinear.rest.value, nl.rest.value);
  ASSERT_TRUE(r.series.has_value());
  ASSERT_EQ(r.series->t.size(), 151u);  // 0, 0.01, ..., 1.5 s
  for (std::size_t i = 0; i < r.series->t.size(); i += 10) {
    const double t = r.series->t[i];
    EXPECT_NEAR(t, 0.01 * static_cast<double>(i), 1e-12);
    EXPECT_EQ(r.series->s[i], law.law().at(t).position);
    EXPECT_LE(std::abs(r.series->eta_linear[i]),
              t <= 1.0 ? r.linear.motion.value : r.linear.rest.value);
  }
  EXPECT_NEAR(r.kinematics.a_peak_positive, law.A(), 1e-12);
  EXPECT_NEAR(r.kinematics.a_peak_negative, law.B(), 1e-12);
  EXPECT_NEAR(r.kinematics.v_peak, law.v_peak(), 1e-12);
}

}  // namespace test_simulation
}  // namespace slosh
