#include "newtonian.hpp"
#include "parameter_check.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace rheosim::core {
namespace {

// Valid ranges, shared by the YAML reader (located errors) and the constructor (invariants).
const Range viscosity_range = Range::positive();

void check(std::string_view key, double value, const Range& range) {
  detail::check_parameter(Newtonian::name, key, value, range);
}

}  // namespace

Newtonian::Params Newtonian::Params::from(const Section& section) {
  Params p;
  p.viscosity = section.number({"viscosity", "dynamic viscosity μ", "Pa·s"}, viscosity_range);
  return p;
}

Newtonian::Newtonian(Params params) : params_(params) { check("viscosity", params_.viscosity, viscosity_range); }

std::vector<Parameter> Newtonian::parameters() const { return {{"viscosity", params_.viscosity, "Pa·s"}}; }

}  // namespace rheosim::core
