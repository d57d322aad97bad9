// Model parameters against the SPEC §2 reference values and against the formulas re-typed here.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slosh/core/model/fluid.hpp"
#include "slosh/core/model/sloshing_model.hpp"

#include "support/fixtures.hpp"

namespace slosh {
namespace test_sloshing_model {

// The thesis container: R = 48.5 mm, h = 82 mm, water with rho = 1000, mu = 1.0e-3.
TEST(SloshingModel, ThesisReferenceValues) {
  ModelOptions options;
  const SloshingModel m = make_sloshing_model(thesis_format(), options);
  ASSERT_EQ(m.modes(), 3);
  EXPECT_NEAR(m.omega[0], 19.260, 5e-4);
  EXPECT_NEAR(m.omega[0] / (2.0 * std::numbers::pi), 3.065, 5e-4);
  EXPECT_NEAR(m.omega[1], 32.84, 5e-3);
  EXPECT_NEAR(m.omega[2], 41.55, 5e-3);
  EXPECT_NEAR(m.zeta, 4.43e-3, 5e-6);
  EXPECT_NEAR(m.C, 1.834, 5e-4);
  EXPECT_NEAR(m.alpha, 0.58, 0.0);
}

TEST(SloshingModel, CatalogueWaterGivesSlightlyDifferentDamping) {
  // Catalogue water (998.2 kg/m^3, 1.0016 mPa s at 20 °C) is not the thesis' rounded water.
  Format f = thesis_format();
  f.fluid = *find_fluid("water");
  const double zeta = damping_ratio(f, DampingCorrelation::kThesis);
  EXPECT_NEAR(zeta, 4.44e-3, 5e-6);
  EXPECT_GT(zeta, damping_ratio(thesis_format(), DampingCorrelation::kThesis));
}

TEST(SloshingModel, DampingCorrelationsMatchTheirFormulas) {
  const Format f = thesis_format();
  const double R = 0.0485, h = 0.082, nu = 1.0e-3 / 1000.0;
  const double re1 = nu / std::sqrt(9.81 * R * R * R);
  const double hr = h / R;
  const double bracket =
      1.0 + 0.318 / std::sinh(1.84 * hr) * (1.0 + (1.0 - hr) / std::cosh(1.84 * hr));
  EXPECT_DOUBLE_EQ(damping_ratio(f, DampingCorrelation::kThesis), 0.79 * std::sqrt(re1) * bracket);
  EXPECT_DOUBLE_EQ(damping_ratio(f, DampingCorrelation::kPaper), 0.92 * std::sqrt(re1) * bracket);
  EXPECT_DOUBLE_EQ(damping_ratio(f, DampingCorrelation::kEq228),
                   2.89 / std::numbers::pi * std::sqrt(re1) * bracket);
  EXPECT_DOUBLE_EQ(damping_ratio(f, DampingCorrelation::kEq227),
                   0.83 * std::sqrt(re1) * std::tanh(1.84 * hr) *
                       (1.0 + 2.0 * (1.0 - hr) / std::cosh(3.68 * hr)));
}

TEST(SloshingModel, ExplicitDampingIsUsedAsGiven) {
  ModelOptions options;
  options.damping = DampingCorrelation::kExplicit;
  options.explicit_zeta = 0.0123;
  EXPECT_EQ(make_sloshing_model(thesis_format(), options).zeta, 0.0123);
}

TEST(SloshingModel, HeightGainsAgreeWithTheMassForm) {
  // eta = sum 8 tanh / (xi (xi^2 - 1)) x_n  ==  4 / (pi R^3 rho) sum m_n x_n  (SPEC §2).
  ModelOptions options;
  options.modes = 5;
  const SloshingModel m = make_sloshing_model(thesis_format(), options);
  ASSERT_EQ(m.modes(), 5);
  for (int n = 0; n < 5; ++n) {
    const double mass_form =
        4.0 / (std::numbers::pi * std::pow(m.radius, 3) * m.density) * m.mass[n];
    EXPECT_NEAR(m.eta_gain[n], mass_form, 1e-13) << "mode " << n + 1;
  }
}

TEST(SloshingModel, NonlinearGainAgreesWithEq236) {
  // K xbar = xi_1^2 m_1 x_1 / (pi R^3 rho) with xbar = x_1 / R, and C = omega_1^2 R / g.
  const SloshingModel m = make_sloshing_model(thesis_format(), {});
  const double xi1 = 1.841184;
  EXPECT_NEAR(m.K / m.radius,
              xi1 * xi1 * m.mass[0] / (std::numbers::pi * std::pow(m.radius, 3) * m.density),
              1e-13);
  EXPECT_NEAR(m.C, m.omega[0] * m.omega[0] * m.radius / 9.81, 1e-12);
}

TEST(SloshingModel, SloshingMassesAreAFractionOfTheFluidAndDecrease) {
  ModelOptions options;
  options.modes = 5;
  for (double h : {0.02, 0.05, 0.082, 0.2, 0.5}) {
    Format f = thesis_format();
    f.fill_height = h;
    const SloshingModel m = make_sloshing_model(f, options);
    EXPECT_NEAR(m.fluid_mass, std::numbers::pi * 0.0485 * 0.0485 * h * 1000.0, 1e-12);
    double total = 0.0;
    for (int n = 0; n < 5; ++n) {
      total += m.mass[n];
      if (n > 0) {
        EXPECT_LT(m.mass[n], m.mass[n - 1]);
        EXPECT_GT(m.omega[n], m.omega[n - 1]);
      }
    }
    EXPECT_LT(total, m.fluid_mass);
  }
}

TEST(SloshingModel, DeepLiquidLimitOfTheFrequency) {
  // tanh -> 1 for h >> R: omega_1 -> sqrt(g xi_1 / R).
  EXPECT_NEAR(natural_frequency(0.0485, 10.0, 1), std::sqrt(9.81 * 1.841184 / 0.0485), 1e-9);
}

TEST(FluidCatalogue, HoldsTheSpecFluidsWithSources) {
  for (const char* name : {"water", "ethanol", "isopropanol", "glycerol_water_50", "milk",
                           "olive_oil", "sunflower_oil", "light_syrup"}) {
    const auto f = find_fluid(name);
    ASSERT_TRUE(f.has_value()) << name;
    EXPECT_GT(f->density, 700.0) << name;
    EXPECT_LT(f->density, 1400.0) << name;
    EXPECT_GT(f->viscosity, 5e-4) << name;
    EXPECT_LT(f->viscosity, 0.2) << name;
    EXPECT_FALSE(f->source.empty()) << name;
  }
  EXPECT_FALSE(find_fluid("Water").has_value());
  EXPECT_FALSE(find_fluid("mercury").has_value());
}

}  // namespace test_sloshing_model
}  // namespace slosh
