#include "rheosim/core/openfoam.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "rheosim/core/error.hpp"
#include "rheosim/core/version.hpp"

namespace rheosim::core {

namespace {

// A parameter of a law by its YAML name (Rheology::parameters()).
double parameter(const core::Rheology& law, std::string_view name) {
  for (const auto& p : law.parameters())
    if (p.name == name) return p.value;
  throw std::logic_error(fmt::format("rheology '{}' has no parameter '{}'", law.name(), name));
}

}  // namespace

std::string foam_number(double value) { return fmt::format("{}", value); }

std::string foam_header(std::string_view cls, std::string_view location, std::string_view object) {
  return fmt::format(
      "/*--------------------------------*- C++ -*----------------------------------*\\\n"
      "  Written by rheosim {} ({}) for OpenFOAM v1912. SI units.\n"
      "\\*---------------------------------------------------------------------------*/\n"
      "FoamFile\n"
      "{{\n"
      "    version     2.0;\n"
      "    format      ascii;\n"
      "    class       {};\n"
      "    location    \"{}\";\n"
      "    object      {};\n"
      "}}\n"
      "// * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * //\n\n",
      core::version, core::git_revision, cls, location, object);
}

std::string foam_laminar_turbulence_properties() {
  return foam_header("dictionary", "constant", "turbulenceProperties") +
         "// Laminar: the viscous stress comes from transportProperties (generalised Newtonian).\n"
         "simulationType  laminar;\n" +
         std::string(foam_footer);
}

OpenFoamTransport openfoam_transport(const FluidProperties& fluid) {
  if (!fluid.rheology) throw std::invalid_argument("openfoam_transport: fluid without rheology");
  const Rheology& law = *fluid.rheology;
  const double rho = fluid.density;
  if (!(rho > 0)) throw_config_error("", "fluid.density", fmt::format("{} is not positive", rho), "density in kg/m³");
  const std::string name(law.name());
  const auto p = [&](std::string_view key) { return parameter(law, key); };
  const double nu_rest = law.viscosity(0.0) / rho;  // rheosim's μ(0)/ρ: finite for every law

  OpenFoamTransport t;
  if (name == "newtonian") {
    t.model = "Newtonian";
    t.coeffs = {{"nu", p("viscosity") / rho}};
  } else if (name == "power_law") {
    // rheosim holds μ = k γ̇_min^(n−1) below γ̇_min; OpenFOAM clips ν to [nuMin, nuMax], which
    // is the same law when the plateau value is the cap on the side the law runs away to.
    const double n = p("index");
    constexpr double no_cap = 1e300;
    t.model = "powerLaw";
    t.coeffs = {
        {"k", p("consistency") / rho}, {"n", n}, {"nuMin", n < 1 ? 0.0 : nu_rest}, {"nuMax", n > 1 ? no_cap : nu_rest}};
  } else if (name == "carreau_yasuda") {
    t.model = "BirdCarreau";
    t.coeffs = {{"nu0", p("zero_shear_viscosity") / rho},
                {"nuInf", p("infinite_shear_viscosity") / rho},
                {"k", p("time_constant")},
                {"n", p("n")},
                {"a", p("a")}};
  } else if (name == "cross") {
    t.model = "CrossPowerLaw";
    t.coeffs = {{"nu0", p("zero_shear_viscosity") / rho},
                {"nuInf", p("infinite_shear_viscosity") / rho},
                {"m", p("time_constant")},
                {"n", p("exponent")}};
  } else if (name == "herschel_bulkley" || name == "bingham") {
    const bool bingham = name == "bingham";
    t.model = "HerschelBulkley";
    t.coeffs = {{"k", (bingham ? p("plastic_viscosity") : p("consistency")) / rho},
                {"n", bingham ? 1.0 : p("index")},
                {"tau0", p("yield_stress") / rho},
                {"nu0", nu_rest}};
    t.note = fmt::format(
        "OpenFOAM's HerschelBulkley is nu = min(nu0, (tau0 + k*gammaDot^n)/gammaDot): the ideal {} law "
        "with a viscosity cap nu0 = mu(0)/rho = {} m^2/s (rheosim's regularised viscosity at rest), not "
        "Papanastasiou's smooth 1 - exp(-m*gammaDot) (m = {} s). Both tend to the ideal law for "
        "gammaDot >> 1/m and differ below it (by up to tau0/e in stress for Bingham, at gammaDot = 1/m).",
        bingham ? "Bingham" : "Herschel-Bulkley", foam_number(nu_rest), foam_number(p("regularization")));
  } else if (name == "casson") {
    t.model = "Casson";
    t.coeffs = {{"m", p("plastic_viscosity") / rho},
                {"tau0", p("yield_stress") / rho},
                {"nuMin", p("plastic_viscosity") / rho},
                {"nuMax", nu_rest}};
    t.note = fmt::format(
        "OpenFOAM's Casson is the ideal law nu = (sqrt(tau0/gammaDot) + sqrt(m))^2 clipped to [nuMin, nuMax] "
        "with nuMax = mu(0)/rho = {} m^2/s (rheosim's regularised viscosity at rest), not rheosim's "
        "Papanastasiou-Casson law with exp(-sqrt(m*gammaDot)) (m = {} s). Both tend to the ideal law for "
        "gammaDot >> 1/m and differ below it.",
        foam_number(nu_rest), foam_number(p("regularization")));
  } else {
    throw_config_error("", "fluid.rheology.model", fmt::format("'{}' has no OpenFOAM v1912 viscosity model", name),
                       "newtonian, power_law, bingham, casson, herschel_bulkley, carreau_yasuda or cross",
                       "OpenFOAM v1912's incompressible transport models are Newtonian, powerLaw, CrossPowerLaw, "
                       "BirdCarreau, HerschelBulkley, Casson (and strainRateFunction, Arrhenius)");
  }
  return t;
}

std::string openfoam_viscosity_entries(const OpenFoamTransport& t, const FluidProperties& fluid,
                                       std::string_view indent) {
  std::string out = fmt::format("{}// rheosim law: {} with", indent, fluid.rheology->name());
  for (const auto& prm : fluid.rheology->parameters())
    out += fmt::format(" {} = {} {};", prm.name, foam_number(prm.value), prm.unit);
  out += fmt::format("\n{}// density {} kg/m^3. OpenFOAM's models are kinematic: nu = mu/rho, k/rho, tau0/rho.\n",
                     indent, foam_number(fluid.density));
  if (!t.note.empty()) out += fmt::format("{}// Note: {}\n", indent, t.note);
  out += fmt::format("{}transportModel  {};\n", indent, t.model);
  if (t.model == "Newtonian") {
    out += fmt::format("{}nu              {};\n", indent, foam_number(t.coeffs.at(0).second));
  } else {
    out += fmt::format("{}{}Coeffs\n{}{{\n", indent, t.model, indent);
    for (const auto& [key, value] : t.coeffs) out += fmt::format("{}    {:<8}{};\n", indent, key, foam_number(value));
    out += fmt::format("{}}}\n", indent);
  }
  return out;
}

}  // namespace rheosim::core
