#include "schiller_naumann.hpp"

#include <cmath>

#include "rheosim/core/units.hpp"

namespace rheosim::coupling {

SchillerNaumann::Params SchillerNaumann::Params::from(const core::Section& /*section*/) { return {}; }

SchillerNaumann::SchillerNaumann(Params /*params*/) {}

double SchillerNaumann::beta(const DragInput& particle) const {
  const double stokes = 3.0 * core::units::pi * particle.fluid_viscosity * particle.diameter;
  // Re without ε: the isolated sphere sees the interstitial slip.
  const double reynolds = particle.fluid_density * particle.diameter * slip_speed(particle) / particle.fluid_viscosity;
  if (reynolds <= 1000.0) return stokes * (1.0 + 0.15 * std::pow(reynolds, 0.687));
  return stokes * 0.44 * reynolds / 24.0;  // C_d = 0.44: β = (π/8) C_d ρ d² |w|
}

}  // namespace rheosim::coupling
