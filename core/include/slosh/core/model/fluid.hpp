#pragma once
// Liquids: a small catalogue of properties at 20 °C with the source of every figure.

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace slosh {

/// A Newtonian liquid.
struct Fluid {
  std::string name;          ///< catalogue name, or "custom"
  double density{1000.0};    ///< rho [kg/m^3]
  double viscosity{1.0e-3};  ///< dynamic viscosity mu [Pa·s]
  std::string source;        ///< where the figures come from

  /// Kinematic viscosity nu = mu / rho [m^2/s].
  [[nodiscard]] double kinematic_viscosity() const { return viscosity / density; }
};

/// The shipped catalogue (properties at 20 °C, atmospheric pressure).
[[nodiscard]] std::span<const Fluid> fluid_catalogue();

/// Looks up a catalogue fluid by name (exact, lower case); nullopt when unknown.
[[nodiscard]] std::optional<Fluid> find_fluid(std::string_view name);

}  // namespace slosh
