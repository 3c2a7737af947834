#include "carreau_yasuda.hpp"
#include "parameter_check.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace rheosim::core {
namespace {

// Valid ranges, shared by the YAML reader (located errors) and the constructor (invariants).
// infinite_shear_viscosity must also be below zero_shear_viscosity.
const Range zero_shear_viscosity_range = Range::positive();
const Range infinite_shear_viscosity_range = Range::non_negative();
const Range time_constant_range = Range::positive();
const Range a_range = Range::open_closed(0.0, 10.0);
const Range n_range = Range::open_closed(0.0, 2.0);

void check(std::string_view key, double value, const Range& range) {
  detail::check_parameter(CarreauYasuda::name, key, value, range);
}

// Validates before the derived constants are computed from the parameters.
CarreauYasuda::Params checked(CarreauYasuda::Params p) {
  check("zero_shear_viscosity", p.zero_shear_viscosity, zero_shear_viscosity_range);
  check("infinite_shear_viscosity", p.infinite_shear_viscosity, infinite_shear_viscosity_range);
  check("time_constant", p.time_constant, time_constant_range);
  check("a", p.a, a_range);
  check("n", p.n, n_range);
  if (!(p.infinite_shear_viscosity < p.zero_shear_viscosity))
    throw std::invalid_argument(fmt::format("{}: infinite_shear_viscosity = {} must be below zero_shear_viscosity = {}",
                                            CarreauYasuda::name, p.infinite_shear_viscosity, p.zero_shear_viscosity));
  return p;
}

}  // namespace

CarreauYasuda::Params CarreauYasuda::Params::from(const Section& section) {
  Params p;
  p.zero_shear_viscosity =
      section.number({"zero_shear_viscosity", "zero-shear viscosity μ0", "Pa·s"}, zero_shear_viscosity_range);
  p.infinite_shear_viscosity = section.number(
      {"infinite_shear_viscosity", "infinite-shear viscosity μ∞ < μ0", "Pa·s"}, infinite_shear_viscosity_range);
  p.time_constant = section.number({"time_constant", "time constant λ", "s"}, time_constant_range);
  p.a = section.number({"a", "Yasuda transition exponent a", "-"}, a_range);
  p.n = section.number({"n", "power-law index n", "-"}, n_range);
  if (!(p.infinite_shear_viscosity < p.zero_shear_viscosity))
    section.fail("infinite_shear_viscosity",
                 fmt::format("{} is not below zero_shear_viscosity = {}", p.infinite_shear_viscosity,
                             p.zero_shear_viscosity),
                 fmt::format("infinite-shear viscosity μ∞ in [0, {}), Pa·s", p.zero_shear_viscosity),
                 "μ∞ is the high-shear plateau and must lie below the zero-shear plateau μ0");
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
