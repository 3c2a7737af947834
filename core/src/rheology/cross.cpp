#include "cross.hpp"
#include "parameter_check.hpp"
#include "plateau_parameters.hpp"

namespace rheosim::core {
namespace {

// The law's own ranges, shared by the YAML reader (located errors) and the constructor
// (invariants); the plateaus' are in plateau_parameters.hpp.
const Range exponent_range = Range::open_closed(0.0, 1.0);

void check(std::string_view key, double value, const Range& range) {
  detail::check_parameter(Cross::name, key, value, range);
}

// Validates before the derived constants are computed from the parameters.
Cross::Params checked(Cross::Params p) {
  detail::check_plateaus(Cross::name, p);
  check("exponent", p.exponent, exponent_range);
  return p;
}

}  // namespace

Cross::Params Cross::Params::from(const Section& section) {
  Params p;
  detail::read_plateaus(section, p);
  p.exponent = section.number({"exponent", "Cross exponent m", "-"}, exponent_range);
  detail::check_plateau_order(section, p);
  return p;
}

Cross::Cross(Params params)
    : params_(checked(params)),
      viscosity_drop_(params_.zero_shear_viscosity - params_.infinite_shear_viscosity),
      min_shear_rate_(min_reduced_shear_rate / params_.time_constant) {}

std::vector<Parameter> Cross::parameters() const {
  return {{"zero_shear_viscosity", params_.zero_shear_viscosity, "Pa·s"},
          {"infinite_shear_viscosity", params_.infinite_shear_viscosity, "Pa·s"},
          {"time_constant", params_.time_constant, "s"},
          {"exponent", params_.exponent, "-"}};
}

}  // namespace rheosim::core
