#include "carreau_yasuda.hpp"
#include "parameter_check.hpp"
#include "plateau_parameters.hpp"

namespace rheosim::core {
namespace {

// The law's own ranges, shared by the YAML reader (located errors) and the constructor
// (invariants); the plateaus' are in plateau_parameters.hpp.
const Range a_range = Range::open_closed(0.0, 10.0);
const Range n_range = Range::open_closed(0.0, 2.0);

void check(std::string_view key, double value, const Range& range) {
  detail::check_parameter(CarreauYasuda::name, key, value, range);
}

// Validates before the derived constants are computed from the parameters.
CarreauYasuda::Params checked(CarreauYasuda::Params p) {
  detail::check_plateaus(CarreauYasuda::name, p);
  check("a", p.a, a_range);
  check("n", p.n, n_range);
  return p;
}

}  // namespace

CarreauYasuda::Params CarreauYasuda::Params::from(const Section& section) {
  Params p;
  detail::read_plateaus(section, p);
  p.a = section.number({"a", "Yasuda transition exponent a", "-"}, a_range);
  p.n = section.number({"n", "power-law index n", "-"}, n_range);
  detail::check_plateau_order(section, p);
  return p;
}

CarreauYasuda::CarreauYasuda(Params params)
    : params_(checked(params)),
      viscosity_drop_(params_.zero_shear_viscosity - params_.infinite_shear_viscosity),
      exponent_((params_.n - 1.0) / params_.a),
      min_shear_rate_(min_reduced_shear_rate / params_.time_constant) {}

std::vector<Parameter> CarreauYasuda::parameters() const {
  return {{"zero_shear_viscosity", params_.zero_shear_viscosity, "Pa·s"},
          {"infinite_shear_viscosity", params_.infinite_shear_viscosity, "Pa·s"},
          {"time_constant", params_.time_constant, "s"},
          {"a", params_.a, "-"},
          {"n", params_.n, "-"}};
}

}  // namespace rheosim::core
