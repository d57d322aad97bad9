// Calibration of a rectangular tank whose moves drive both of its directions
// (core/model/rectangular_calibration): measured runs synthesized from a known pair of
// per-direction scales by each direction's NonlinearResponse (independent of the dual-number
// integrator the fit differentiates), with seeded noise, and the scales recovered; a run along
// one side fits that side only and says the other is unmeasured; peaks of one turned move cannot
// tell the directions apart, and the answer refuses, naming the moves that would.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/fluid.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_calibration.hpp"
#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh {
namespace {

// The README's cup: 120 x 80 mm, 50 mm of water, moved 200 mm.
Format cup() {
  Format f;
  f.container.rectangular = RectangularTank{0.12, 0.08, 0.0};
  f.container.height = 0.07;
  f.fill_height = 0.05;
  f.fluid = *find_fluid("water");
  f.stroke = 0.2;
  f.motion_time = 1.0;
  return f;
}

// The truth: the length's frequencies 6 % below the theory with zeta 0.012, the width's 4 %
// above with zeta 0.02, the wall heights 0.9 of the theory's.
constexpr double kOmegaL = 0.94, kZetaL = 0.012, kOmegaW = 1.04, kZetaW = 0.02, kGain = 0.9;

// Gaussian noise from the raw 32-bit outputs of mt19937 (Box-Muller; fully specified).
class Noise {
 public:
  explicit Noise(std::uint32_t seed) : rng_(seed) {}
  double operator()(double sd) {
    const double u1 = (static_cast<double>(rng_()) + 1.0) / 4294967297.0;
    const double u2 = static_cast<double>(rng_()) / 4294967296.0;
    return sd * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::mt19937 rng_;
};

// The truth's driven direction models at `orientation_deg`: the theory's, scaled by hand.
std::vector<DrivenDirection> truth_directions(double orientation_deg) {
  RectangularModel m = rectangular_model_of(cup(), {});
  for (auto [model, scale, zeta] : {std::tuple{&m.along_length, kOmegaL, kZetaL},
                                    std::tuple{&m.along_width, kOmegaW, kZetaW}}) {
    for (double& w : model->omega) w *= scale;
    for (double& g : model->eta_gain) g *= kGain;
    model->K *= kGain;
    model->zeta = zeta;
  }
  m.orientation_deg = orientation_deg;
  return driven_directions(m);
}

// simulate's wave height of the truth: the signed wall ahead when one direction moves, the
// highest corner when both do.
struct Truth {
  std::vector<NonlinearResponse> responses;
  std::vector<double> signs;
  Truth(double orientation_deg, const MotionLaw& law, double rest) {
    for (const DrivenDirection& d : truth_directions(orientation_deg)) {
      responses.emplace_back(d.model, law, rest);
      signs.push_back(d.component < 0.0 ? -1.0 : 1.0);
    }
  }
  [[nodiscard]] double eta(double t) const {
    if (responses.size() == 1) return signs[0] * responses[0].eta(t);
    return std::abs(responses[0].eta(t)) + std::abs(responses[1].eta(t));
  }
};

RectangularMeasuredMove measured(double orientation_deg, const MotionLaw& law, Noise& noise,
                                 double sd = 0.2e-3) {
  RectangularMeasuredMove m;
  m.orientation_deg = orientation_deg;
  m.move.name = "at " + std::to_string(orientation_deg) + " deg";
  m.move.law = law;
  const double rest = 1.5;
  const Truth truth(orientation_deg, law, rest);
  MeasuredSeries s;
  for (double t = 0.0; t <= law.duration() + rest; t += 0.01) {  // 100 Hz
    s.t.push_back(t);
    s.eta.push_back(truth.eta(t) + noise(sd));
  }
  m.move.series = std::move(s);
  return m;
}

void expect_within(const FittedParameter& p, double truth, double sigmas, const char* what) {
  ASSERT_TRUE(p.standard_error.has_value()) << what;
  EXPECT_EQ(p.state, ParameterState::kFitted) << what;
  EXPECT_LE(std::abs(p.value - truth), sigmas * *p.standard_error)
      << what << ": " << p.value << " vs " << truth << " +- " << *p.standard_error;
  EXPECT_NE(p.value, p.prior) << what;
}

TEST(RectangularCalibration, RecoversBothDirectionsScalesFromTurnedRuns) {
  Noise noise(2026u);
  const MotionLaw law = make_modified_trapezoid_law(0.2, 1.0);
  const std::vector<RectangularMeasuredMove> moves{measured(30.0, law, noise),
                                                   measured(60.0, law, noise)};
  const RectangularCalibrationResult fit = calibrate_rectangular(cup(), {}, moves, {});
  ASSERT_TRUE(fit.refused.empty()) << fit.refused;
  EXPECT_EQ(fit.status, CalibrationStatus::kConverged);
  EXPECT_TRUE(fit.notes.empty()) << fit.notes.front();
  EXPECT_TRUE(fit.length.measured && fit.width.measured);
  expect_within(fit.length.omega_scale, kOmegaL, 3.0, "length omega_scale");
  expect_within(fit.length.zeta, kZetaL, 3.0, "length zeta");
  expect_within(fit.width.omega_scale, kOmegaW, 3.0, "width omega_scale");
  expect_within(fit.width.zeta, kZetaW, 3.0, "width zeta");
  expect_within(fit.height_gain, kGain, 3.0, "height_gain");
  // The frequency scales to a fraction of their difference (10 %).
  EXPECT_LT(std::abs(fit.length.omega_scale.value - kOmegaL), 2e-3);
  EXPECT_LT(std::abs(fit.width.omega_scale.value - kOmegaW), 2e-3);
  EXPECT_NEAR(fit.sigma, 0.2e-3, 0.02e-3);
  for (const MoveFit& m : fit.moves) EXPECT_LT(m.rms_after, m.rms_before);
}

TEST(RectangularCalibration, ARunAlongOneSideFitsThatSideAndSaysTheOtherIsUnmeasured) {
  Noise noise(7u);
  const MotionLaw law = make_poly5_law(0.2, 1.0);
  // Along W at -90 degrees: the wave ahead is the width's, with the sign of the share.
  const RectangularCalibrationResult fit =
      calibrate_rectangular(cup(), {}, {measured(-90.0, law, noise)}, {});
  ASSERT_TRUE(fit.refused.empty()) << fit.refused;
  EXPECT_TRUE(fit.width.measured);
  EXPECT_FALSE(fit.length.measured);
  expect_within(fit.width.omega_scale, kOmegaW, 3.0, "width omega_scale");
  expect_within(fit.width.zeta, kZetaW, 3.0, "width zeta");
  for (const FittedParameter* p : {&fit.length.omega_scale, &fit.length.zeta}) {
    EXPECT_EQ(p->state, ParameterState::kFixed);
    EXPECT_EQ(p->value, p->prior);
    EXPECT_FALSE(p->standard_error.has_value());
  }
  EXPECT_EQ(fit.length.omega_scale.prior, 1.0);
  ASSERT_EQ(fit.notes.size(), 1u);
  EXPECT_EQ(fit.notes.front(),
            "the length is unmeasured: no move drives it, so its omega_scale and zeta keep their "
            "priors; a move along it (orientation 0 or 180 degrees) or a turned move would "
            "measure it");
}

TEST(RectangularCalibration, PeaksOfOneSquareDiagonalMoveCannotSeparateTheDirections) {
  // A square tank at 45 degrees: both directions are the same oscillator, driven alike, and
  // their peaks say nothing about which is which.
  Format f = cup();
  f.container.rectangular = RectangularTank{0.1, 0.1, 0.0};
  const MotionLaw law = make_modified_trapezoid_law(0.2, 1.0);
  RectangularMeasuredMove m;
  m.orientation_deg = 45.0;
  m.move.law = law;
  m.move.peaks = MeasuredPeaks{12e-3, 4e-3, 1.0};
  CalibrationSettings settings;
  settings.parameters[1].fit = false;  // zeta held: only the two frequency scales and the gain
  const RectangularCalibrationResult fit = calibrate_rectangular(f, {}, {m}, settings);
  EXPECT_EQ(fit.status, CalibrationStatus::kFailed);
  EXPECT_NE(fit.refused.find("the length's omega_scale and the width's omega_scale cannot be "
                             "separated by these moves ("),
            std::string::npos)
      << fit.refused;
  EXPECT_NE(fit.refused.find("): add a move along the length (orientation 0 or 180 degrees) and "
                             "one along the width (90 or -90 degrees), or a measured series of a "
                             "turned move, whose two frequencies tell the directions apart"),
            std::string::npos)
      << fit.refused;
  EXPECT_EQ(fit.length.omega_scale.value, fit.length.omega_scale.prior);
  EXPECT_EQ(fit.width.omega_scale.value, fit.width.omega_scale.prior);
}

}  // namespace
}  // namespace slosh
