#include "bingham.hpp"
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
  detail::check_parameter(Bingham::name, key, value, range);
}

}  // namespace

Bingham::Params Bingham::Params::from(const Section& section) {
  const Params defaults;
  Params p;
  p.plastic_viscosity = section.number({"plastic_viscosity", "plastic viscosity μ∞", "Pa·s"}, plastic_viscosity_range);
  p.yield_stress = section.number({"yield_stress", "yield stress τ0", "Pa"}, yield_stress_range);
  p.regularization = section.number_or({"regularization", "Papanastasiou regularisation parameter m", "s"},
                                       defaults.regularization, regularization_range);
  return p;
}

Bingham::Bingham(Params params) : params_(params) {
  check("plastic_viscosity", params_.plastic_viscosity, plastic_viscosity_range);
  check("yield_stress", params_.yield_stress, yield_stress_range);
  check("regularization", params_.regularization, regularization_range);
}

std::vector<Parameter> Bingham::parameters() const {
  return {{"plastic_viscosity", params_.plastic_viscosity, "Pa·s"},
          {"yield_stress", params_.yield_stress, "Pa"},
          {"regularization", params_.regularization, "s"}};
}

}  // namespace rheosim::core
