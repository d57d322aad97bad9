// The rectangular tank's linear and nonlinear model parameters against the closed forms of
// potential-flow theory re-typed here, their limits (shallow and deep fill, quasi-static tilt),
// and published approximations and numbers (Housner 1963; Sun et al. 1992; the critical depth of
// Faltinsen 1974 / Faltinsen et al. 2000; Penney & Price 1952).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_model.hpp"

namespace slosh {
namespace test_rectangular_model {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;

// The thesis bench's water (rho = 1000 kg/m^3, mu = 1.0e-3 Pa s).
Fluid water() {
  return thesis_format().fluid;
}

TEST(RectangularModel, FrequenciesAreTheStandingWaveDispersionRelation) {
  const RectangularTank tank{0.12, 0.08, 0.0};
  const double h = 0.05;
  RectangularModelOptions options;
  options.modes = 4;
  const RectangularModel m = make_rectangular_model(tank, h, water(), options);
  for (int n = 1; n <= 4; ++n) {
    const double kl = (2 * n - 1) * kPi / 0.12;
    const double kw = (2 * n - 1) * kPi / 0.08;
    EXPECT_NEAR(m.along_length.omega[n - 1], std::sqrt(kG * kl * std::tanh(kl * h)), 1e-12);
    EXPECT_NEAR(m.along_width.omega[n - 1], std::sqrt(kG * kw * std::tanh(kw * h)), 1e-12);
  }
  // A 120 mm cup filled 50 mm: f_1 = 2.3707 Hz along L (hand computation of the formula).
  EXPECT_NEAR(m.along_length.omega[0] / (2 * kPi), 2.3707, 5e-4);
  EXPECT_EQ(m.along_length.fluid_mass, 1000.0 * 0.12 * 0.08 * 0.05);
  EXPECT_EQ(m.along_width.fluid_mass, m.along_length.fluid_mass);
}

// Housner (1963), "The dynamic behavior of water tanks", Bull. Seismol. Soc. Am. 53(2), the
// rectangular tank of half-length l: omega_1^2 = 1.58 g / l tanh(1.58 h / l) and the convective
// mass m_1 / m_f = 0.527 (l / h) tanh(1.58 h / l) (1.58 for pi/2 and 0.527 for 16/pi^3: his
// rounded approximation of the exact first term, 1.5 % and 3 % off at most;
// also the form of ACI 350.3 and Eurocode 8-4). The exact values agree within its accuracy.
TEST(RectangularModel, FirstModeMatchesHousnersPublishedApproximation) {
  for (double hl : {0.2, 0.3, 0.5, 0.75, 1.0, 1.5}) {
    const double L = 0.1, h = hl * L, l = L / 2.0;
    const double w2_housner = 1.58 * kG / l * std::tanh(1.58 * h / l);
    const double m_housner = 0.527 * (l / h) * std::tanh(1.58 * h / l);
    const double w = rectangular_frequency(L, h, 1);
    EXPECT_NEAR(w * w / w2_housner, 1.0, 0.015) << "h/L " << hl;
    EXPECT_NEAR(rectangular_sloshing_mass(1.0, L, h, 1) / m_housner, 1.0, 0.03) << "h/L " << hl;
  }
}

TEST(RectangularModel, SloshingMassesTendToTheFluidMassInShallowFill) {
  // tanh(k h) -> k h: m_n -> m_f 8 / ((2n - 1)^2 pi^2), whose sum over n is m_f (sum of the odd
  // inverse squares = pi^2 / 8): in very shallow fill all the liquid sloshes.
  const double L = 0.1, h = 1e-5;
  double sum = 0.0;
  for (int n = 1; n <= 20000; ++n) sum += rectangular_sloshing_mass(1.0, L, h, n);
  EXPECT_NEAR(sum, 1.0, 2e-4);
}

TEST(RectangularModel, SloshingMassesVanishRelativeToTheFluidInDeepFill) {
  // tanh -> 1: m_n h / (m_f L) -> 8 / ((2n - 1)^3 pi^3), summing to 7 zeta(3) / pi^3: the
  // sloshing mass stays that of a layer ~0.27 L deep, the rest moves as a rigid body.
  const double L = 0.1;
  const double zeta3 = 1.2020569031595942;
  for (double h : {1.0, 10.0}) {
    double sum = 0.0;
    for (int n = 1; n <= 2000; ++n) sum += rectangular_sloshing_mass(1.0, L, h, n);
    EXPECT_NEAR(sum * h / L, 7.0 * zeta3 / (kPi * kPi * kPi), 1e-6);
  }
  EXPECT_NEAR(rectangular_sloshing_mass(1.0, L, 1.0, 1) * 1.0 / L, 8.0 / (kPi * kPi * kPi), 1e-12);
}

TEST(RectangularModel, QuasiStaticWallHeightIsTheTiltedPlane) {
  // Under a constant acceleration a the potential-flow free surface is the plane of slope a/g,
  // so the wall rises a L / (2 g). The modal static response x_n = -a / w_n^2 summed with the
  // wall gains converges to it; with N modes it is the partial sum of 8 / ((2n - 1)^2 pi^2).
  const double L = 0.12, h = 0.05, a = 2.0;
  double eta = 0.0, partial = 0.0;
  for (int n = 1; n <= 4000; ++n) {
    const double w = rectangular_frequency(L, h, n);
    eta += rectangular_wall_gain(L, h, n) * a / (w * w);
    if (n <= 3) partial += 8.0 / ((2 * n - 1) * (2 * n - 1) * kPi * kPi);
  }
  EXPECT_NEAR(eta / (a * L / (2 * kG)), 1.0, 1e-4);
  double three = 0.0;
  for (int n = 1; n <= 3; ++n) {
    const double w = rectangular_frequency(L, h, n);
    three += rectangular_wall_gain(L, h, n) * a / (w * w);
  }
  EXPECT_NEAR(three / (a * L / (2 * kG)), partial, 1e-12);
}

TEST(RectangularModel, WallGainIsTheMomentOfTheModeShape) {
  // Equivalent-model consistency: the sloshing mass times its displacement is the first moment
  // of the mode's surface, rho W int x eta_n(x) dx with eta_n = beta_n sin(k_n x) and wall value
  // (-1)^(n+1) beta_n = G_n x_n, integrated here by the midpoint rule.
  const double L = 0.12, W = 0.08, h = 0.04, rho = 1000.0;
  const double mf = rho * L * W * h;
  for (int n = 1; n <= 3; ++n) {
    const double k = (2 * n - 1) * kPi / L;
    const double beta = rectangular_wall_gain(L, h, n) * ((n % 2 == 1) ? 1.0 : -1.0);  // x_n = 1
    const int steps = 20000;
    double moment = 0.0;
    for (int i = 0; i < steps; ++i) {
      const double x = -L / 2 + (i + 0.5) * L / steps;
      moment += x * beta * std::sin(k * x) * L / steps;
    }
    EXPECT_NEAR(rho * W * moment, rectangular_sloshing_mass(mf, L, h, n), 1e-9 * mf) << n;
  }
}

TEST(RectangularModel, BoundaryLayerDampingMatchesItsFormula) {
  const double L = 0.12, W = 0.08, h = 0.05, nu = 1e-6;
  const double k = kPi / L;
  const double w = std::sqrt(kG * k * std::tanh(k * h));
  const double expected =
      std::sqrt(nu / (2 * w)) * (k * (1 - 2 * h / L) / std::sinh(2 * k * h) + 1 / L + 1 / W);
  EXPECT_DOUBLE_EQ(rectangular_damping_ratio(L, W, h, nu, 1), expected);
  const RectangularModel m = make_rectangular_model({L, W, 0.0}, h, water());
  EXPECT_DOUBLE_EQ(m.along_length.zeta, expected);
  EXPECT_DOUBLE_EQ(m.along_width.zeta, rectangular_damping_ratio(W, L, h, nu, 1));
  // Order of magnitude of the cylinder's correlation for a cup of the same size (~4e-3).
  EXPECT_NEAR(m.along_length.zeta, 3.9e-3, 1e-4);
}

// The damping from its definition, integrated here by the midpoint rule: the mean Stokes-layer
// dissipation (rho U^2 / 2) sqrt(nu w / 2) per unit area of wetted wall and bottom, U the
// tangential velocity amplitude of the mode phi = cos(k x) cosh(k (z + h)), x in [0, L], over
// 2 w times its energy (rho / 2) int |grad phi|^2 dV, breadth B across.
TEST(RectangularModel, BoundaryLayerDampingIsTheStokesLayerDissipationOverTheModeEnergy) {
  const double L = 0.12, B = 0.08, nu = 1e-6;
  for (double h : {0.02, 0.05, 0.15}) {
    for (int n = 1; n <= 2; ++n) {
      const double k = (2 * n - 1) * kPi / L;
      const double w = std::sqrt(kG * k * std::tanh(k * h));
      auto u = [&](double x, double z) { return -k * std::sin(k * x) * std::cosh(k * (z + h)); };
      auto v = [&](double x, double z) { return k * std::cos(k * x) * std::sinh(k * (z + h)); };
      const int N = 600;
      const double dx = L / N, dz = h / N;
      double volume = 0, bottom = 0, ends = 0, sides = 0;
      for (int i = 0; i < N; ++i) {
        const double x = (i + 0.5) * dx;
        bottom += u(x, -h) * u(x, -h) * dx * B;
        for (int j = 0; j < N; ++j) {
          const double z = -h + (j + 0.5) * dz;
          const double q = u(x, z) * u(x, z) + v(x, z) * v(x, z);
          volume += q * dx * dz * B;
          sides += 2 * q * dx * dz;  // both velocity components are tangential on y = 0, B
        }
      }
      for (int j = 0; j < N; ++j) {
        const double z = -h + (j + 0.5) * dz;
        ends += (v(0.0, z) * v(0.0, z) + v(L, z) * v(L, z)) * dz * B;  // only w is tangential
      }
      const double zeta = std::sqrt(nu * w / 2) * (bottom + ends + sides) / (2 * w * volume);
      EXPECT_NEAR(rectangular_damping_ratio(L, B, h, nu, n) / zeta, 1.0, 1e-5) << h << " " << n;
    }
  }
}

// Sun, Fujino, Pacheco & Chaiseri (1992), "Modelling of tuned liquid damper (TLD)", J. Wind
// Eng. Ind. Aerodyn. 41-44: in shallow water zeta = 1/(2h) sqrt(nu / (2 omega)) (1 + 2h/b + S),
// b the breadth across the motion, S the surface-contamination term (0 for a clean surface).
TEST(RectangularModel, BoundaryLayerDampingTendsToTheShallowWaterTldFormula) {
  const double L = 0.5, b = 0.3, nu = 1e-6;
  for (double h : {0.005, 0.01}) {
    const double w = rectangular_frequency(L, h, 1);
    const double tld = 1 / (2 * h) * std::sqrt(nu / (2 * w)) * (1 + 2 * h / b);
    EXPECT_NEAR(rectangular_damping_ratio(L, b, h, nu, 1) / tld, 1.0, 7 * (h / L) * (h / L) + 1e-3)
        << h;
  }
}

TEST(RectangularModel, ExplicitDampingAndCalibrationScalesAreApplied) {
  RectangularModelOptions options;
  options.explicit_zeta = 0.02;
  options.omega_scale = 1.1;
  options.height_gain = 0.9;
  const RectangularModel m = make_rectangular_model({0.1, 0.06, 30.0}, 0.04, water(), options);
  EXPECT_EQ(m.along_length.zeta, 0.02);
  EXPECT_EQ(m.along_width.zeta, 0.02);
  EXPECT_EQ(m.orientation_deg, 30.0);
  EXPECT_DOUBLE_EQ(m.along_width.omega[0], 1.1 * rectangular_frequency(0.06, 0.04, 1));
  EXPECT_DOUBLE_EQ(m.along_width.eta_gain[1], 0.9 * rectangular_wall_gain(0.06, 0.04, 2));
  EXPECT_DOUBLE_EQ(m.along_length.K, 0.9 * rectangular_wall_gain(0.1, 0.04, 1) * 0.1);
}

// The third-order frequency of a standing wave changes sign at the critical depth h/L = 0.3368
// (Faltinsen 1974, J. Ship Res. 18; Faltinsen et al. 2000, J. Fluid Mech. 407, sec. 5: soft
// spring above, hard spring below), and tends in deep water to omega_1 (1 - (k A)^2 / 8)
// (Penney & Price 1952, Phil. Trans. R. Soc. A 244).
TEST(RectangularModel, NonlinearCorrectionChangesSignAtThePublishedCriticalDepth) {
  const double L = 1.0;
  EXPECT_GT(rectangular_frequency_correction(L, 0.3360), 0.0);
  EXPECT_LT(rectangular_frequency_correction(L, 0.3376), 0.0);
  EXPECT_NEAR(rectangular_frequency_correction(L, 5.0), -1.0 / 8.0, 1e-12);
  // Shallower fill hardens strongly (T^-4).
  EXPECT_GT(rectangular_frequency_correction(L, 0.1), 1.0);
}

TEST(RectangularModel, DuffingCoefficientReproducesTheThirdOrderBackbone) {
  // Backbone of x'' + w^2 x (1 + alpha (x/L)^2) = 0: w (1 + 3 alpha (A/L)^2 / 8); with the wall
  // amplitude G_1 A it must equal w (1 + c (pi G_1 A / L)^2).
  const double L = 0.1;
  for (double h : {0.025, 0.05, 0.1}) {
    const SloshingModel m =
        make_rectangular_direction_model({L, 0.05, 0.0}, h, water(), TankAxis::kLength, {});
    const double g1 = 4 * std::tanh(kPi * h / L) / kPi;
    EXPECT_NEAR(3 * m.alpha / 8, rectangular_frequency_correction(L, h) * kPi * kPi * g1 * g1,
                1e-12);
    EXPECT_EQ(m.C, 0.0);
    EXPECT_EQ(m.radius, L);
    EXPECT_NEAR(m.K, g1 * L, 1e-15);
  }
}

}  // namespace test_rectangular_model
}  // namespace slosh
