#pragma once
// OpenFOAM v1912 as the independent reference: what every exported case shares — the file
// header and footer of a dictionary, numbers written so they read back exactly, and the mapping
// of rheosim's viscosity laws to OpenFOAM's transport models. OpenFOAM is used as a program, not
// a library (Debian packages no headers): the exporters (rheometer/openfoam.hpp for simpleFoam,
// ldd/openfoam.hpp for interFoam) only write text files.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rheosim/core/case.hpp"

namespace rheosim::core {

// The transport model OpenFOAM gets for a rheology law, in kinematic units.
struct OpenFoamTransport {
  std::string model;                                   // transportModel, e.g. "powerLaw"
  std::vector<std::pair<std::string, double>> coeffs;  // <model>Coeffs entries, SI kinematic
  std::string note;                                    // how it differs from rheosim's law ("" if exact)
};

// Maps the fluid to OpenFOAM v1912's incompressible viscosity models (ρ = fluid.density):
//   newtonian         Newtonian      nu = μ/ρ                                         exact
//   power_law         powerLaw       k/ρ, n; nuMax/nuMin from rheosim's plateau        exact
//   carreau_yasuda    BirdCarreau    nu0, nuInf = μ0/ρ, μ∞/ρ; k = λ; n; a              exact
//   cross             CrossPowerLaw  nu0, nuInf = μ0/ρ, μ∞/ρ; m = λ; n = exponent      exact
//   herschel_bulkley  HerschelBulkley k/ρ, n, tau0 = τ₀/ρ, nu0 = μ(0)/ρ               approximate
//   bingham           HerschelBulkley with n = 1, k = μ∞/ρ, tau0 = τ₀/ρ, nu0 = μ(0)/ρ    approximate
//   casson            Casson         m = μ∞/ρ, tau0 = τ₀/ρ, nuMin = μ∞/ρ, nuMax = μ(0)/ρ approximate
// OpenFOAM's HerschelBulkley is ν = min(ν₀, (τ₀ + kγ̇ⁿ)/γ̇) — the ideal law with a viscosity cap —
// and its Casson is the ideal Casson law clipped to [nuMin, nuMax]; rheosim regularises both
// with Papanastasiou's exponential. With the cap set to rheosim's μ(0) both agree with the ideal
// law far above γ̇ = 1/m and differ only below it (for Bingham the cap's stress exceeds
// Papanastasiou's by at most τ₀/e, at γ̇ = 1/m); the note says so. Any other law has no
// OpenFOAM counterpart and is a ConfigError naming it.
[[nodiscard]] OpenFoamTransport openfoam_transport(const FluidProperties& fluid);

// The law's lines of a transportProperties dictionary, each prefixed by indent: a comment with
// rheosim's law, its parameters and the density, the note (if any), `transportModel X;` and
// `nu v;` or the `XCoeffs { … }` block.
[[nodiscard]] std::string openfoam_viscosity_entries(const OpenFoamTransport& transport, const FluidProperties& fluid,
                                                     std::string_view indent = "");

// The FoamFile header of a dictionary of class cls ("dictionary", "volScalarField", …) written
// at location ("system", "constant", "0") as object, stamped with rheosim's version.
[[nodiscard]] std::string foam_header(std::string_view cls, std::string_view location, std::string_view object);
inline constexpr std::string_view foam_footer =
    "\n// ************************************************************************* //\n";
// constant/turbulenceProperties of a laminar case: the viscous stress is the transport model's.
[[nodiscard]] std::string foam_laminar_turbulence_properties();
// The shortest text that reads back to the same double.
[[nodiscard]] std::string foam_number(double value);

}  // namespace rheosim::core
