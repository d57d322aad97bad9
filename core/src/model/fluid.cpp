#include "slosh/core/model/fluid.hpp"

#include <vector>

namespace slosh {

std::span<const Fluid> fluid_catalogue() {
  static const std::vector<Fluid> catalogue{
      {"water", 998.2, 1.0016e-3,
       "IAPWS-95 density and IAPWS 2008 viscosity formulation, pure water at 20 °C"},
      {"ethanol", 789.3, 1.19e-3,
       "CRC Handbook of Chemistry and Physics, 97th ed.: ethanol density and viscosity at 20 °C"},
      {"isopropanol", 786.0, 2.37e-3,
       "CRC Handbook of Chemistry and Physics, 97th ed.: 2-propanol at 20 °C"},
      {"glycerol_water_50", 1126.3, 6.0e-3,
       "Segur & Oberstar, Ind. Eng. Chem. 43 (1951) 2117: 50 % w/w glycerol in water at 20 °C"},
      {"milk", 1032.0, 2.0e-3,
       "Fox & McSweeney, Dairy Chemistry and Biochemistry (2015): whole milk, 3.5 % fat, 20 °C"},
      {"olive_oil", 915.0, 84.0e-3,
       "Sahasrabudhe et al., J. Food Sci. Technol. 54 (2017): olive oil at 20 °C"},
      {"sunflower_oil", 920.0, 60.0e-3,
       "Fasina & Colley, Int. J. Food Prop. 11 (2008) 738: sunflower oil at 20 °C"},
      {"light_syrup", 1176.4, 6.2e-3,
       "ICUMSA / Asadi, Beet-Sugar Handbook (2007): 40 % w/w sucrose solution at 20 °C"},
  };
  return catalogue;
}

std::optional<Fluid> find_fluid(std::string_view name) {
  for (const Fluid& f : fluid_catalogue()) {
    if (f.name == name) return f;
  }
  return std::nullopt;
}

}  // namespace slosh
