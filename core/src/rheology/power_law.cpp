#include "power_law.hpp"
#include "parameter_check.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace rheosim::core {
namespace {

// Valid ranges, shared by the YAML reader (located errors) and the constructor (invariants).
const Range consistency_range = Range::positive();
const Range index_range = Range::open_closed(0.0, 2.0);
const Range min_shear_rate_range = Range::positive();

void check(std::string_view key, double value, const Range& range) {
  detail::check_parameter(PowerLaw::name, key, value, range);
}

}  // namespace

PowerLaw::Params PowerLaw::Params::from(const Section& section) {
  const Params defaults;
  Params p;
  p.consistency = section.number({"consistency", "flow-consistency index k", "Pa·s^n"}, consistency_range);
  p.index = section.number({"index", "flow-behaviour index n", "-"}, index_range);
  p.min_shear_rate = section.number_or({"min_shear_rate", "shear rate below which μ is held constant", "1/s"},
                                       defaults.min_shear_rate, min_shear_rate_range);
  return p;
}

PowerLaw::PowerLaw(Params params) : params_(params) {
  check("consistency", params_.consistency, consistency_range);
  check("index", params_.index, index_range);
  check("min_shear_rate", params_.min_shear_rate, min_shear_rate_range);
}

std::vector<Parameter> PowerLaw::parameters() const {
  return {{"consistency", params_.consistency, "Pa·s^n"},
          {"index", params_.index, "-"},
          {"min_shear_rate", params_.min_shear_rate, "1/s"}};
}

}  // namespace rheosim::core
