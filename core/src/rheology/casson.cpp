#include "casson.hpp"
#include "parameter_check.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace rheosim::core {
namespace {

// Valid ranges, shared by the YAML reader (located errors) and the constructor (invariants).
const Range plastic_viscosity_range = Range::positive();
const Range yield_stress_range = Range::non_negative();
const Range regularization_range = Range::positive();

void check(std::string_view key, double value, const Range& range) {
  detail::check_parameter(Casson::name, key, value, range);
}

// Validates before the derived constants are computed from the parameters.
Casson::Params checked(Casson::Params p) {
  check("plastic_viscosity", p.plastic_viscosity, plastic_viscosity_range);
  check("yield_stress", p.yield_stress, yield_stress_range);
  check("regularization", p.regularization, regularization_range);
  return p;
}

}  // namespace

Casson::Params Casson::Params::from(const Section& section) {
  const Params defaults;
  Params p;
  p.plastic_viscosity =
      section.number({"plastic_viscosity", "Casson plastic viscosity μ∞", "Pa·s"}, plastic_viscosity_range);
  p.yield_stress = section.number({"yield_stress", "yield stress τ0", "Pa"}, yield_stress_range);
  p.regularization = section.number_or({"regularization", "Papanastasiou regularisation parameter m", "s"},
                                       defaults.regularization, regularization_range);
  return p;
}

Casson::Casson(Params params)
    : params_(checked(params)),
      sqrt_mu_inf_(std::sqrt(params_.plastic_viscosity)),
      sqrt_tau0_m_(std::sqrt(params_.yield_stress * params_.regularization)),
      min_shear_rate_(min_regularized_root * min_regularized_root / params_.regularization) {}

std::vector<Parameter> Casson::parameters() const {
  return {{"plastic_viscosity", params_.plastic_viscosity, "Pa·s"},
          {"yield_stress", params_.yield_stress, "Pa"},
          {"regularization", params_.regularization, "s"}};
}

}  // namespace rheosim::core
