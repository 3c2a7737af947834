#include "cross.hpp"
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
const Range exponent_range = Range::open_closed(0.0, 1.0);

void check(std::string_view key, double value, const Range& range) {
  detail::check_parameter(Cross::name, key, value, range);
}

// Validates before the derived constants are computed from the parameters.
Cross::Params checked(Cross::Params p) {
  check("zero_shear_viscosity", p.zero_shear_viscosity, zero_shear_viscosity_range);
  check("infinite_shear_viscosity", p.infinite_shear_viscosity, infinite_shear_viscosity_range);
  check("time_constant", p.time_constant, time_constant_range);
  check("exponent", p.exponent, exponent_range);
  if (!(p.infinite_shear_viscosity < p.zero_shear_viscosity))
    throw std::invalid_argument(fmt::format("{}: infinite_shear_viscosity = {} must be below zero_shear_viscosity = {}",
                                            Cross::name, p.infinite_shear_viscosity, p.zero_shear_viscosity));
  return p;
}

}  // namespace

Cross::Params Cross::Params::from(const Section& section) {
  Params p;
  p.zero_shear_viscosity =
      section.number({"zero_shear_viscosity", "zero-shear viscosity μ0", "Pa·s"}, zero_shear_viscosity_range);
  p.infinite_shear_viscosity = section.number(
      {"infinite_shear_viscosity", "infinite-shear viscosity μ∞ < μ0", "Pa·s"}, infinite_shear_viscosity_range);
  p.time_constant = section.number({"time_constant", "time constant λ", "s"}, time_constant_range);
  p.exponent = section.number({"exponent", "Cross exponent m", "-"}, exponent_range);
  if (!(p.infinite_shear_viscosity < p.zero_shear_viscosity))
    section.fail("infinite_shear_viscosity",
                 fmt::format("{} is not below zero_shear_viscosity = {}", p.infinite_shear_viscosity,
                             p.zero_shear_viscosity),
                 fmt::format("infinite-shear viscosity μ∞ in [0, {}), Pa·s", p.zero_shear_viscosity),
                 "μ∞ is the high-shear plateau and must lie below the zero-shear plateau μ0");
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
