#include "di_felice.hpp"

#include <cmath>

#include "rheosim/core/units.hpp"

namespace rheosim::coupling {
namespace {

// χ of CD eq. 33. At Re_p = 0, log10 would be −∞; the Gaussian term vanishes there, so χ = 3.7.
double voidage_exponent(double reynolds) {
  if (!(reynolds > 0.0)) return 3.7;
  const double distance = 1.5 - std::log10(reynolds);
  return 3.7 - 0.65 * std::exp(-0.5 * distance * distance);
}

}  // namespace

DiFelice::Params DiFelice::Params::from(const core::Section& /*section*/) { return {}; }

DiFelice::DiFelice(Params /*params*/) {}

double DiFelice::beta(const DragInput& particle) const {
  const double reynolds = particle_reynolds_number(particle);
  const double chi = voidage_exponent(reynolds);
  const double cd_times_re_root = 4.8 + 0.63 * std::sqrt(reynolds);  // √(C_d Re_p)
  return core::units::pi / 8.0 * particle.fluid_viscosity * particle.diameter *
         std::pow(particle.void_fraction, 1.0 - chi) * cd_times_re_root * cd_times_re_root;
}

}  // namespace rheosim::coupling
